#!/usr/bin/env bash
# Submits a sharded HQ render to Slurm: one bake job, an array of N render shards that starts
# when the bake has succeeded, and a merge job after every shard has (docs/farm.md).
#   deploy/slurm/submit.sh SCENE OUT_DIR SHARDS [render options...]
# OUT_DIR must be on storage every node sees. Prints the merge job's id.
set -euo pipefail
if [[ $# -lt 3 ]]; then
  echo "usage: $0 SCENE OUT_DIR SHARDS [render options...]" >&2
  exit 2
fi
scene=$(realpath "$1")
out=$(realpath -m "$2")
shards=$3
shift 3
here=$(dirname "$(realpath "$0")")
mkdir -p "$out"
bake=$(sbatch --parsable --chdir="$out" --output="$out/bake.log" \
  "$here/bake.sbatch" "$scene" "$out/bake")
render=$(sbatch --parsable --chdir="$out" --dependency="afterok:$bake" \
  --array="0-$((shards - 1))" --output="$out/shard_%a.log" \
  "$here/render-shard.sbatch" "$scene" "$out/bake" "$out" "$@")
merge=$(sbatch --parsable --chdir="$out" --dependency="afterok:$render" \
  --output="$out/merge.log" "$here/merge.sbatch" "$out" "$shards")
echo "$merge"
