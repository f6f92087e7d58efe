#!/usr/bin/env bash
# Runs the whole test suite on lavapipe with the Vulkan validation layers on.
set -euo pipefail
cd "$(dirname "$0")/.."
export IVGI_VALIDATION=1
ctest --test-dir build --output-on-failure -j"$(nproc)" "$@"
