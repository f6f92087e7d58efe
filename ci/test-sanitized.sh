#!/usr/bin/env bash
# Builds ivgi and its tests with clang, AddressSanitizer and UndefinedBehaviorSanitizer in
# build-asan/ and runs the test suite there (lavapipe, validation on): any report fails the run.
# Lavapipe and LLVM are not instrumented; what they keep until exit is left out of the leak check
# (ci/lsan.supp). The loader unloads the driver with the instance, which would leave a report of
# what it kept naming no module to match: preloaded, it stays loaded. (Not the validation layer:
# it exports the loader's own entry points, which a preload would put in the loader's place.)
# Arguments go to ctest (e.g. -R PathTracer).
set -euo pipefail
cd "$(dirname "$0")/.."
flags="-fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer"
cmake -S . -B build-asan -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_C_FLAGS="$flags" -DCMAKE_CXX_FLAGS="$flags" >/dev/null
cmake --build build-asan -j"$(nproc)"
export IVGI_VALIDATION=1 IVGI_DEVICE="${IVGI_DEVICE:-llvmpipe}"
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:strict_string_checks=1"
export LSAN_OPTIONS="suppressions=$PWD/ci/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
export LD_PRELOAD="libvulkan_lvp.so"
ctest --test-dir build-asan --output-on-failure -j"$(nproc)" "$@"
