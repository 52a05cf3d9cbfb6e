#!/usr/bin/env bash
# Configures and builds lightbake in build/ (Release, warnings as errors).
set -euo pipefail
cd "$(dirname "$0")/.."
mkdir -p build
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DLIGHTBAKE_WERROR=ON > build/configure.log 2>&1 \
  || { cat build/configure.log; exit 1; }
cmake --build build --parallel "$(nproc)"
