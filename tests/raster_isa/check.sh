#!/bin/bash
# The rasteriser compiled for this CPU, for an AVX2 CPU and for generic x86-64 gives the same fragments, bit for
# bit, in every case of raster_isa_hash.cpp (which says why). The AVX2 build is skipped, and said so, on a CPU
# without AVX2, which cannot run it.
# Usage: check.sh NATIVE_DRIVER AVX2_DRIVER GENERIC_DRIVER MESH...
set -euo pipefail
native=$1 avx2=$2 generic=$3
shift 3
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
"$native" "$@" > "$out/native"
drivers=(generic)
if grep -qw avx2 /proc/cpuinfo; then drivers+=(avx2); else echo "note: this CPU has no AVX2: the AVX2 build is not run"; fi
status=0
for d in "${drivers[@]}"; do
    "${!d}" "$@" > "$out/$d"
    if ! diff "$out/native" "$out/$d" > "$out/diff"; then
        echo "FAIL: the $d build's fragments differ from this CPU's build in these cases (< native, > $d):"
        cat "$out/diff"
        status=1
    fi
done
cases=$(wc -l < "$out/native")
[ "$cases" -gt 0 ] || { echo "FAIL: the native driver printed no case"; exit 1; }
[ $status -eq 0 ] && echo "ok: $cases cases, the same fragments from the native, ${drivers[*]} builds"
exit $status
