#!/usr/bin/env bash
# Builds everything with AddressSanitizer and UndefinedBehaviorSanitizer in build-asan/ and runs
# every test under them (any report fails the test), except those labelled `external`: the
# checks whose work is done by another program (the Khronos validator in Node, three.js in
# Chromium, Cycles in Blender), which scripts/test.sh runs; they would spend sanitizer time on
# exports the other tests already make under the sanitizers. No benchmark is built. Slower than
# scripts/test.sh. Warnings are not errors here: GCC 12 with the sanitizers reports
# uninitialised values inside OpenMesh.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
mkdir -p build-asan
cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=Release -DLIGHTBAKE_SANITIZE=ON \
  -DLIGHTBAKE_WERROR=OFF -DLIGHTBAKE_BENCHMARKS=OFF > build-asan/configure.log 2>&1 \
  || { cat build-asan/configure.log; exit 1; }
cmake --build build-asan --parallel "$(nproc)"
scripts/install-pypi.sh build-asan
cd build-asan
ctest --output-on-failure --parallel "$(nproc)" --timeout 1200 --label-exclude external
