#!/usr/bin/env bash
# Sets up, builds, and runs the main job on the bundled default scene: bake it, write the
# maps, a real-time snapshot and a high-quality render, and open the viewer when a display
# exists. Outputs go to out/.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
scripts/build.sh
scene=${1:-scenes/room.toml}
name=$(basename "$scene" .toml)
lightbake=build/app/lightbake
$lightbake info "$scene"
$lightbake bake "$scene" -o "out/$name"
$lightbake snapshot "$scene" "out/$name" -o "out/$name/snapshot.png"
$lightbake render "$scene" "out/$name" --size 640x480 --spp 16 -o "out/$name/render.png"
if [[ -n ${DISPLAY:-} ]]; then
  $lightbake view "$scene" "out/$name"
fi
