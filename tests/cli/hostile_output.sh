#!/bin/sh
# hostile_output.sh SHADELAB MESH PVL SCRATCH
# Writing onto a full file system or into a read-only folder: every output (an sRGB PNG, a float EXR, a FITS
# image, a batch's images and report, a photometry table) must end in exactly one error line (the progress
# lines a command prints on stderr aside) naming the folder and the cause, exit 1, and no file left behind
# (neither the target nor the hidden temporary).
#
# The full and read-only folders are small tmpfs mounts made in a private mount namespace (unshare -m), so
# nothing is visible outside this script and nothing is left mounted if it dies. Where the machine cannot
# mount (not root, no mount namespaces) the test is skipped (exit 77) and says why.
set -u
exe=$1; mesh=$2; pvl=$3; scratch=$4
if [ "${SHADELAB_OUTPUT_NS:-}" != 1 ]; then
    if ! unshare -m --propagation private true 2> /dev/null; then
        echo "SKIP: cannot make a private mount namespace here (unshare -m needs root or user namespaces)"
        exit 77
    fi
    SHADELAB_OUTPUT_NS=1 exec unshare -m --propagation private sh "$0" "$@"
fi
rm -rf "$scratch"
mkdir -p "$scratch/full" "$scratch/ro" "$scratch/in"
if ! mount -t tmpfs -o size=64k tmpfs "$scratch/full" 2> /dev/null ||
   ! mount -t tmpfs -o ro,size=64k tmpfs "$scratch/ro" 2> /dev/null; then
    echo "SKIP: cannot mount a 64 kB tmpfs here (mount -t tmpfs needs CAP_SYS_ADMIN)"
    exit 77
fi
# Fill the small file system to its last block: dd stops with ENOSPC.
dd if=/dev/zero of="$scratch/full/filler" bs=4096 > /dev/null 2>&1
printf '{ "name": "s", "meshes": [ { "path": "%s" } ], "resolution": [32, 32], "outputs": { "png": "{name}.png" } }\n' \
    "$mesh" > "$scratch/in/s.json"
printf 'phase,incidence,emission\n60,45,30\n30,20,10\n' > "$scratch/in/g.csv"

fail=0
# check NAME CAUSE DIR COMMAND...: exit 1, one 'shadelab: error:' line naming DIR and CAUSE, DIR holds only
# the filler.
check() {
    name=$1; cause=$2; dir=$3; shift 3
    err=$("$@" 2>&1 > /dev/null)
    got=$?
    line=$(printf '%s\n' "$err" | grep '^shadelab: error:')
    lines=$(printf '%s\n' "$err" | grep -c '^shadelab: error:')
    left=$(ls -A "$dir" | grep -vx filler | tr '\n' ' ')
    verdict=ok
    [ "$got" -eq 1 ] || verdict="exit $got, expected 1"
    [ "$lines" -eq 1 ] || verdict="$verdict; $lines error lines, expected 1"
    printf '%s\n' "$line" | grep -Fq -- "$dir" || verdict="$verdict; the message does not name the folder"
    printf '%s\n' "$line" | grep -Fq -- "$cause" || verdict="$verdict; the message does not say '$cause'"
    [ -z "$left" ] || verdict="$verdict; left behind: $left"
    echo "$name: $verdict"
    printf '    %s\n' "$line"
    [ "$verdict" = ok ] || fail=1
}
full=$scratch/full; ro=$scratch/ro
for d in full ro; do
    eval dir=\$$d
    cause="the disk is full"
    [ $d = ro ] && cause="read-only"
    check "render png ($d)" "$cause" "$dir" "$exe" render "$mesh" --size 64x64 -o "$dir/x.png"
    check "render exr ($d)" "$cause" "$dir" "$exe" render "$mesh" --size 64x64 -o "$dir/x.exr"
    check "render fits ($d)" "$cause" "$dir" "$exe" render "$mesh" --size 64x64 -o "$dir/x.fits"
    check "batch ($d)" "$cause" "$dir" "$exe" batch "$scratch/in/s.json" --out "$dir"
    check "photometry csv ($d)" "$cause" "$dir" "$exe" photometry eval --pvl "$pvl" --csv "$scratch/in/g.csv" -o "$dir/v.csv"
done
exit $fail
