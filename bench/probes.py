#!/usr/bin/python3
"""Light probes (issue 38): a ball in the Cornell box drawn probe-lit (marked dynamic, by
`snapshot`) against HQ mode's render of the same ball baked as static geometry.

    /usr/bin/python3 bench/probes.py                      # radii 0.1 and 0.2 m
    /usr/bin/python3 bench/probes.py --radii 0.15 --spp 16 --passes 64

Per radius (a white ball centred at (0.3, 0, 0.4), the box's camera) it bakes the box with the
ball static and with it dynamic, renders the static one in HQ mode (`render`, final gather on
from 256 samples a pixel) and snapshots the dynamic one, and reports, over the ball's pixels
(its projected disc less 2 pixels at the rim):
  hq, probes   mean radiance (luminance, W/(sr m^2)): the ball's albedo times its mean incident
               light over the visible half, E/pi;
  ratio        probes / hq - 1 (the issue's target: within 5%);
  exported, exported_ratio
               the same of the dynamic scene's export (`export`, then `snapshot out.glb`): the
               ball lit by blends of the file's grid at its vertices, as an engine copying
               docs/light-probes.md draws it (tests/web/probe_grid.js);
  cpu_*        CPU seconds (user + sys of the children) of the dynamic scene's bake, its
               snapshot (which bakes the probes it reads) and the export's snapshot (which
               blends the file's grid at every vertex).
CSV on stdout.
"""

import argparse
import math
import os
import sys
import tempfile

import OpenImageIO as oiio

from lightmap_density import run  # CPU seconds of the child, its stdout

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CENTRE = (0.3, 0.0, 0.4)
CAMERA = (0.0, 0.0, 3.9)  # scenes/cornell_box.toml: looking at the origin, square image
FOV_DEG = 39.3077


def scene_text(radius, dynamic):
    box = os.path.join(ROOT, "scenes", "cornell_box.toml")
    return (f'include = "{box}"\n[[objects]]\nname = "ball"\nshape = "sphere"\n'
            f"radius = {radius}\ntranslate = [{CENTRE[0]}, {CENTRE[1]}, {CENTRE[2]}]\n"
            f'material = "white"\ndynamic = {"true" if dynamic else "false"}\n')


def ball_mean(path, radius, size):
    """Mean luminance over the ball's disc (pinhole projection, 2-pixel margin)."""
    image = oiio.ImageBuf(path)
    pixels = image.get_pixels(oiio.FLOAT)
    focal = (size / 2) / math.tan(math.radians(FOV_DEG) / 2)
    depth = CAMERA[2] - CENTRE[2]
    cx = size / 2 + focal * (CENTRE[0] - CAMERA[0]) / depth
    cy = size / 2 - focal * (CENTRE[1] - CAMERA[1]) / depth
    r = focal * radius / math.sqrt(depth * depth - radius * radius) - 2.0
    total, count = 0.0, 0
    for y in range(size):
        for x in range(size):
            if (x + 0.5 - cx) ** 2 + (y + 0.5 - cy) ** 2 > r * r:
                continue
            p = pixels[y][x]
            total += 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2]
            count += 1
    return total / count


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--binary", default=os.path.join(ROOT, "build/app/lightbake"))
    parser.add_argument("--radii", type=float, nargs="+", default=[0.1, 0.2])
    parser.add_argument("--size", type=int, default=192)
    parser.add_argument("--spp", type=int, default=16)
    parser.add_argument("--passes", type=int, default=16)
    args = parser.parse_args()
    size = f"{args.size}x{args.size}"
    print("radius_m,hq,probes,ratio,exported,exported_ratio,cpu_bake_dynamic,"
          "cpu_snapshot_dynamic,cpu_snapshot_exported")
    with tempfile.TemporaryDirectory() as work:
        for radius in args.radii:
            paths = {}
            for kind in ("static", "dynamic"):
                scene = os.path.join(work, f"{kind}.toml")
                with open(scene, "w") as f:
                    f.write(scene_text(radius, kind == "dynamic"))
                bake = os.path.join(work, kind + "_bake")
                cpu_bake, _ = run([args.binary, "bake", scene, "-o", bake, "-q", "--force"])
                paths[kind] = (scene, bake, cpu_bake)
            scene, bake, _ = paths["static"]
            hq = os.path.join(work, "hq.exr")
            print(f"r = {radius}: HQ render ...", file=sys.stderr)
            run([args.binary, "render", scene, bake, "--size", size, "--spp", str(args.spp),
                 "--passes", str(args.passes), "-o", hq, "-q"])
            scene, bake, cpu_bake = paths["dynamic"]
            snap = os.path.join(work, "probes.exr")
            cpu_snapshot, _ = run([args.binary, "snapshot", scene, bake, "--size", size, "-o",
                                   snap, "-q"])
            glb, exported = os.path.join(work, "dynamic.glb"), os.path.join(work, "exported.exr")
            run([args.binary, "export", scene, bake, "-o", glb, "-q", "--force"])
            cpu_exported, _ = run([args.binary, "snapshot", glb, "--size", size, "-o",
                                   exported, "-q"])
            hq_mean = ball_mean(hq, radius, args.size)
            probe_mean = ball_mean(snap, radius, args.size)
            exported_mean = ball_mean(exported, radius, args.size)
            print(f"{radius},{hq_mean:.5f},{probe_mean:.5f},{probe_mean / hq_mean - 1:+.4f},"
                  f"{exported_mean:.5f},{exported_mean / hq_mean - 1:+.4f},"
                  f"{cpu_bake:.2f},{cpu_snapshot:.2f},{cpu_exported:.2f}", flush=True)


if __name__ == "__main__":
    main()
