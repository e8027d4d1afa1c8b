#!/usr/bin/env bash
# Results on stdout, logs on stderr, in every command: each command's files (and its textual result) are on
# stdout, every file named there exists, the logs are on stderr, and the global -q leaves stderr empty on success.
# Usage: streams.sh SHADELAB_BINARY SOURCE_DIR
set -uo pipefail
bin="$(cd "$(dirname "$1")" && pwd)/$(basename "$1")"; src="$(cd "$2" && pwd)"
work="$(mktemp -d)"; trap 'rm -rf "$work"' EXIT; cd "$work"
fails=0; passes=0
fail() { echo "FAIL $1"; fails=$((fails + 1)); }

# streams NAME 'STDOUT_REGEX' -- command...: run it twice, plain and with -q after the binary.
streams() {
    local name="$1" want="$2"; shift 3
    local rc
    "$bin" "$@" > out.txt 2> err.txt; rc=$?
    if [ "$rc" -ne 0 ]; then fail "$name: exit $rc: $(tail -2 err.txt)"; return; fi
    grep -Eq -- "$want" out.txt || { fail "$name: stdout does not match /$want/: $(head -3 out.txt)"; return; }
    # Every line of stdout that names a file with an extension this command writes must exist.
    while IFS= read -r line; do
        case "$line" in *.png|*.exr|*.fits|*.tif|*.csv|*.json|*.pvl)
            [ -e "$line" ] || { fail "$name: stdout names '$line', which does not exist"; return; } ;;
        esac
    done < out.txt
    "$bin" -q "$@" > out_q.txt 2> err_q.txt; rc=$?
    if [ "$rc" -ne 0 ]; then fail "$name -q: exit $rc"; return; fi
    [ -s err_q.txt ] && { fail "$name: with -q stderr is not empty: $(head -2 err_q.txt)"; return; }
    grep -Eq -- "$want" out_q.txt || { fail "$name -q: stdout lost its result: $(head -3 out_q.txt)"; return; }
    passes=$((passes + 1))
}

mesh="$src/meshes/spot.obj"
streams render '^a\.png$' -- render "$mesh" --size 64x64 -o a.png
streams "render --tolerance" '^p\.png$' -- render "$mesh" --size 64x64 --tolerance 1 --no-catalogue -o p.png
streams batch '^b/lights\.png$' -- batch "$src/scenes/lights.json" --out b --force
streams "batch report" '^b/batch_report\.json$' -- batch "$src/scenes/lights.json" --out b
streams compare '^pixels compared' -- compare a.png a.png
streams models '^lambert ' -- models
streams "models --json" '"name"' -- models --json
streams "moon render" '^d\.fits$' -- moon render --size 96x96 --phase 30 -o d.fits
streams "moon curve" '^c\.csv$' -- moon curve --phase 30 -o c.csv
streams "moon geometry" '^g\.png$' -- moon geometry --phase 60 --pa 30 -o g.png
streams "moon fit" 'k += ' -- moon fit d.fits --no-plot -o f.csv
streams "moon compare" '^disc ' -- moon compare d.fits --k 0.7 --no-plot -o cmp.csv
streams view '^v/polar\.png$' -- view lambert -o v
streams "photometry eval" '^value: ' -- photometry eval --model lommel_seeliger --phase 30 --incidence 20 --emission 10
streams fit '^  albedo ' -- fit --target oren_nayar -p sigma=0.3 --model lambert --samples 4096
streams plan "^scene " -- plan "$src/scenes/lights.json" --no-catalogue
streams "report merge" '^m\.json$' -- report merge b/batch_report.json -o m.json
echo "streams: $passes passed, $fails failed"
[ "$fails" -eq 0 ]
