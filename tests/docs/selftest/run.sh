#!/usr/bin/env bash
# The doc runner's own test: a page whose examples hold passes, and a wrong transcript or a failing command fails
# with a line that names it. Usage: run.sh PYTHON BUILD_DIR SOURCE_DIR
set -uo pipefail
py="$1"; build="$2"; src="$3"; here="$src/tests/docs/selftest"; fails=0
check() {   # check PAGE EXPECTED_EXIT REGEX
    local out rc
    out="$("$py" "$src/tests/docs/run_doc_commands.py" "$here/$1" "$build" "$src" 2>&1)"; rc=$?
    if [ "$rc" -ne "$2" ] || ! grep -Eq -- "$3" <<<"$out"; then
        echo "FAIL $1: exit $rc (expected $2), output does not match /$3/:"; echo "$out"; fails=$((fails + 1))
    fi
}
check good.md 0 "3 passed, 0 failed, 1 not run"
check good.md 0 "not run .*a synopsis: an optional part in brackets"
check bad_output.md 1 "shown but not printed: 'shadelab 0.2.0'"
check bad_exit.md 1 "exit status 1, the page expects 0"
[ "$fails" -eq 0 ] && echo "doc runner self-test: 4 checks passed"
[ "$fails" -eq 0 ]
