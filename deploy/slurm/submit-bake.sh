#!/usr/bin/env bash
# Submits a sharded bake to Slurm: an array of N pass-1 shards and the merge that finishes the
# bake in OUT_DIR/bake. The same as `submit-shards.sh bake ...` (docs/farm.md).
#   deploy/slurm/submit-bake.sh SCENE OUT_DIR SHARDS [bake options...]
exec "$(dirname "$(realpath "$0")")/submit-shards.sh" bake "$@"
