#!/usr/bin/env bash
# Builds everything with AddressSanitizer and UndefinedBehaviorSanitizer in build-asan/ and runs
# every test under them (any report fails the test), except those labelled `external`: the
# checks whose work is done by another program (the Khronos validator in Node, three.js in
# Chromium, Cycles in Blender), which scripts/test.sh runs; they would spend sanitizer time on
# exports the other tests already make under the sanitizers; and those named in
# tests/sanitize_leave_out.txt, each of whose lines of the tool's code the tests kept run too
# (chosen by coverage: scripts/select-sanitized-tests.py). No benchmark is built. Compiled at
# -O1, which halves the build's time. Warnings are not errors here: GCC 12 with the sanitizers
# reports uninitialised values inside OpenMesh.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
mkdir -p build-asan
cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=Release -DLIGHTBAKE_SANITIZE=ON \
  "-DCMAKE_CXX_FLAGS_RELEASE=-O1 -DNDEBUG" "-DCMAKE_C_FLAGS_RELEASE=-O1 -DNDEBUG" \
  -DLIGHTBAKE_WERROR=OFF -DLIGHTBAKE_BENCHMARKS=OFF > build-asan/configure.log 2>&1 \
  || { cat build-asan/configure.log; exit 1; }
cmake --build build-asan --parallel "$(nproc)"
scripts/install-pypi.sh build-asan
cd build-asan
# Every name on the list must still be a test, or the list would rot silently.
names=$(sed -e 's/#.*//' -e 's/[[:space:]]//g' -e '/^$/d' ../tests/sanitize_leave_out.txt)
# A parameterised test's name ends in gtest's "  # GetParam() = ...", which the list omits.
listed=$(ctest -N | sed -n 's/^ *Test *#[0-9]*: //p' | sed 's/  # .*//')
for name in $names; do
  grep -qxF "$name" <<<"$listed" \
    || { echo "tests/sanitize_leave_out.txt: no test is named $name" >&2; exit 1; }
done
ctest --output-on-failure --parallel "$(nproc)" --timeout 1200 --label-exclude external \
  --exclude-regex "^($(paste -sd'|' <<<"$names"))(  # .*)?\$"
