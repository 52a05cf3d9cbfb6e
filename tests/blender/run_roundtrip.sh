#!/usr/bin/env bash
# ctest blender_roundtrip: our export of a Blender-made scene back into Blender (docs/gltf.md,
# "The lightmap in Blender").
#
#   1. `lightbake export point.glb --contents all` (the point-lamp room of tests/blender, whose
#      corpus blender_point made; it runs first).
#   2. Blender's glTF importer loads the export without an error (import_gltf.py; Debian's
#      Blender 3.4.1 needs numpy's `bool` alias restored first) and TEXCOORD_1 arrives as the
#      second UV map, value for value.
#   3. The lightmap wired into every material as docs/gltf.md says, Cycles (0 bounces: the map
#      holds the light) shows what `lightbake render` shows of the same file: energy within 1%,
#      MRE over 4x4 blocks within 2% (cycles_check with lightbake's image as both halves).
#   4. And what Cycles' own path tracing shows of the original scene: within 2% / 5%, as the
#      scene's HQ render must be (run_blender_check.sh).
#
# Exits 77 (ctest: skipped) when Blender is missing, except under CI (env CI set): a failure.
# Usage: run_roundtrip.sh LIGHTBAKE CYCLES_CHECK SOURCE_DIR CORPUS_DIR OUTPUT_DIR
set -uo pipefail
lightbake=$1 check=$2 source=$3 corpus=$4 out=$5
# shellcheck source=tests/blender/blender_env.sh
source "$source/tests/blender/blender_env.sh"
require_blender

size=96x72
make_scene point "$corpus" --size $size --samples 512  # as run_blender_check.sh: cached
out=$out/roundtrip
rm -rf "$out" && mkdir -p "$out"
status=0

"$lightbake" export "$corpus/point.glb" -o "$out/point_export.glb" --contents all -q \
  2> "$out/export.err" || { echo "lightbake export failed:"; cat "$out/export.err"; exit 1; }

nice "$blender" -b --factory-startup --python-exit-code 1 \
  --python "$source/tests/blender/import_gltf.py" -- "$out/point_export.glb" \
  --render "$out/point_export_blender.exr" --size $size --samples 16 > "$out/import.log" 2>&1 ||
  { echo "Blender's import failed; the end of $out/import.log:"; tail -n 30 "$out/import.log";
    exit 1; }
grep '^import_gltf: ' "$out/import.log"
# The importer reports problems on the console ("HH:MM:SS | ERROR: ...") and carries on.
if grep -E '\| (ERROR|WARNING): ' "$out/import.log"; then
  echo "Blender's importer complained about our export (above)"
  status=1
fi

"$lightbake" render "$out/point_export.glb" --size $size --spp 16 -q \
  -o "$out/point_export_lightbake.exr" > /dev/null 2> "$out/render.err" ||
  { echo "lightbake render of the export failed:"; cat "$out/render.err"; exit 1; }
echo "Blender showing the lightmap against lightbake's render of the same file:"
"$check" "$out/point_export_blender.exr" "$out/point_export_lightbake.exr" \
  "$out/point_export_lightbake.exr" --max-energy 0.01 --max-mre 0.02 \
  --evidence "$out" blender_vs_lightbake || status=1
echo "Blender showing the lightmap against Cycles' path tracing of the original scene:"
"$check" "$out/point_export_blender.exr" "$corpus/point_lambert_a.exr" \
  "$corpus/point_lambert_b.exr" --max-energy 0.02 --max-mre 0.05 \
  --evidence "$out" blender_vs_cycles || status=1
exit $status
