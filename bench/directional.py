#!/usr/bin/python3
"""Directional lightmaps (issue 38): the exported file drawn alone, plain against directional,
each against a converged reference.

    /usr/bin/python3 bench/directional.py                       # studded wall + Figure 6
    /usr/bin/python3 bench/directional.py --scenes studded_wall --reference-spp 1024
    /usr/bin/python3 bench/directional.py --native              # the native bake, no export

Per scene it bakes once, exports with `--contents all` three times (plain, `--directional`,
and `--directional --directional-share`), draws each file alone (`snapshot out.glb --terms
baked`, the directional ones with `--directional`, i.e. the L1 band taken at the bump- or
normal-mapped shading normal) and reports:
  mre        mean relative error over the diffuse pixels (reference red below 50 W/(sr m^2), less
             one pixel around the rest, which drops visible lamps) against `lightbake reference`
             at --reference-spp (cached under build/bench/references/, as
             bench/lightmap_density.py caches its own);
  energy     the directional frames' sums over the plain frame's, minus 1 (same pixels), and
             each frame's sum over the reference's, minus 1 (bumped surfaces receive less light
             than the plain map draws: the decode's W term, docs/export.md);
  cpu        CPU seconds (user + sys of the children, os.wait4) of bake + export, plain and
             directional (the default encoding), and the directional one's increase;
  memory     the map's bytes in the file, 8 bits a channel: the plain map's, the directional
             one's (L0 + three RGB L1 maps: 4x) and with the share (the x map RGBA: 13/3 x).

--native measures the native bake instead (no export): per scene it bakes twice (plain, and
`--directional`: the caustic and soft maps' L1 bands), draws the directional bake with HQ
`render` (--hq-spp) and with `snapshot` (every term, the direct light at view time), each with
the bands and with `--no-directional` (the maps flat), and reports each one's mre against the
reference (as above), the bakes' CPU seconds and their increase, and the soft band's own work
from the manifest (its gather rays and wall seconds).
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
    for kind, extra in (("plain", []), ("directional", ["--directional"]),
                        ("share", ["--directional", "--directional-share"])):
        glb = os.path.join(work, f"{scene_name}_{kind}.glb")
        cpu, out = run([binary, "export", scene, bake, "-o", glb, "--contents", "all",
                        "--force"] + extra)
        image = os.path.join(work, f"{scene_name}_{kind}.exr")
        run([binary, "snapshot", glb, "--terms", "baked", "--size", size, "-o", image, "-q",
             "--force"] + extra[:1])
        row[f"cpu_export_{kind}"] = cpu
        against_reference = compare(binary, image, ref, mask)
        row[f"mre_{kind}"] = against_reference["mre"]
        row[f"energy_ref_{kind}"] = against_reference["sum_ratio_total"] - 1.0
        row[f"image_{kind}"] = image
        for line in out.splitlines():
            if line.startswith("lightmap"):
                dims = line.split()[1].split("x")
                row["texels"] = int(dims[0]) * int(dims[1])
    for kind in ("directional", "share"):
        row[f"energy_{kind}"] = compare(binary, row[f"image_{kind}"], row["image_plain"],
                                        mask)["sum_ratio_total"] - 1.0
    return row


def measure_native(binary, scene_name, work, size, spp, hq_spp):
    scene = os.path.join(ROOT, "scenes", scene_name + ".toml")
    ref, mask = reference(binary, scene, size, spp)
    row = {"scene": scene_name}
    for kind, extra in (("plain", []), ("directional", ["--directional"])):
        bake = os.path.join(work, f"{scene_name}_{kind}_bake")
        row[f"cpu_bake_{kind}"], _ = run([binary, "bake", scene, "-o", bake, "-q", "--force"]
                                         + extra)
    bake = os.path.join(work, f"{scene_name}_directional_bake")
    with open(os.path.join(bake, "manifest.json")) as f:
        soft = json.load(f)["soft_light"]
    row["band_rays"] = soft.get("band_rays", 0)
    row["band_seconds"] = soft.get("band_seconds", 0.0)
    for kind, extra in (("flat", ["--no-directional"]), ("band", [])):
        image = os.path.join(work, f"{scene_name}_hq_{kind}.exr")
        row[f"cpu_hq_{kind}"], _ = run([binary, "render", scene, bake, "--spp", str(hq_spp),
                                        "--size", size, "--seed", "7", "-o", image, "-q",
                                        "--force"] + extra)
        row[f"hq_{kind}"] = compare(binary, image, ref, mask)["mre"]
        image = os.path.join(work, f"{scene_name}_snapshot_{kind}.exr")
        run([binary, "snapshot", scene, bake, "--size", size, "-o", image, "-q", "--force"]
            + extra)
        row[f"snapshot_{kind}"] = compare(binary, image, ref, mask)["mre"]
    return row


def main_native(args, work):
    print("scene,hq_mre_flat,hq_mre_band,hq_ratio,snapshot_mre_flat,snapshot_mre_band,"
          "snapshot_ratio,cpu_bake_plain_s,cpu_bake_directional_s,cpu_bake_increase,"
          "soft_band_rays,soft_band_wall_s,cpu_hq_flat_s,cpu_hq_band_s")
    for name in args.scenes.split(","):
        r = measure_native(args.binary, name, work, args.size, args.reference_spp, args.hq_spp)
        print(f"{name},{r['hq_flat']:.4f},{r['hq_band']:.4f},{r['hq_band'] / r['hq_flat']:.3f},"
              f"{r['snapshot_flat']:.4f},{r['snapshot_band']:.4f},"
              f"{r['snapshot_band'] / r['snapshot_flat']:.3f},{r['cpu_bake_plain']:.2f},"
              f"{r['cpu_bake_directional']:.2f},"
              f"{r['cpu_bake_directional'] / r['cpu_bake_plain'] - 1:+.3f},{r['band_rays']},"
              f"{r['band_seconds']:.2f},{r['cpu_hq_flat']:.2f},{r['cpu_hq_band']:.2f}",
              flush=True)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--scenes", default="studded_wall,fig6_bump")
    parser.add_argument("--binary", default=os.path.join(ROOT, "build/app/lightbake"))
    parser.add_argument("--size", default="256x192")
    parser.add_argument("--reference-spp", type=int, default=4096)
    parser.add_argument("--work", default=None)
    parser.add_argument("--native", action="store_true",
                        help="the native bake drawn by render and snapshot (no export)")
    parser.add_argument("--hq-spp", type=int, default=64, help="--native: HQ render's spp")
    args = parser.parse_args()
    work = args.work or tempfile.mkdtemp(prefix="directional_")
    os.makedirs(work, exist_ok=True)
    if args.native:
        main_native(args, work)
        return
    print("scene,mre_plain,mre_directional,ratio,mre_share,ratio_share,energy_vs_plain,"
          "energy_share_vs_plain,energy_plain_vs_reference,energy_directional_vs_reference,"
          "energy_share_vs_reference,cpu_bake_s,cpu_export_plain_s,cpu_export_directional_s,"
          "cpu_export_share_s,cpu_increase,map_bytes_plain,map_bytes_directional,"
          "map_bytes_share")
    for name in args.scenes.split(","):
        r = measure(args.binary, name, work, args.size, args.reference_spp)
        plain = r["cpu_bake"] + r["cpu_export_plain"]
        directional = r["cpu_bake"] + r["cpu_export_directional"]
        texels = r.get("texels", 0)
        print(f"{name},{r['mre_plain']:.4f},{r['mre_directional']:.4f},"
              f"{r['mre_directional'] / r['mre_plain']:.3f},{r['mre_share']:.4f},"
              f"{r['mre_share'] / r['mre_plain']:.3f},{r['energy_directional']:+.5f},"
              f"{r['energy_share']:+.5f},{r['energy_ref_plain']:+.5f},"
              f"{r['energy_ref_directional']:+.5f},{r['energy_ref_share']:+.5f},"
              f"{r['cpu_bake']:.2f},{r['cpu_export_plain']:.2f},{r['cpu_export_directional']:.2f},"
              f"{r['cpu_export_share']:.2f},{directional / plain - 1:+.3f},{3 * texels},"
              f"{12 * texels},{13 * texels}", flush=True)


if __name__ == "__main__":
    main()
