#!/usr/bin/env bash
# The one list of every Debian package shadelab builds, runs and tests with.
# Run as root on Debian 12 (bookworm). Safe to re-run: it installs only what is missing.
set -euo pipefail

PACKAGES=(
  # toolchain
  build-essential cmake pkg-config
  # OpenCL: PoCL CPU runtime, ICD loader, C and C++ headers, clinfo for diagnosis
  pocl-opencl-icd ocl-icd-opencl-dev opencl-c-headers opencl-clhpp-headers clinfo
  # mesh IO, image IO, host maths
  libopenmesh-dev libopenimageio-dev openimageio-tools libglm-dev
  # EXR headers checked before OpenImageIO opens them (OpenEXR core C library)
  libopenexr-dev
  # PNG written without OpenImageIO, which the image plug-in loads only when needed (host/image/png_writer.hpp)
  libpng-dev zlib1g-dev
  # planetary data: FITS (cfitsio) and ISIS3 cubes, PDS3/PDS4, GeoTIFF (GDAL)
  libcfitsio-dev libgdal-dev
  # command line, JSON, tests
  libcli11-dev nlohmann-json3-dev catch2
  # SHA-256 keys and checksums of the OpenCL program-binary cache (host/cl/program_cache.cpp)
  libssl-dev
  # charts (gnuplot renders the PNG plots); the font the contact sheet's labels use
  gnuplot-nox fonts-dejavu-core
  # the Python module (pybind11 on Debian's python3 and numpy), its tests, and docs/python.md's worked example
  pybind11-dev python3-dev python3-numpy python3-pytest python3-astropy python3-matplotlib
  # the docs' own examples, run by ctest (tests/docs/setup/): an ISIS3 cube made with GDAL's Python bindings
  python3-gdal
  # GNU parallel: the cluster recipe of docs/batch.md and its test (tests/cli/shards.sh)
  parallel
  # pmccabe: the function-length rule of host/ (tests/house/function_length.sh)
  pmccabe
  # bench/bench_e2e.cpp: Mesa's llvmpipe (software OpenGL) headless through EGL, and the EGL/OpenGL headers
  libegl-dev libopengl-dev libgl-dev libegl-mesa0 libgl1-mesa-dri
  # fuzz/ (scripts/fuzz.sh): clang with libFuzzer and the ASan/UBSan runtimes
  clang libclang-rt-14-dev
)

missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#PACKAGES[@]} packages present"
  exit 0
fi

if [ "$(id -u)" -ne 0 ]; then
  echo "install-deps: missing packages: ${missing[*]}" >&2
  echo "install-deps: run this script as root (or: sudo apt-get install ${missing[*]})" >&2
  exit 1
fi

echo "install-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
apt-get update -qq
apt-get install -y -qq --no-install-recommends "${missing[@]}"
