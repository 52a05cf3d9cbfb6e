#!/usr/bin/env bash
# Sets up, builds, and runs the main job on the bundled default scene.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
scripts/build.sh
scene=${1:-scenes/room.toml}
build/app/lightbake info "$scene"
build/app/lightbake bake "$scene" -o out/room
