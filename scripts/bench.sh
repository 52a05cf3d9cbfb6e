#!/usr/bin/env bash
# Builds and runs every benchmark; results go to bench/results/ (JSON, and CSV for the lightmap
# benches) and to the terminal.
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
# The lightmap benches against references (minutes each; references cached in build/bench):
# issue 36's densities and leaks, issue 38's directional maps and light probes.
day=$(date +%F)
/usr/bin/python3 bench/lightmap_density.py > "bench/results/lightmap_density_$day.csv"
/usr/bin/python3 bench/directional.py > "bench/results/directional_$day.csv"
# Issue 39: light groups, 4 groups against 1 (CPU seconds, memory) and the blend against a bake
# of scaled powers.
/usr/bin/python3 bench/light_groups.py > "bench/results/light_groups_$day.json"
/usr/bin/python3 bench/probes.py > "bench/results/probes_$day.csv"
# Issue 40: where the CPU time of the room's bake and HQ render goes, per stage (needs perf).
if command -v perf > /dev/null; then
  profile_dir=$(mktemp -d)
  {
    /usr/bin/python3 bench/profile_stages.py -- build/app/lightbake bake scenes/room.toml \
      -o "$profile_dir/bake" -q
    /usr/bin/python3 bench/profile_stages.py -- build/app/lightbake render scenes/room.toml \
      "$profile_dir/bake" --spp 16 --size 640x480 -o "$profile_dir/room.exr" -q
  } > "bench/results/profile_stages_$day.md"
  rm -rf "$profile_dir"
fi
# Issue 36: the direct term denoised by Open Image Denoise (its library from PyPI into build/).
scripts/install-pypi.sh build
/usr/bin/python3 bench/denoise.py > "bench/results/denoise_$day.csv"
# Issue 37: the race against Cycles' baker on the Cornell box's exported atlas (Blender's
# Cycles on the CPU; about an hour of CPU, most of it Cycles' reference bakes).
/usr/bin/python3 bench/cycles_bake_race.py > "bench/results/cycles_bake_race_$day.txt"
