#!/usr/bin/env bash
# Sets up, builds, and runs every test.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
scripts/build.sh
# The Khronos glTF validator for the export test (npm, into the build tree), where npm exists.
if command -v npm > /dev/null && [[ ! -d build/npm/node_modules/gltf-validator ]]; then
  npm install --prefix build/npm --no-audit --no-fund --loglevel=error gltf-validator > /dev/null
fi
cd build
ctest --output-on-failure --parallel "$(nproc)" --timeout 600
