#!/usr/bin/env bash
# The house rule of issue 14: no function in host/ is longer than 80 lines (pmccabe's line count, column 5).
# Fails naming each longer function with its file and line. Functions that other work is splitting at the same
# time may be listed in long_functions.allow ("file function  # who removes it"); an allowed function that is no
# longer long (or no longer exists) fails too, so the list cannot go stale.
# Usage: function_length.sh SOURCE_DIR [MAX_LINES]
set -euo pipefail
src="$1"
max="${2:-80}"
allow="$src/tests/house/long_functions.allow"
command -v pmccabe > /dev/null || { echo "FAIL: pmccabe not found: run scripts/install-deps.sh"; exit 1; }
cd "$src"
mapfile -t files < <(find host -name '*.cpp' | sort)
[ "${#files[@]}" -gt 0 ] || { echo "FAIL: no host/**/*.cpp under $src"; exit 1; }

# pmccabe does not know C++11 raw strings: a quote inside R"(...)" makes it read the rest of the file as one
# function. It reads copies whose raw strings are emptied (their newlines kept, so every line number holds).
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
for f in "${files[@]}"; do
    mkdir -p "$tmp/src/$(dirname "$f")"
    perl -0pe 's/R"([^(\s"]*)\((.*?)\)\1"/my $b = $2; $b =~ s{[^\n]}{}g; "R\"$1($b)$1\""/gse' "$f" > "$tmp/src/$f"
done
# pmccabe: "complexity  modified  statements  first-line  lines  file(line): name"; names are shown without the
# shadelab:: and anonymous-namespace qualifiers, as a reader names them.
(cd "$tmp/src" && pmccabe "${files[@]}") > "$tmp/out" 2> "$tmp/err" || true
[ -s "$tmp/out" ] || { echo "FAIL: pmccabe printed nothing: $(head -3 "$tmp/err")"; exit 1; }
# What else it could not follow (a class nested in a class): said, not failed; the lengths it gives there still hold.
sed 's/^/note: pmccabe: /' "$tmp/err"
awk -F'\t' -v max="$max" '$5 > max {
    loc = $6; sub(/: .*/, "", loc); name = $6; sub(/^[^:]*\): /, "", name)
    gsub(/shadelab::|anonymous_namespace::/, "", name)
    file = loc; sub(/\(.*/, "", file); line = loc; sub(/.*\(/, "", line); sub(/\)/, "", line)
    print file "\t" name "\t" line "\t" $5 }' "$tmp/out" > "$tmp/long"

declare -A allowed=()
if [ -f "$allow" ]; then
    n=0
    while IFS= read -r raw || [ -n "$raw" ]; do
        n=$((n + 1))
        entry="${raw%%#*}"
        read -r file func rest <<< "$entry" || true
        [ -n "${file:-}" ] || continue
        if [ -z "${func:-}" ] || [ -n "${rest:-}" ] || [[ "$raw" != *"#"?* ]]; then
            echo "FAIL: $allow:$n: expected 'file function  # who removes it', got '$raw'"; exit 1
        fi
        allowed["$file $func"]=1
    done < "$allow"
fi

fails=0
while IFS=$'\t' read -r file name line lines; do
    if [ -n "${allowed["$file $name"]+x}" ]; then
        echo "allowed: $file:$line: $name is $lines lines (listed in long_functions.allow)"
        allowed["$file $name"]=seen
    else
        echo "FAIL: $file:$line: $name is $lines lines (more than $max): split it by meaning, one function per step"
        fails=$((fails + 1))
    fi
done < "$tmp/long"
for key in "${!allowed[@]}"; do
    if [ "${allowed[$key]}" != seen ]; then
        echo "FAIL: long_functions.allow lists '$key', which is no longer over $max lines: remove the line"
        fails=$((fails + 1))
    fi
done
checked="$(wc -l < "$tmp/out")"
if [ "$fails" -gt 0 ]; then
    echo "function length: $fails failed ($checked functions in ${#files[@]} files)"
    exit 1
fi
echo "function length: $checked functions in ${#files[@]} files, none over $max lines outside the allow-list"
