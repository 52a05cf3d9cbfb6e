#!/usr/bin/env bash
# Builds everything with AddressSanitizer and UndefinedBehaviorSanitizer in build-asan/ and runs
# every test under them (any report fails the test). Slower than scripts/test.sh. Warnings are
# not errors here: GCC 12 with the sanitizers reports uninitialised values inside OpenMesh.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
mkdir -p build-asan
cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=Release -DLIGHTBAKE_SANITIZE=ON \
  -DLIGHTBAKE_WERROR=OFF > build-asan/configure.log 2>&1 || { cat build-asan/configure.log; exit 1; }
cmake --build build-asan --parallel "$(nproc)"
# The export validator test needs the npm package where scripts/test.sh put it.
if [[ -d build/npm ]] && [[ ! -e build-asan/npm ]]; then ln -s ../build/npm build-asan/npm; fi
# The Blender corpus and its Cycles renders (tests/blender) do not depend on the build: reused.
if [[ -d build/blender-corpus ]] && [[ ! -e build-asan/blender-corpus ]]; then
  ln -s ../build/blender-corpus build-asan/blender-corpus
fi
cd build-asan
ctest --output-on-failure --parallel "$(nproc)" --timeout 1200
