#!/usr/bin/env bash
# ctest gltf_export_validator: exports a few scenes with `lightbake export` and runs the Khronos
# glTF-Validator on each (scripts/validate_gltf.js); fails on any error or warning.
# Exits 77 (ctest: skipped) when Node or the npm package is missing; install the package with
#   npm install --prefix build/npm gltf-validator
# Usage: validate_exports.sh LIGHTBAKE SOURCE_DIR OUTPUT_DIR NODE_MODULES
set -uo pipefail
lightbake=$1 source=$2 out=$3 modules=$4
if ! command -v node >/dev/null || [[ ! -d $modules/gltf-validator ]]; then
  # scripts/test.sh installs the package wherever npm exists, as on CI's machines: there a
  # missing validator is a failure, not a skip.
  if [[ ${CI:-} == true ]]; then
    echo "error: CI needs node and $modules/gltf-validator (scripts/test.sh installs it)"
    exit 1
  fi
  echo "skipped: needs node and $modules/gltf-validator (npm install --prefix build/npm gltf-validator)"
  exit 77
fi
mkdir -p "$out"
status=0
for scene in scenes/room.toml scenes/cornell_glass.toml scenes/fig6_bump.toml \
             tests/data/gltf/materials.gltf tests/data/gltf/textured_quad.gltf; do
  name=$(basename "${scene%.*}")
  for ext in glb gltf; do
    file=$out/$name.$ext
    if ! "$lightbake" export -q "$source/$scene" -o "$file" --force 2>/dev/null; then
      echo "$scene: export failed"; status=1; continue
    fi
    NODE_PATH=$modules node "$source/scripts/validate_gltf.js" "$file" | grep -v '^  \[2\]' || status=1
  done
done
exit $status
