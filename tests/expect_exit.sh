#!/bin/sh
# expect_exit.sh CODE TEXT COMMAND [ARGS...]
# Runs COMMAND; passes when it exits with exactly CODE (a signal is never a pass) and its stderr contains
# TEXT (a fixed string). Prints what it saw either way.
code=$1; text=$2; shift 2
err=$("$@" 2>&1 >/dev/null)
got=$?
printf '%s\n' "$err" | head -5
if [ "$got" -ne "$code" ]; then
    echo "expect_exit: '$*' exited $got, expected $code" >&2
    exit 1
fi
if ! printf '%s\n' "$err" | grep -Fq -- "$text"; then
    echo "expect_exit: stderr does not contain '$text'" >&2
    exit 1
fi
exit 0
