#!/usr/bin/env bash
# Set everything up, then run every test (GoogleTest with the Vulkan
# validation layer, the CLI contract, Blender tests) through ctest.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${RTSDF_BUILD_DIR:-$root/build}"
"$root/scripts/setup.sh"
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-$(mktemp -d)}"
cd "$build"
ctest --output-on-failure -j "$(nproc)"
