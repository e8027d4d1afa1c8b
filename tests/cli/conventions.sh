#!/usr/bin/env bash
# The command line's conventions, run as a user would: --version, exit codes (0 ok, 1 bad input, 2 usage),
# "did you mean" for subcommands, flags and model names, models --json / models NAME, defaults that work
# outside the source tree. Usage: conventions.sh SHADELAB_BINARY
set -uo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/expect.sh"   # fails, passes, expect
bin="$1"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
cd "$work"   # outside the source tree on purpose

expect version 0 '^shadelab [0-9]+\.[0-9]+\.[0-9]+$' -- "$bin" --version
expect mistyped_subcommand 2 "unknown command 'rendr' \(did you mean 'render'\?\)" -- "$bin" rendr
expect no_subcommand 2 "subcommand is required" -- "$bin"
expect mistyped_flag 2 "unknown option '--sise' for 'render' \(did you mean '--size'\?\)" -- "$bin" render x.obj --sise 4x4
expect missing_argument 2 "mesh is required" -- "$bin" render
expect mistyped_model 2 "unknown model 'minaert' \(did you mean 'minnaert_1941'\?\)" -- "$bin" render x.obj -m minaert
expect bad_input_is_1 1 "no-such-mesh.obj" -- "$bin" render no-such-mesh.obj -o x.png
expect models_one 0 "range \[0, 2\]" -- "$bin" models minnaert_1941
expect models_unknown 2 "did you mean 'oren_nayar'" -- "$bin" models orennayar
# models --json: a JSON array, one object per model, each with name and params.
if "$bin" models --json > models.json 2> models.err; then
    if python3 -c '
import json, sys
d = json.load(open("models.json"))
assert isinstance(d, list) and len(d) > 30, "not an array of the catalogue"
for m in d:
    assert isinstance(m["name"], str) and isinstance(m["params"], list), m
    for p in m["params"]:
        assert p["min"] <= p["default"] <= p["max"], (m["name"], p)
names = [m["name"] for m in d]
assert len(set(names)) == len(names) and "lambert" in names and "oren_nayar" in names
'; then passes=$((passes + 1)); else echo "FAIL models_json: bad JSON (above)"; fails=$((fails + 1)); fi
else
    echo "FAIL models_json: exit non-zero: $(cat models.err)"; fails=$((fails + 1))
fi
# The plain listing: every parameter line has a gap between its name and "default".
if "$bin" models | grep -E '^ +[a-z0-9_]+default' ; then echo "FAIL models_columns: columns run together"; fails=$((fails + 1)); else passes=$((passes + 1)); fi
# Defaults that name bundled files work from this scratch folder, and write here, not into the source tree.
expect contact_anywhere 0 "contact_sheet.png" -- "$bin" -q contact -m lambert --cell 16
[ -s contact_sheet.png ] && passes=$((passes + 1)) || { echo "FAIL contact_anywhere: no contact_sheet.png here"; fails=$((fails + 1)); }

echo "$passes passed, $fails failed"
[ "$fails" -eq 0 ]
