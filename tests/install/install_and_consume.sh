#!/usr/bin/env bash
# Installs shadelab into a temporary prefix and uses it from outside the source tree: every public header
# compiles on its own, find_package(shadelab) gives shadelab::shadelab, pkg-config finds shadelab.pc, and a
# consumer program built both ways runs from another folder (kernels and meshes found from the prefix).
# The installed Python module too, when PYTHON is given. Usage: install_and_consume.sh BUILD_DIR [PYTHON]
set -euo pipefail
build="$(cd "$1" && pwd)"
here="$(cd "$(dirname "$0")" && pwd)"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
prefix="$tmp/prefix"
cmake --install "$build" --prefix "$prefix" > "$tmp/install.log"
for h in "$prefix"/include/shadelab/*.hpp; do
    echo "#include <shadelab/$(basename "$h")>" > "$tmp/one.cpp"
    g++ -std=c++17 -Wall -Wextra -Werror -fsyntax-only -I"$prefix/include" "$tmp/one.cpp" \
        || { echo "FAIL: $(basename "$h") does not compile on its own"; exit 1; }
done
echo "headers: $(ls "$prefix"/include/shadelab/*.hpp | wc -l) compile on their own"
mesh="$prefix/share/shadelab/meshes/spot.obj"
[ -f "$mesh" ] || { echo "FAIL: bundled mesh not installed"; exit 1; }
# CMake package
cmake -S "$here/consumer" -B "$tmp/consumer" -DCMAKE_PREFIX_PATH="$prefix" > "$tmp/consumer.log" 2>&1 \
    || { cat "$tmp/consumer.log"; echo "FAIL: find_package(shadelab)"; exit 1; }
cmake --build "$tmp/consumer" > "$tmp/consumer-build.log" 2>&1 || { cat "$tmp/consumer-build.log"; exit 1; }
out="$(cd "$tmp" && env -u SHADELAB_KERNELS "$tmp/consumer/consumer" "$mesh")"
echo "$out"
real_prefix="$(cd "$prefix" && pwd -P)"
grep -q "^kernels: $real_prefix/share/shadelab/kernels" <<<"$out" \
    || { echo "FAIL: the library did not read its kernels from the prefix"; exit 1; }
# pkg-config
pc="$(ls -d "$prefix"/lib*/pkgconfig | head -1)"
[ -f "$pc/shadelab.pc" ] || { echo "FAIL: no shadelab.pc"; exit 1; }
flags="$(PKG_CONFIG_PATH="$pc" pkg-config --cflags --libs shadelab)"
libdir="$(PKG_CONFIG_PATH="$pc" pkg-config --variable=libdir shadelab)"
g++ "$here/consumer/main.cpp" $flags -Wl,-rpath,"$libdir" -o "$tmp/consumer-pc"
(cd "$tmp" && "$tmp/consumer-pc" "$mesh")
# the installed command line works from anywhere too
(cd "$tmp" && "$prefix/bin/shadelab" --version)
(cd "$tmp" && env -u SHADELAB_KERNELS "$prefix/bin/shadelab" devices) | grep -q "^kernels: *$real_prefix/share/shadelab/kernels" \
    || { echo "FAIL: the installed shadelab did not read its kernels from the prefix"; exit 1; }
# ... and finds the image plug-in of the prefix (OpenImageIO reads the PNG back; host/image/image_io.hpp)
(cd "$tmp" && "$prefix/bin/shadelab" -q render "$mesh" --size 32x24 -o "$tmp/i.png" > /dev/null &&
    LD_DEBUG=files "$prefix/bin/shadelab" compare "$tmp/i.png" "$tmp/i.png" 2> "$tmp/plugin.log" > /dev/null) \
    || { echo "FAIL: the installed shadelab could not read back the PNG it wrote"; exit 1; }
grep -q "file=$real_prefix/lib.*/shadelab/libshadelab_imageio.so" "$tmp/plugin.log" \
    || { echo "FAIL: the installed shadelab did not load the prefix's image plug-in"; exit 1; }
if [ $# -ge 2 ]; then
    site="$(ls -d "$prefix"/lib*/python3/dist-packages | head -1)"
    (cd "$tmp" && env -u SHADELAB_KERNELS PYTHONPATH="$site" "$2" -c '
import numpy as np, shadelab
N = np.array([[0, 0, 1]], np.float32)
v = shadelab.shade("lambert", N, N, N)
assert abs(v[0, 0] - 1) < 1e-6, v
print("python module from the prefix:", shadelab.__file__)
') || { echo "FAIL: the installed Python module"; exit 1; }
fi
echo "install: 1 passed, 0 failed"
