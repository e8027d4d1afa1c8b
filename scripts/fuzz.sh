#!/usr/bin/env bash
# The libFuzzer targets of fuzz/ (clang, ASan + UBSan), in their own build tree build-fuzz/.
#
#   scripts/fuzz.sh --ctest [SECONDS]     build, make the seed corpora, run every target SECONDS (default 30)
#                                         through ctest (label 'fuzz'): what CI runs
#   scripts/fuzz.sh TARGET SECONDS [JOBS] a long run of one target (mesh, scene or image), JOBS processes
#                                         (default 1); the corpus grows in build-fuzz/corpus/TARGET
#
# Findings (crash-*, timeout-*, oom-*, leak-*) land in build-fuzz/findings/; replay one with
# build-fuzz/fuzz/fuzz_TARGET FILE, then keep it as a regression file in tests/data/hostile with a test.
set -euo pipefail
cd "$(dirname "$0")/.."
B=build-fuzz

if ! command -v clang++ > /dev/null; then
  echo "fuzz: clang++ not found: install the Debian packages 'clang libclang-rt-14-dev' (scripts/install-deps.sh)" >&2
  exit 1
fi

mode=${1:-}
case "$mode" in
  --ctest) seconds=${2:-30} ;;
  mesh|scene|image) seconds=${2:?"fuzz: give the seconds to run, e.g. scripts/fuzz.sh mesh 3600"}; jobs=${3:-1} ;;
  *) sed -n '2,12p' "$0" >&2; exit 2 ;;
esac

cmake -S . -B "$B" -DSHADELAB_FUZZ=ON -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=RelWithDebInfo \
      -DSHADELAB_FUZZ_SECONDS="${seconds}" > "$B.log" 2>&1 || { cat "$B.log"; exit 1; }
nice cmake --build "$B" -j"$(nproc)" >> "$B.log" 2>&1 || { tail -40 "$B.log"; echo "fuzz: build failed (see $B.log)" >&2; exit 1; }

# Seed corpora from the bundled files. The mesh and image targets read a format byte first.
rm -rf "$B/seeds"
mkdir -p "$B/seeds/mesh" "$B/seeds/scene" "$B/seeds/image"
for f in tests/data/*.* tests/data/hostile/*.* meshes/*.obj; do
  [ "$(stat -c %s "$f")" -le 65536 ] || continue   # the big meshes only slow every run down
  case "${f,,}" in
    *.obj) b='\000' ;; *.ply) b='\001' ;; *.off) b='\002' ;; *.stl) b='\003' ;; *) continue ;;
  esac
  { printf "$b"; cat "$f"; } > "$B/seeds/mesh/$(basename "$f")"
done
cp scenes/*.json tests/data/*.json "$B/seeds/scene/"
printf '{ "meshes": [ { "path": "m.obj", "material": { "model": "phong", "params": { "shininess": 20 } } } ],\n  "lights": [ { "type": "point", "position": [1, 2, 3], "intensity": 4, "range": 9 } ],\n  "outputs": { "png": "{name}_{mesh}.png", "exr": "{scene}.exr" } }\n' \
  > "$B/seeds/scene/with_mesh.json"
for f in tests/data/hostile/*.fits tests/data/hostile/*.png; do
  case "$f" in *.fits) b='\000' ;; *.png) b='\001' ;; esac
  { printf "$b"; cat "$f"; } > "$B/seeds/image/$(basename "$f")"
done
# Small valid images of each format, written by the one tool that is sure to read them back.
if command -v oiiotool > /dev/null; then
  tmp=$(mktemp -d)
  oiiotool --pattern checker:width=4:height=4 8x6 4 -d uint8 -o "$tmp/c.png" \
           --pattern fill:top=0.1,0.2,0.3:bottom=0.9,0.8,0.7 8x6 3 -d half -o "$tmp/f.exr" > /dev/null 2>&1 || true
  [ -f "$tmp/c.png" ] && { printf '\001'; cat "$tmp/c.png"; } > "$B/seeds/image/checker.png"
  [ -f "$tmp/f.exr" ] && { printf '\002'; cat "$tmp/f.exr"; } > "$B/seeds/image/fill.exr"
  rm -rf "$tmp"
fi
# A valid 4x3 FITS image (BITPIX -32, big-endian floats), written here byte by byte.
{
  printf '\000'
  for card in "SIMPLE  =                    T" "BITPIX  =                  -32" "NAXIS   =                    2" \
              "NAXIS1  =                    4" "NAXIS2  =                    3" "BSCALE  =                  1.0" "END"; do
    printf '%-80s' "$card"
  done
  printf '%*s' $((2880 - 7 * 80)) ''
  for i in $(seq 12); do printf '\077\200\000\000'; done   # 1.0f
} > "$B/seeds/image/grey.fits"

if [ "$mode" = --ctest ]; then
  (cd "$B" && ctest -L fuzz --output-on-failure)
  echo "fuzz: findings, if any, are in $B/findings/"
else
  mkdir -p "$B/corpus/$mode" "$B/findings"
  asan=detect_leaks=1
  [ "$mode" = image ] && asan=$asan:fast_unwind_on_malloc=0   # see sanitizers/lsan.supp
  parallel=()
  [ "$jobs" -gt 1 ] && parallel=(-jobs="$jobs" -workers="$jobs")   # each job logs to build-fuzz/fuzz-N.log
  supp=$PWD/sanitizers/lsan.supp
  cd "$B"
  SHADELAB_MAX_MEMORY=${SHADELAB_MAX_MEMORY:-1G} ASAN_OPTIONS=$asan LSAN_OPTIONS=suppressions=$supp \
    "fuzz/fuzz_$mode" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2560 -print_final_stats=1 \
    "${parallel[@]}" -artifact_prefix="findings/$mode-" "corpus/$mode" "seeds/$mode"
fi
