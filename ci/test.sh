#!/usr/bin/env bash
# Runs the whole test suite on lavapipe with the Vulkan validation layers on.
set -euo pipefail
cd "$(dirname "$0")/.."
export IVGI_VALIDATION=1
# lavapipe even where a GPU is present: the goldens are lavapipe's, and so are the defaults the
# tests check (iv's --receiver-tol follows the device).
export IVGI_DEVICE="${IVGI_DEVICE:-llvmpipe}"
ctest --test-dir build --output-on-failure -j"$(nproc)" "$@"
