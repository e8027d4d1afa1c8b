#!/usr/bin/env bash
# shadelab devices: the lines that tell how the kernels run here (lanes, two-chain models, streaming stores, light
# kinds), the environment variables that set them for every model or launch, and a bad value of each as one error
# line on stderr, nothing on stdout, exit 1.
# Usage: devices.sh SHADELAB_BINARY
set -euo pipefail
bin="$1"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
env -u SHADELAB_STREAM_STORES -u SHADELAB_CHAINS -u SHADELAB_LIGHT_KINDS "$bin" devices > "$tmp/out"
for want in "^lanes: " "^chains: .*lambert" "^stores: .*streaming (non-temporal) where a launch.s shaded planes reach 32 MB.*plain below and for .*hapke_leg" \
            "^lights: .*built into the shade programs"; do
    grep -q "$want" "$tmp/out" || { echo "FAIL: no line matching '$want' in: $(cat "$tmp/out")"; exit 1; }
done
SHADELAB_STREAM_STORES=1 "$bin" devices | grep -q "^stores: *streaming (non-temporal) for every launch" ||
    { echo "FAIL: SHADELAB_STREAM_STORES=1 not shown"; exit 1; }
SHADELAB_STREAM_STORES=0 "$bin" devices | grep -q "^stores: *plain for every launch" ||
    { echo "FAIL: SHADELAB_STREAM_STORES=0 not shown"; exit 1; }
SHADELAB_LIGHT_KINDS=0 "$bin" devices | grep -q "^lights: .*read per light at run time" ||
    { echo "FAIL: SHADELAB_LIGHT_KINDS=0 not shown"; exit 1; }
for var in SHADELAB_STREAM_STORES SHADELAB_CHAINS SHADELAB_LIGHT_KINDS; do
    set +e
    env "$var=yes" "$bin" devices > "$tmp/o" 2> "$tmp/e"
    rc=$?
    set -e
    [ "$rc" -eq 1 ] || { echo "FAIL: $var=yes exits $rc, not 1"; exit 1; }
    [ ! -s "$tmp/o" ] || { echo "FAIL: $var=yes printed to stdout: $(cat "$tmp/o")"; exit 1; }
    [ "$(wc -l < "$tmp/e")" -eq 1 ] && grep -q "$var is 'yes'" "$tmp/e" ||
        { echo "FAIL: $var=yes is not one error line naming it: $(cat "$tmp/e")"; exit 1; }
done
echo "devices: 1 passed, 0 failed"
