#!/bin/sh
# hostile_exr_memory.sh SHADELAB WIDE_EXR SMALL_IMAGE
# The fuzz finding exr_wide_data_window_3GB.exr read with the memory limit raised (SHADELAB_MAX_MEMORY=64G)
# under an address-space cap of 4 GB above what `shadelab compare` maps at rest: the read must stay within it
# (the float image, its native copy and OpenEXR's decode buffers: 2.8 GB of address space measured, VmPeak,
# with OpenImageIO's 2 threads), and compare must go on to refuse the size mismatch with exit 1. Before the
# native read, OpenImageIO's converting read_scanlines asked for 3.2 GB more, which the cap turns into
# std::bad_alloc.
# Skipped (exit 77) under AddressSanitizer, whose shadow memory does not fit an address-space cap.
set -u
exe=$1; wide=$2; small=$3
if ldd "$exe" 2> /dev/null | grep -q libasan; then
    echo "SKIP: an ASan build maps terabytes of shadow memory; an address-space cap does not apply"
    exit 77
fi
# What the process maps before reading anything big: compare two small images, peak VmPeak from /proc.
base_kb=$("$exe" compare "$small" "$small" > /dev/null 2>&1 & pid=$!; peak=0
          while kill -0 $pid 2> /dev/null; do
              v=$(awk '/^VmPeak/ {print $2}' /proc/$pid/status 2> /dev/null); [ -n "$v" ] && [ "$v" -gt "$peak" ] && peak=$v
              sleep 0.05
          done; echo $peak)
[ "$base_kb" -gt 0 ] || base_kb=1000000
cap_kb=$((base_kb + 4000000))
echo "address-space cap: ${cap_kb} kB (${base_kb} kB at rest + 4 GB)"
# OpenEXR keeps 2 x threads decode buffers: pin the threads (OpenImageIO reads OPENIMAGEIO_THREADS) so the
# figure does not grow with the machine.
err=$( (ulimit -v "$cap_kb"; OPENIMAGEIO_THREADS=2 SHADELAB_MAX_MEMORY=64G exec "$exe" compare "$wide" "$small") 2>&1 > /dev/null)
got=$?
printf '%s\n' "$err" | head -3
[ "$got" -eq 1 ] || { echo "hostile_exr_memory: exit $got, expected 1" >&2; exit 1; }
printf '%s\n' "$err" | grep -Fq "images differ in size (2097160x6" ||
    { echo "hostile_exr_memory: the wide EXR was not read within the cap" >&2; exit 1; }
exit 0
