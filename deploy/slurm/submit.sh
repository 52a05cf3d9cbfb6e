#!/usr/bin/env bash
# Submits a sharded HQ render to Slurm: the bake, an array of N render shards after it and the
# merge (OUT_DIR/render.exr, .png). The same as `submit-shards.sh render ...` (docs/farm.md).
#   deploy/slurm/submit.sh SCENE OUT_DIR SHARDS [render options...]
exec "$(dirname "$(realpath "$0")")/submit-shards.sh" render "$@"
