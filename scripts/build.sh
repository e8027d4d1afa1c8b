#!/usr/bin/env bash
# Installs what is missing (Debian packages, as root), then configures and builds into build/.
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/install-deps.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release > build.log 2>&1 || { cat build.log; echo "configure failed (log above)" >&2; exit 1; }
cmake --build build -j"$(nproc)" >> build.log 2>&1 || { tail -50 build.log; echo "build failed: see build.log" >&2; exit 1; }
echo "build: ok (build/shadelab, build/shadelab_tests)"
