#!/usr/bin/env bash
# The test suite under AddressSanitizer + UndefinedBehaviorSanitizer, in its own build tree build-asan/.
#
#   scripts/sanitize.sh            build shadelab and shadelab_tests_input with -fsanitize=address,undefined,
#                                  then run the input-facing tests: loaders, scenes and batches, raster,
#                                  images, colour and photometry ([mesh] [scene] [batch] [raster] [image]
#                                  [color] [moon] [hostile] [atomic_file] [photometry] [pvl]) and the CLI checks
#                                  (label hostile)
#   scripts/sanitize.sh --all      the whole suite instead (about an hour on a busy 2-core machine)
#
# Any ASan/UBSan report fails the run (-fno-sanitize-recover). Leaks of the OpenCL runtime (PoCL, LLVM)
# are suppressed by sanitizers/lsan.supp, which names only their libraries (and OpenMesh's one start-up
# leak, explained there).
set -euo pipefail
cd "$(dirname "$0")/.."
B=build-asan
./scripts/install-deps.sh
flags="-fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer"
cmake -S . -B "$B" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS="$flags" \
      -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" > "$B.log" 2>&1 || { cat "$B.log"; exit 1; }
# The subset needs only the input-facing test files (target shadelab_tests_input); --all needs every one.
tests=shadelab_tests_input
[ "${1:-}" = --all ] && tests=shadelab_tests
nice cmake --build "$B" -j2 --target shadelab "$tests" >> "$B.log" 2>&1 ||
  { tail -40 "$B.log"; echo "sanitize: build failed (see $B.log)" >&2; exit 1; }
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=0:halt_on_error=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
export LSAN_OPTIONS=suppressions=$PWD/sanitizers/lsan.supp:print_suppressions=0
cd "$B"
if [ "${1:-}" = --all ]; then
  ctest --output-on-failure -j2 --timeout 3600
else
  ./shadelab_tests_input "[mesh],[scene],[batch],[raster],[parallel],[image],[color],[moon],[hostile],[atomic_file],[photometry],[pvl]"
  ctest --output-on-failure -L hostile
fi
echo "sanitize: clean (ASan + UBSan)"
