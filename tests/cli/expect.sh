# Sourced by the CLI test scripts: counters and `expect`, one definition for all of them.
fails=0
passes=0

# expect NAME CODE REGEX -- command...: exit code CODE and REGEX (grep -E) somewhere in stdout+stderr.
expect() {
    local name="$1" code="$2" regex="$3"
    shift 4
    local out rc
    out="$("$@" 2>&1)"
    rc=$?
    if [ "$rc" -ne "$code" ]; then
        echo "FAIL $name: exit $rc, expected $code; output: $out"
        fails=$((fails + 1))
    elif ! grep -Eq -- "$regex" <<<"$out"; then
        echo "FAIL $name: output does not match /$regex/: $out"
        fails=$((fails + 1))
    else
        passes=$((passes + 1))
    fi
}
