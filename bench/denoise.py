#!/usr/bin/python3
"""The export's direct term with and without `--denoise` (Open Image Denoise on the shadow
share, issue 36): error against an independent reference and CPU seconds, at the automatic
shadow rays and at a quarter of them, read two ways.

    /usr/bin/python3 bench/denoise.py                    # Cornell box, 3 densities, ~3 min
    /usr/bin/python3 bench/denoise.py --runs 20:16,16/8,8

Each run DENSITY:SIDES bakes the Cornell box at DENSITY texels/m (0: the automatic rule), then
exports it with `--contents all` at each side, with and without --denoise, and once with
`--contents indirect`. A side N is `--direct-samples N` (N x N points a cell, a shadow ray
each); N/S is `--direct-samples N --shadow-rays S` (N x N points place the texels' fit, S x S
rays a cell on average trace where the shadows are). The default runs take the automatic side
(16 at 10 and 20 texels/m, 4 at the automatic 74), a quarter of its rays from a quarter of the
points, and a quarter of its rays from all the points. Each file is drawn alone (`snapshot out.glb --terms baked`); the
`all` image less the `indirect` one is the direct term as an engine shows it, compared over the
diffuse pixels (the mask of bench/lightmap_density.py) with `lightbake reference --terms
direct` at --reference-spp (cached under build/bench/references/). Both are first averaged
over --block x --block pixel blocks (the mask keeps whole blocks only): the reference's own
noise, 2.3% RMS a pixel at 4096 spp, falls --block times, and a texel at 10 texels/m covers
several pixels anyway. Reports MRE, the sum ratio, and the export's CPU seconds (user + sys of
the child, os.wait4). Needs OIDN's library: scripts/install-pypi.sh puts it in build/pypi,
where lightbake finds it.
"""

import argparse
import json
import os
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from lightmap_density import DIFFUSE_MASK_BELOW, ROOT, run  # noqa: E402


def snapshot(binary, glb, image):
    run([binary, "snapshot", glb, "--terms", "baked", "--size", "256x256", "-o", image, "-q",
         "--force"])


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--binary", default=os.path.join(ROOT, "build/app/lightbake"))
    parser.add_argument("--runs", default="10:16,16/8,8 20:16,16/8,8 0:4,4/2,2",
                        help="DENSITY:SIDE[/SHADOW],... separated by spaces (density 0: "
                        "automatic; SIDE/SHADOW: --direct-samples SIDE --shadow-rays SHADOW)")
    parser.add_argument("--reference-spp", type=int, default=4096)
    parser.add_argument("--block", type=int, default=4, help="pixels a side averaged")
    parser.add_argument("--work", default=None)
    args = parser.parse_args()
    binary = args.binary
    work = args.work or tempfile.mkdtemp(prefix="denoise_")
    os.makedirs(work, exist_ok=True)
    scene = os.path.join(ROOT, "scenes/cornell_box.toml")
    refs = os.path.join(ROOT, "build/bench/references")
    os.makedirs(refs, exist_ok=True)
    reference = os.path.join(
        refs, f"cornell_box_256x256_reference_direct_{args.reference_spp}spp.exr")
    if not os.path.exists(reference):
        print(f"reference, direct term ({args.reference_spp} spp) ...", file=sys.stderr)
        run([binary, "reference", scene, "--terms", "direct", "--spp", str(args.reference_spp),
             "--size", "256x256", "--seed", "1000", "-o", reference, "-q"])
    mask = os.path.join(refs, f"cornell_box_256x256_reference_{4096}spp_diffuse_mask.png")
    if not os.path.exists(mask):
        full = mask.replace("_diffuse_mask.png", ".exr")
        if not os.path.exists(full):
            run([binary, "reference", scene, "--spp", "4096", "--size", "256x256", "--seed",
                 "1000", "-o", full, "-q"])
        subprocess.run(["oiiotool", full, "--ch", "R", "--subc", str(DIFFUSE_MASK_BELOW),
                        "--mulc", "1e6", "--clamp:min=0:max=1", "--dilate", "3x3", "--mulc",
                        "-1", "--addc", "1", "-d", "uint8", "-o", mask], check=True)

    size = f"{256 // args.block}x{256 // args.block}"

    def blocks(image, out):
        subprocess.run(["oiiotool", image, "--resize:filter=box", size, "-o", out], check=True)
        return out

    reference_blocks = blocks(reference, os.path.join(work, "reference_blocks.exr"))
    mask_blocks = os.path.join(work, "mask_blocks.exr")
    subprocess.run(["oiiotool", mask, "--ch", "0", "--resize:filter=box", size, "--subc",
                    "0.999", "--mulc", "1e6", "--clamp:min=0:max=1", "-o", mask_blocks],
                   check=True)

    print("texels_per_m,direct_samples,shadow_rays,rays_per_cell,denoise,export_cpu_s,"
          "direct_mre,direct_sum_ratio")
    for spec in args.runs.split():
        density, sides = spec.split(":")
        measure(binary, scene, float(density), [(x + "/" + x).split("/")[:2] for x in
                                                sides.split(",")],
                os.path.join(work, f"density_{density}"), blocks, reference_blocks, mask_blocks)


def measure(binary, scene, texel_density, sides, work, blocks, reference_blocks, mask_blocks):
    """One bake at texel_density, then the exports at each (side, shadow rays' side), printed
    as CSV rows."""
    os.makedirs(work, exist_ok=True)
    bake = os.path.join(work, "bake")
    density = ["--texel-density", str(texel_density)] if texel_density > 0 else []
    run([binary, "bake", scene, "-o", bake, "-q", "--force"] + density)
    indirect_glb = os.path.join(work, "indirect.glb")
    run([binary, "export", scene, bake, "-o", indirect_glb, "-q", "--force"])
    indirect = os.path.join(work, "indirect.exr")
    snapshot(binary, indirect_glb, indirect)
    for side, shadow in sides:
        shadow_rays = ["--shadow-rays", shadow] if shadow != side else []
        for denoise in (False, True):
            name = f"all_{side}_{shadow}{'_denoised' if denoise else ''}"
            glb = os.path.join(work, name + ".glb")
            cpu, _ = run([binary, "export", scene, bake, "-o", glb, "-q", "--force",
                          "--contents", "all", "--direct-samples", side] + shadow_rays +
                         (["--denoise"] if denoise else []))
            image = os.path.join(work, name + ".exr")
            snapshot(binary, glb, image)
            direct = os.path.join(work, name + "_direct.exr")
            subprocess.run(["oiiotool", image, indirect, "--sub", "-o", direct], check=True)
            direct = blocks(direct, os.path.join(work, name + "_direct_blocks.exr"))
            _, out = run([binary, "compare", direct, reference_blocks, "--mask", mask_blocks])
            metrics = json.loads(out)
            print(f"{texel_density:g},{side},{shadow},{int(shadow) ** 2},{int(denoise)},"
                  f"{cpu:.2f},"
                  f"{metrics['mre']:.4f},{metrics['sum_ratio_total']:.5f}", flush=True)

if __name__ == "__main__":
    main()
