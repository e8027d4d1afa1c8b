#!/usr/bin/env bash
# The empirical family (minnaert_empirical, lunar_lambert_empirical) wherever the catalogue is: render with a table
# on the command line, a batch scene with the tables as JSON arrays, moon render, chart, plan, fit (the target and
# the fitted model), `models`, and the table checks: one line and exit 1 each.
# Usage: empirical.sh SHADELAB_BINARY SOURCE_DIR
set -uo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/expect.sh"   # fails, passes, expect
bin="$1"
src="$2"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
cd "$work"

table=(-p phase_list=0,30,60,90,120 -p k_list=0.55,0.6,0.66,0.72,0.8 -p phase_curve_list=1,0.8,0.6,0.42,0.28)
expect "models lists the tables" 0 "phase_list=0,25,50,75,100,125,150 +\(ISIS PhaseList; 2 to 32 entries" -- \
    "$bin" models minnaert_empirical
expect "models --json has the tables" 0 '"name": ?"k_list"' -- "$bin" models --json
expect "render with a table" 0 "" -- "$bin" -q render "$src/meshes/spot.obj" -m minnaert_empirical "${table[@]}" \
    --size 64x64 -o spot.png
[ -s spot.png ] || { echo "FAIL render: no spot.png"; fails=$((fails + 1)); }
expect "render with ISIS's names" 0 "" -- "$bin" -q render "$src/meshes/spot.obj" -m lunar_lambert_empirical \
    -p PhaseList=0,60,120 -p LList=1,0.7,0.4 -p PhaseCurveList=1,0.6,0.3 --size 48x48 -o spot-ll.png
expect "render at the defaults, fast, per vertex" 0 "" -- "$bin" -q render "$src/meshes/spot.obj" -m minnaert_empirical \
    --precision fast --per-vertex --size 48x48 -o spot-fast.png

# a batch scene: the tables as JSON arrays; the known answer at the centre of a head-on quad (g = 0, mu0 = mu = 1):
# 0.5 (light) * 0.8 (albedo) * B(0) = 0.5 * 0.8 * 1 = 0.4
mkdir scene
cp "$src/tests/data/scene_quad.obj" scene/
cat > scene/quad.json <<'JSON'
{
  "camera": { "position": [0, 0, 3], "target": [0, 0, 0], "up": [0, 1, 0], "fov": 20 },
  "resolution": [48, 32],
  "meshes": [ { "path": "scene_quad.obj", "material": { "model": "minnaert_empirical", "albedo": [0.8, 0.8, 0.8],
      "params": { "phase_list": [0, 30, 60], "k_list": [0.6, 0.7, 0.8], "phase_curve_list": [1, 0.7, 0.5] } } } ],
  "lights": [ { "type": "directional", "direction": [0, 0, 1], "intensity": 0.5 } ],
  "outputs": { "exr": "{name}.exr" }
}
JSON
expect "batch with a table scene" 0 "" -- "$bin" -q batch scene/quad.json -o out
centre="$(oiiotool out/quad.exr --cut 2x2+23+15 --printstats 2>&1 | grep -m1 'Stats Avg' || true)"
if ! grep -Eq "Avg: 0\.(39[89]|40[01])" <<<"$centre"; then echo "FAIL batch centre pixel: $centre"; fails=$((fails + 1)); fi
sed 's/"k_list": \[0.6, 0.7, 0.8\]/"k_list": [0.6, 0.7]/' scene/quad.json > scene/bad.json
expect "scene: tables of different lengths" 1 "table 'k_list' of model 'minnaert_empirical' has 2 entries but 'phase_list' has 3" -- \
    "$bin" batch scene/bad.json -o out-bad

expect "moon render" 0 "" -- "$bin" -q moon render -m lunar_lambert_empirical --phase 40 --size 64x64 -o moon.exr
expect "chart" 0 "" -- "$bin" -q chart --models minnaert_empirical,lambert --modes precise --size 48x48 --fragments 20000 \
    --repeats 1 --rounds 1 --subdiv-models minnaert_empirical --out chart
expect "plan a table scene" 0 "" -- "$bin" -q plan scene/quad.json --tolerance 2
expect "fit lambert to the empirical law" 0 "lambert" -- "$bin" fit --target minnaert_empirical "${table[@]}" --model lambert \
    --samples 2000
expect "fit the empirical law's albedo, tables held" 0 "minnaert_empirical" -- "$bin" fit --target lambert \
    --model minnaert_empirical --samples 2000
expect "fit --all names it" 1 "fit --all: model 'minnaert_empirical' reads tables \(phase_list, ...\), which a fit does not vary" -- \
    "$bin" fit --all --target lambert --models lambert,minnaert_empirical --samples 500 -o all
expect "a table cannot be held fixed" 1 "--param k_list: '0.5,0.6' is a list \(a table\), and this option takes one number" -- \
    "$bin" fit --target lambert --model minnaert_empirical --fix k_list=0.5,0.6 --samples 500

expect "phases not increasing" 1 "table 'phase_list' of model 'minnaert_empirical' is not increasing: entry 3 = 20 follows 30" -- \
    "$bin" render "$src/meshes/spot.obj" -m minnaert_empirical -p phase_list=0,30,20 -p k_list=0.6,0.7,0.8 \
    -p phase_curve_list=1,0.8,0.6 --size 32x32 -o x.png
expect "a non-number in a list" 1 "--param k_list \(entry 2\): 'x' is not a finite number" -- \
    "$bin" render "$src/meshes/spot.obj" -m minnaert_empirical -p k_list=0.6,x,0.8 --size 32x32 -o x.png
expect "an unknown table" 1 "model 'minnaert_empirical' has no table parameter 'l_list'" -- \
    "$bin" render "$src/meshes/spot.obj" -m minnaert_empirical -p l_list=0.6,0.7 --size 32x32 -o x.png
expect "photometry eval agrees" 0 "value: " -- "$bin" photometry eval --model minnaert_empirical "${table[@]}" \
    --phase 40 --incidence 30 --emission 20 --reference

echo "empirical CLI: $passes passed, $fails failed"
[ "$fails" -eq 0 ]
