#!/usr/bin/env bash
# Builds and runs every benchmark; results go to bench/results/ as JSON and to the terminal.
# Heavy: minutes, not seconds. Not part of the test command.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
scripts/build.sh
mkdir -p bench/results
for exe in build/bench/bench_*; do
  [[ -x $exe ]] || continue
  name=$(basename "$exe")
  echo "== $name"
  "$exe" --benchmark_out="bench/results/$name.json" --benchmark_out_format=json "$@"
done
