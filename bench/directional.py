#!/usr/bin/python3
"""Directional lightmaps (issue 38): the exported file drawn alone, plain against directional,
each against a converged reference.

    /usr/bin/python3 bench/directional.py                       # studded wall + Figure 6
    /usr/bin/python3 bench/directional.py --scenes studded_wall --reference-spp 1024

Per scene it bakes once, exports with `--contents all` twice (plain, and `--directional`),
draws each file alone (`snapshot out.glb --terms baked`, the directional one with
`--directional`, i.e. the L1 band taken at the bump- or normal-mapped shading normal) and
reports:
  mre        mean relative error over the diffuse pixels (reference red below 50 W/(sr m^2), less
             one pixel around the rest, which drops visible lamps) against `lightbake reference`
             at --reference-spp (cached under build/bench/references/, as
             bench/lightmap_density.py caches its own);
  energy     the directional frame's sum over the plain frame's, minus 1 (same pixels), and
             each frame's sum over the reference's, minus 1 (bumped surfaces receive less light
             than the plain map draws: the decode's W term, docs/export.md);
  cpu        CPU seconds (user + sys of the children, os.wait4) of bake + export, plain and
             directional, and the directional one's increase;
  memory     the map's bytes in the file, 8 bits a channel: the plain map's, and the
             directional's (L0 + the three L1 maps, the x map with s in alpha: 13/3 x).
"""

import argparse
import json
import os
import subprocess
import sys
import tempfile

from lightmap_density import run  # CPU seconds of the child, its stdout

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DIFFUSE_MASK_BELOW = 50.0  # W/(sr m^2): above every diffuse pixel of these scenes, below lamps


def reference(binary, scene, size, spp):
    """The cached reference EXR of SCENE and its diffuse-pixel mask."""
    refs = os.path.join(ROOT, "build/bench/references")
    os.makedirs(refs, exist_ok=True)
    name = os.path.basename(scene)[:-5]
    path = os.path.join(refs, f"{name}_{size}_reference_{spp}spp.exr")
    if not os.path.exists(path):
        print(f"{name}: reference ({spp} spp) ...", file=sys.stderr)
        run([binary, "reference", scene, "--spp", str(spp), "--size", size, "--seed", "1000",
             "-o", path, "-q"])
    mask = path[:-4] + "_diffuse_mask.png"
    if not os.path.exists(mask):
        subprocess.run(["oiiotool", path, "--ch", "R", "--subc", str(DIFFUSE_MASK_BELOW),
                        "--mulc", "1e6", "--clamp:min=0:max=1", "--dilate", "3x3", "--mulc",
                        "-1", "--addc", "1", "-d", "uint8", "-o", mask], check=True)
    return path, mask


def compare(binary, image, ref, mask):
    _, out = run([binary, "compare", image, ref, "--mask", mask])
    return json.loads(out)


def measure(binary, scene_name, work, size, spp):
    scene = os.path.join(ROOT, "scenes", scene_name + ".toml")
    ref, mask = reference(binary, scene, size, spp)
    bake = os.path.join(work, scene_name + "_bake")
    cpu_bake, _ = run([binary, "bake", scene, "-o", bake, "-q", "--force"])
    row = {"scene": scene_name, "cpu_bake": cpu_bake}
    for kind, extra in (("plain", []), ("directional", ["--directional"])):
        glb = os.path.join(work, f"{scene_name}_{kind}.glb")
        cpu, out = run([binary, "export", scene, bake, "-o", glb, "--contents", "all",
                        "--force"] + extra)
        image = os.path.join(work, f"{scene_name}_{kind}.exr")
        run([binary, "snapshot", glb, "--terms", "baked", "--size", size, "-o", image, "-q",
             "--force"] + extra)
        row[f"cpu_export_{kind}"] = cpu
        against_reference = compare(binary, image, ref, mask)
        row[f"mre_{kind}"] = against_reference["mre"]
        row[f"energy_ref_{kind}"] = against_reference["sum_ratio_total"] - 1.0
        row[f"image_{kind}"] = image
        for line in out.splitlines():
            if line.startswith("lightmap"):
                dims = line.split()[1].split("x")
                row["texels"] = int(dims[0]) * int(dims[1])
    row["energy"] = compare(binary, row["image_directional"], row["image_plain"],
                            mask)["sum_ratio_total"] - 1.0
    return row


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--scenes", default="studded_wall,fig6_bump")
    parser.add_argument("--binary", default=os.path.join(ROOT, "build/app/lightbake"))
    parser.add_argument("--size", default="256x192")
    parser.add_argument("--reference-spp", type=int, default=4096)
    parser.add_argument("--work", default=None)
    args = parser.parse_args()
    work = args.work or tempfile.mkdtemp(prefix="directional_")
    os.makedirs(work, exist_ok=True)
    print("scene,mre_plain,mre_directional,ratio,energy_vs_plain,energy_plain_vs_reference,"
          "energy_directional_vs_reference,cpu_bake_s,cpu_export_plain_s,"
          "cpu_export_directional_s,cpu_increase,map_bytes_plain,map_bytes_directional")
    for name in args.scenes.split(","):
        r = measure(args.binary, name, work, args.size, args.reference_spp)
        plain = r["cpu_bake"] + r["cpu_export_plain"]
        directional = r["cpu_bake"] + r["cpu_export_directional"]
        texels = r.get("texels", 0)
        print(f"{name},{r['mre_plain']:.4f},{r['mre_directional']:.4f},"
              f"{r['mre_directional'] / r['mre_plain']:.3f},{r['energy']:+.5f},"
              f"{r['energy_ref_plain']:+.5f},{r['energy_ref_directional']:+.5f},"
              f"{r['cpu_bake']:.2f},{r['cpu_export_plain']:.2f},{r['cpu_export_directional']:.2f},"
              f"{directional / plain - 1:+.3f},{3 * texels},{13 * texels}", flush=True)


if __name__ == "__main__":
    main()
