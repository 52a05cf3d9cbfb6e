#!/usr/bin/env bash
# Submits a sharded bake to Slurm: an array of N pass-1 shards and a merge job that starts
# when every shard has succeeded and writes OUT_DIR/bake (docs/farm.md).
#   deploy/slurm/submit-bake.sh SCENE OUT_DIR SHARDS [bake options...]
# OUT_DIR must be on storage every node sees. Prints the merge job's id.
set -euo pipefail
if [[ $# -lt 3 ]]; then
  echo "usage: $0 SCENE OUT_DIR SHARDS [bake options...]" >&2
  exit 2
fi
scene=$(realpath "$1")
out=$(realpath -m "$2")
shards=$3
shift 3
here=$(dirname "$(realpath "$0")")
mkdir -p "$out"
pass1=$(sbatch --parsable --chdir="$out" --array="0-$((shards - 1))" \
  --output="$out/pass1_%a.log" "$here/bake-shard.sbatch" "$scene" "$out" "$@")
merge=$(sbatch --parsable --chdir="$out" --dependency="afterok:$pass1" \
  --output="$out/merge-bake.log" "$here/merge-bake.sbatch" "$scene" "$out" "$shards")
echo "$merge"
