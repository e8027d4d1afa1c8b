#!/usr/bin/env bash
# The image plug-in (host/image/image_io.hpp): OpenImageIO and GDAL are loaded only when a format needs them.
# `shadelab render -o x.png` and `-o x.exr` must not load them (the dynamic loader's own log, LD_DEBUG=files,
# names every library it opens); reading the images back (`compare`) must load the plug-in and work; a plug-in
# that cannot be found is one error line naming where it was looked for, with exit 1.
# Usage: image_plugin.sh SHADELAB_BINARY MESH
set -euo pipefail
bin="$1"
mesh="$2"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

LD_DEBUG=files "$bin" -q render "$mesh" --size 64x48 -o "$tmp/a.png" 2> "$tmp/render.log" > /dev/null
[ -s "$tmp/a.png" ] || fail "render wrote no PNG"
grep -q "file=libOpenCL" "$tmp/render.log" || fail "the loader's log names no library at all: LD_DEBUG=files did not work"
! grep -q "libOpenImageIO" "$tmp/render.log" || fail "render -o .png loaded OpenImageIO"
! grep -q "libgdal" "$tmp/render.log" || fail "render -o .png loaded GDAL"
! grep -q "libshadelab_imageio" "$tmp/render.log" || fail "render -o .png loaded the image plug-in"

LD_DEBUG=files "$bin" compare "$tmp/a.png" "$tmp/a.png" 2> "$tmp/compare.log" > "$tmp/compare.out"
grep -q "libshadelab_imageio" "$tmp/compare.log" || fail "compare did not load the image plug-in to read the PNG"
grep -q "libOpenImageIO" "$tmp/compare.log" || fail "the image plug-in did not bring OpenImageIO"
grep -q "Delta E 2000 *mean 0 " "$tmp/compare.out" || fail "the PNG does not compare equal to itself: $(cat "$tmp/compare.out")"

LD_DEBUG=files "$bin" -q render "$mesh" --size 64x48 -o "$tmp/a.exr" 2> "$tmp/render_exr.log" > /dev/null
[ -s "$tmp/a.exr" ] || fail "render wrote no EXR"
! grep -q "libOpenImageIO\|libgdal\|libshadelab_imageio" "$tmp/render_exr.log" || fail "render -o .exr loaded the image plug-in"
"$bin" compare "$tmp/a.exr" "$tmp/a.png" > "$tmp/exr.out" || fail "EXR against PNG did not compare"
grep -q "Delta E 2000" "$tmp/exr.out" || fail "no comparison printed: $(cat "$tmp/exr.out")"

set +e
SHADELAB_IMAGEIO_PLUGIN="$tmp/no-such-plugin.so" "$bin" compare "$tmp/a.png" "$tmp/a.png" > /dev/null 2> "$tmp/err"
code=$?
set -e
[ "$code" -eq 1 ] || fail "a missing plug-in exited $code, not 1"
[ "$(wc -l < "$tmp/err")" -eq 1 ] || fail "a missing plug-in printed more than one line: $(cat "$tmp/err")"
grep -q "cannot load the image plug-in libshadelab_imageio.so.*no-such-plugin.so" "$tmp/err" ||
    fail "the missing plug-in's message does not say what and where: $(cat "$tmp/err")"
echo "image_plugin: 5 passed, 0 failed"
