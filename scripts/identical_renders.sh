#!/usr/bin/env bash
# Proves that this checkout renders exactly what BASE_REV renders: builds BASE_REV (a git worktree in a temporary
# folder, Release build of the shadelab target only) and this checkout (build/, the shadelab target), renders the
# same set of images with both and compares every image pixel for pixel with OpenImageIO's idiff (-fail 0 -warn 0).
# The set: the bundled scenes (scenes/*.json) and the bundled meshes through the studio template in one batch, as
# scripts/main.sh runs them; the contact sheet; a `render` of each bundled mesh (per pixel, per vertex, fast
# precision, a planned --tolerance render); `moon render` discs (Minnaert and Hapke).
# Prints one line per image ("same" or "DIFFERENT" and why) and exits 1 on any difference, 2 on a usage error.
# The planned render is compared only when both builds' planners chose the same configuration: the choice
# depends on measured timings, so on a loaded machine it can differ between two runs of one build ("timing").
#
#   scripts/identical_renders.sh main           # against the main branch
#   scripts/identical_renders.sh HEAD~3         # against any revision git knows
# KEEP=1 keeps the temporary folder (both sets of images) and prints where it is. BASE_CACHE=DIR keeps the base
# checkout and its build in DIR (DIR/src, DIR/build) so that the next run against the same or a nearby revision
# rebuilds only what changed.
set -euo pipefail
[ $# -eq 1 ] || { echo "usage: scripts/identical_renders.sh BASE_REV (a git revision: main, HEAD~1, a hash)" >&2; exit 2; }
cd "$(dirname "$0")/.."
src="$(pwd)"
base_rev="$1"
git rev-parse --verify --quiet "$base_rev^{commit}" > /dev/null \
    || { echo "identical_renders: '$base_rev' is not a revision of this repository" >&2; exit 2; }
command -v idiff > /dev/null || { echo "identical_renders: idiff not found (Debian package openimageio-tools; scripts/install-deps.sh)" >&2; exit 1; }

tmp="$(mktemp -d)"
if [ -n "${BASE_CACHE:-}" ]; then mkdir -p "$BASE_CACHE"; base_src="$(cd "$BASE_CACHE" && pwd)/src"; base_build="$(cd "$BASE_CACHE" && pwd)/build"
else base_src="$tmp/base"; base_build="$tmp/base-build"; fi
cleanup() {
    [ -n "${BASE_CACHE:-}" ] || git -C "$src" worktree remove --force "$base_src" > /dev/null 2>&1 || true
    if [ "${KEEP:-0}" = 1 ]; then echo "kept: $tmp" >&2; else rm -rf "$tmp"; fi
}
trap cleanup EXIT

build() {   # build SOURCE_DIR BUILD_DIR LABEL
    cmake -S "$1" -B "$2" -DCMAKE_BUILD_TYPE=Release > "$tmp/$3-configure.log" 2>&1 \
        || { tail -20 "$tmp/$3-configure.log"; echo "identical_renders: configuring $3 failed" >&2; exit 1; }
    cmake --build "$2" -j"$(nproc)" --target shadelab > "$tmp/$3-build.log" 2>&1 \
        || { tail -30 "$tmp/$3-build.log"; echo "identical_renders: building $3 failed" >&2; exit 1; }
}

echo "building $base_rev ($(git rev-parse --short "$base_rev")) and this checkout ..." >&2
if [ -d "$base_src/.git" ] || [ -f "$base_src/.git" ]; then
    git -C "$base_src" checkout --quiet --detach "$(git rev-parse "$base_rev")" \
        || { echo "identical_renders: cannot check out '$base_rev' in $base_src" >&2; exit 1; }
else
    git worktree add --detach "$base_src" "$base_rev" > /dev/null 2>&1 \
        || { echo "identical_renders: cannot check out '$base_rev' into a temporary worktree" >&2; exit 1; }
fi
build "$base_src" "$base_build" base
build "$src" "$src/build" this

# render_all SHADELAB OUT: every image of the set into OUT, run from the source folder (relative scene paths).
render_all() {
    local bin="$1" out="$2"
    mkdir -p "$out"
    "$bin" -q batch scenes/*.json --meshes meshes --scene scenes/templates/studio.json --out "$out/batch" --force > /dev/null
    "$bin" -q contact -o "$out/contact_sheet.exr" > /dev/null
    local m stem
    for m in meshes/*.obj; do
        stem="$(basename "$m" .obj)"
        "$bin" -q render "$m" --model oren_nayar -p sigma=0.4 --albedo 0.9,0.6,0.3 --light dir:1,1,0.5:1,1,1:1.0 \
            --light point:0,4,3:1,0.8,0.6:20 --size 320x240 -o "$out/render_$stem.exr" > /dev/null
    done
    "$bin" -q render meshes/spot.obj --model phong -p n=40 --per-vertex --size 256x256 -o "$out/render_spot_per_vertex.exr" > /dev/null
    "$bin" -q render meshes/teapot.obj --model cook_torrance --precision fast --size 256x256 -o "$out/render_teapot_fast.exr" > /dev/null
    # the planner's choice depends on measured timings (docs/planner.md): its report is kept beside the image
    "$bin" render meshes/spot.obj --model minnaert_1941 --tolerance 0.5 --size 128x128 -o "$out/render_spot_planned.exr" \
        > "$out/render_spot_planned.plan" 2>&1
    "$bin" -q moon render --model minnaert --k 0.7 --phase 30 --size 256x256 -o "$out/moon_minnaert.exr" > /dev/null
    "$bin" -q moon render -m hapke_hen -p wh=0.52 -p b0=1 -p hh=1 -p theta=30 -p hg1=0.213 -p hg2=1 --phase 40 \
        --size 256x256 -o "$out/moon_hapke.exr" > /dev/null
    "$bin" -q moon render -m minnaert_1941 -p k=0.7 --phase 60 --mesh 3 --size 200x200 -o "$out/moon_minnaert_icosphere.exr" > /dev/null
    "$bin" -q moon render -m oren_nayar -p sigma=0.3 --phase 20 --mesh 2 --size 200x200 -o "$out/moon_on_icosphere.exr" > /dev/null
}

echo "rendering with $base_rev ..." >&2
render_all "$base_build/shadelab" "$tmp/base-images"
echo "rendering with this checkout ..." >&2
render_all "$src/build/shadelab" "$tmp/this-images"

status=0
count=0
timing=0
while IFS= read -r rel; do
    count=$((count + 1))
    if [ ! -f "$tmp/this-images/$rel" ]; then
        echo "DIFFERENT $rel: written by $base_rev, missing from this checkout"; status=1; continue
    fi
    plan_base="$tmp/base-images/${rel%.*}.plan" plan_this="$tmp/this-images/${rel%.*}.plan"
    if [ -f "$plan_base" ] && [ -f "$plan_this" ]; then
        # A planned render: when the two builds' planners chose different configurations (by timing, which a
        # shared machine jitters past the planner's 5% margin), the images are of different configurations.
        chose_base="$(sed -n 's/^chosen: \(.*\) (max.*/\1/p' "$plan_base")"
        chose_this="$(sed -n 's/^chosen: \(.*\) (max.*/\1/p' "$plan_this")"
        if [ -n "$chose_base" ] && [ "$chose_base" != "$chose_this" ]; then
            echo "timing    $rel: the plan chose '$chose_base' with $base_rev and '$chose_this' here (measured timings decide, docs/planner.md): not compared"
            timing=$((timing + 1))
            continue
        fi
    fi
    if idiff -fail 0 -warn 0 "$tmp/base-images/$rel" "$tmp/this-images/$rel" > "$tmp/idiff.log" 2>&1; then
        echo "same      $rel"
    else
        echo "DIFFERENT $rel: $(grep -m1 -iE 'max|differ|error' "$tmp/idiff.log" | tr -s ' ')"; status=1
    fi
done < <(cd "$tmp/base-images" && find . -type f \( -name '*.png' -o -name '*.exr' -o -name '*.tif' -o -name '*.fits' \) | sed 's|^\./||' | sort)
while IFS= read -r rel; do
    [ -f "$tmp/base-images/$rel" ] || { echo "DIFFERENT $rel: written by this checkout only"; status=1; }
done < <(cd "$tmp/this-images" && find . -type f \( -name '*.png' -o -name '*.exr' -o -name '*.tif' -o -name '*.fits' \) | sed 's|^\./||' | sort)
[ "$count" -gt 0 ] || { echo "identical_renders: $base_rev wrote no image" >&2; exit 1; }
if [ "$status" = 0 ]; then
    echo "identical: $((count - timing)) images, pixel for pixel, against $base_rev$([ "$timing" = 0 ] || echo " ($timing planned render(s) not compared: the plans chose differently)")"
else echo "identical_renders: images differ from $base_rev (lines above)" >&2; fi
exit "$status"
