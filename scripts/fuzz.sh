#!/usr/bin/env bash
# The libFuzzer targets of fuzz/ (clang, ASan + UBSan), in their own build tree build-fuzz/.
#
#   scripts/fuzz.sh --ctest [SECONDS]     build, make the seed corpora, run every target through ctest (label
#                                         'fuzz'): a fixed number of inputs from a fixed -seed, capped at SECONDS
#                                         (default 60) each, from a fresh corpus: what CI runs
#   scripts/fuzz.sh TARGET SECONDS [JOBS] a long run of one target (mesh, scene, image, pvl, csv or raster), JOBS
#                                         processes (default 1); the corpus grows in build-fuzz/corpus/TARGET
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
  --ctest) seconds=${2:-60} ;;
  mesh|scene|image|pvl|csv|raster) seconds=${2:?"fuzz: give the seconds to run, e.g. scripts/fuzz.sh mesh 3600"}; jobs=${3:-1} ;;
  *) sed -n '2,12p' "$0" >&2; exit 2 ;;
esac

cmake -S . -B "$B" -DSHADELAB_FUZZ=ON -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=RelWithDebInfo \
      -DSHADELAB_FUZZ_SECONDS="${seconds}" > "$B.log" 2>&1 || { cat "$B.log"; exit 1; }
targets=(fuzz_mesh fuzz_scene fuzz_image fuzz_pvl fuzz_csv fuzz_raster)
[ "$mode" = --ctest ] || targets=("fuzz_$mode")
nice cmake --build "$B" -j2 --target "${targets[@]}" >> "$B.log" 2>&1 || { tail -40 "$B.log"; echo "fuzz: build failed (see $B.log)" >&2; exit 1; }

# Seed corpora from the bundled files. The mesh and image targets read a format byte first.
rm -rf "$B/seeds"
mkdir -p "$B/seeds/mesh" "$B/seeds/scene" "$B/seeds/image" "$B/seeds/pvl" "$B/seeds/csv" "$B/seeds/raster"
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
for f in tests/data/hostile/*.fits tests/data/hostile/*.png tests/data/hostile/*.exr; do
  case "$f" in *.fits) b='\000' ;; *.png) b='\001' ;; *.exr) b='\002' ;; esac
  { printf "$b"; cat "$f"; } > "$B/seeds/image/$(basename "$f")"
done
# Small valid images of each format, written by the one tool that is sure to read them back.
# (No command line in their metadata: a finding derived from them names no folder of this machine.)
if command -v oiiotool > /dev/null; then
  tmp=$(mktemp -d)
  (cd "$tmp" && oiiotool --nosoftwareattrib --pattern checker:width=4:height=4 8x6 4 -d uint8 -o c.png \
     --pattern fill:top=0.1,0.2,0.3:bottom=0.9,0.8,0.7 8x6 3 -d half -o f.exr \
     --pattern fill:top=0.1,0.2,0.3,1:bottom=0.9,0.8,0.7,0.5 9x7 4 -d float --tile 4 4 --compression piz -o t.exr) \
     > /dev/null 2>&1 || true
  [ -f "$tmp/c.png" ] && { printf '\001'; cat "$tmp/c.png"; } > "$B/seeds/image/checker.png"
  [ -f "$tmp/f.exr" ] && { printf '\002'; cat "$tmp/f.exr"; } > "$B/seeds/image/fill.exr"
  [ -f "$tmp/t.exr" ] && { printf '\002'; cat "$tmp/t.exr"; } > "$B/seeds/image/tiled.exr"
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

# PVL: the bundled parameter files, and one file per ISIS law (the empirical ones with both table forms).
cp tests/data/photometry/*.pvl "$B/seeds/pvl/"
pvl() { printf 'Object = PhotometricModel\n  Group = Algorithm\n%b  End_Group\nEnd_Object\nEnd\n' "$2" > "$B/seeds/pvl/$1.pvl"; }
pvl lambert '    Name = Lambert\n'
pvl lommel '    Name = LommelSeeliger\n'
pvl lunar_lambert '    Name = LunarLambert\n    L = 0.7 <unitless>\n'
pvl mcewen '    PHTNAME = LunarLambertMcEwen\n'
pvl minnaert '    Name = Minnaert\n    /* a comment */\n    K = 0.6\n'
pvl hapke_leg '    Name = HapkeLeg\n    Wh = 0.52\n    B0 = 1.0\n    Hh = 1.0\n    Bh = 0.1\n    Ch = -0.2\n    Theta = 30 <deg>\n    ZeroB0Standard = FALSE\n'
pvl minnaert_empirical '    Name = MinnaertEmpirical\n    PhaseList = "0.,10.,20.,30.,40.,50.,6-\n                 0.,70."\n    KList = "0.505,0.584,0.650,0.700,0.744,0.787,0.828,0.865"\n    PhaseCurveList = "0.03335,0.03366,0.03328,0.03220,0.03074,0.02909,0.02737,0.02559"\n'
pvl lunar_lambert_empirical '    Name = LunarLambertEmpirical\n    PhaseList = (0, 30, 60,\n                 90, 120)\n    LList = {1, 0.7, 0.5, 0.3, 0.1}\n    PhaseCurveList = (1, 0.8, 0.6, 0.4, 0.2)\n'
# CSV: geometry tables in the forms the reader accepts.
printf 'phase,incidence,emission\n0,0,0\n60,45,30\n180,90,90\n' > "$B/seeds/csv/plain.csv"
printf '\357\273\277id,"Emission",value,Phase,INCIDENCE\r\na,30,9,60,45\r\n\r\nb,0.5,,1e1,2.5e1\r\n' > "$B/seeds/csv/bom_crlf_value.csv"
printf 'incidence,phase,emission,note\n  10 , 20 ,30,x\n\n89.9,179.9,0,"y, z"\n' > "$B/seeds/csv/spaces_extra.csv"

# Rasters through GDAL: an ISIS3 cube, a GeoTIFF and a PDS4 label written by GDAL's Python bindings (Debian's
# python3, which has python3-gdal), PDS3 images with attached labels written byte by byte.
py=python3
python3 -c 'import osgeo' 2> /dev/null || { [ -x /usr/bin/python3 ] && py=/usr/bin/python3; }
"$py" fuzz/make_raster_seeds.py "$B/seeds/raster"

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
