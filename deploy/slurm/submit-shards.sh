#!/usr/bin/env bash
# Submits a sharded lightbake command to Slurm: an array of N shards (shard.sbatch) and a merge
# job that starts when every shard has succeeded (merge.sbatch, --dependency=afterok); render
# and export first submit the bake their shards read (bake.sbatch), unless BAKE_DIR names one.
#   deploy/slurm/submit-shards.sh KIND SCENE OUT_DIR SHARDS [options of the KIND's command...]
#   KIND      shards                       merge job writes
#   render    OUT_DIR/shard_i.rendershard  OUT_DIR/render.exr and .png
#   bake      OUT_DIR/pass1_i.pass1        OUT_DIR/bake (directory)
#   reference OUT_DIR/ref_i.refshard       OUT_DIR/reference.exr and .png
#   export    OUT_DIR/part_i.texshard      OUT_DIR/export.glb (+ its lightmap); --contents all
# OUT_DIR (and BAKE_DIR) must be on storage every node sees, and lightbake on every node's
# PATH. Prints the merge job's id. docs/farm.md.
set -euo pipefail
if [[ $# -lt 4 || ! $1 =~ ^(render|bake|reference|export)$ || ! $4 =~ ^[1-9][0-9]*$ ]]; then
  echo "usage: $0 render|bake|reference|export SCENE OUT_DIR SHARDS [options...]" >&2
  exit 2
fi
kind=$1
scene=$(realpath "$2")
out=$(realpath -m "$3")
shards=$4
shift 4
here=$(dirname "$(realpath "$0")")
mkdir -p "$out"

after=()
if [[ $kind == render || $kind == export ]]; then
  if [[ -n ${BAKE_DIR:-} ]]; then
    bake=$(realpath "$BAKE_DIR")
  else
    bake="$out/bake"
    job=$(sbatch --parsable --chdir="$out" --output="$out/bake.log" \
      "$here/bake.sbatch" "$scene" "$bake")
    after=(--dependency="afterok:$job")
  fi
fi
merge_options=()
name=$kind
case $kind in
  # The PNG first: each merge rewrites the .json report, which then names the EXR.
  render)
    part='shard_{}.rendershard' command=(render "$scene" "$bake" --force)
    outputs="$out/render.png,$out/render.exr" merge_options=(--force) ;;
  bake)
    # Named pass1: bake.sbatch's job is the whole bake.
    part='pass1_{}.pass1' command=(bake "$scene") name=pass1
    outputs="$out/bake" merge_options=(--scene "$scene") ;;
  reference)
    part='ref_{}.refshard' command=(reference "$scene")
    outputs="$out/reference.png,$out/reference.exr" ;;
  export)
    part='part_{}.texshard' command=(export "$scene" "$bake" --contents all)
    outputs="$out/export.glb" ;;
esac
stem=${part%.*}
array=$(sbatch --parsable --chdir="$out" "${after[@]}" --array="0-$((shards - 1))" \
  --job-name="lightbake-$name" --output="$out/${stem//\{\}/%a}.log" \
  "$here/shard.sbatch" "$out/$part" "${command[@]}" "$@")
merge=$(sbatch --parsable --chdir="$out" --dependency="afterok:$array" \
  --job-name="lightbake-merge-$kind" --output="$out/merge.log" \
  "$here/merge.sbatch" "$out/$part" "$shards" "$outputs" "${merge_options[@]}")
echo "$merge"
