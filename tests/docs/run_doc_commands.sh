#!/usr/bin/env bash
# Runs the commands a doc page shows, as they stand, so a doc example that stops working fails the tests.
# Every line of the page's ```sh blocks that starts with `build/` (continuation lines joined) runs in a scratch
# folder that sees the source tree's meshes/, scenes/ and tests/ (data) read-only through links and the build folder
# as build/; outputs land in the scratch folder. A line saying "(not run by the tests: REASON)" is skipped and
# counted. Usage: run_doc_commands.sh PAGE.md BUILD_DIR SOURCE_DIR
set -uo pipefail
page="$1"; build="$(cd "$2" && pwd)"; src="$(cd "$3" && pwd)"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
ln -s "$build" "$tmp/build"
for d in meshes scenes tests; do ln -s "$src/$d" "$tmp/$d"; done
awk '/^```sh$/{on=1; next} /^```$/{on=0} on' "$page" |
    awk '{ if (sub(/\\$/, "")) { buf = buf $0; next } print buf $0; buf = "" }' > "$tmp/lines.txt"
passed=0; failed=0; skipped=0
cd "$tmp"
while IFS= read -r line; do
    case "$line" in build/*) ;; *) continue ;; esac
    if grep -q "(not run by the tests" <<<"$line"; then skipped=$((skipped + 1)); continue; fi
    cmd="${line%%  #*}"   # drop the trailing comment
    if out="$(timeout 300 bash -c "$cmd" 2>&1 < /dev/null)"; then
        passed=$((passed + 1))
    else
        echo "FAIL ($page): $cmd"
        echo "$out" | tail -5
        failed=$((failed + 1))
    fi
done < "$tmp/lines.txt"
[ $((passed + failed)) -gt 0 ] || { echo "FAIL: no command found in $page"; exit 1; }
echo "$page: $skipped skipped (marked)"
echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]
