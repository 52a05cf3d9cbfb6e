#!/usr/bin/python3
"""Lightmap atlas packing efficiency: ours (bake/illumination/atlas.h) against xatlas (PyPI
`xatlas`), same surfaces, same texel density, matched padding (bench only, not ctest).

    cmake --build build --target bench_atlas_stats
    /usr/bin/python3 bench/atlas_packing.py            # every bundled scene, ~1 minute

Installs numpy and xatlas by name into build/venv the first time and re-runs itself there.
Ours: `build/bench/bench_atlas_stats SCENE --padding P` builds the atlas with every diffuse,
non-emitting mesh included (automatic texel size, per-mesh texel sizes as the scene sets them)
and prints its JSON, meshes included. xatlas gets the same world-space meshes, each scaled by
(atlas texel / mesh texel) so one texels_per_unit = 1 / atlas texel gives every mesh its own
density, with bilinear = True and brute-force placement (its best packing).

Efficiency = used texel area / atlas area, used = the sum of the charts' UV triangle areas in
texels (the same formula on both sides; xatlas's own `utilization` counts padding texels).
Padding: ours P texels between chart rectangles, whose bilinear footprint reaches one node
beyond each side, leaves P - 2 free texels between footprints; xatlas dilates every footprint
by its padding Q, leaving 2Q. So ours 2 ~ xatlas 0 and ours 4 ~ xatlas 1 are matched pairs;
our default, 3, lies between them.
"""

import json
import os
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BUILD = os.path.join(ROOT, "build")
VENV = os.path.join(BUILD, "venv")
STATS = os.path.join(BUILD, "bench", "bench_atlas_stats")
PAIRS = [(2, 0), (4, 1)]  # (our padding, xatlas padding) with the same free texels


def ensure_venv():
    """Re-runs this script with build/venv's Python, installing numpy and xatlas there."""
    python = os.path.join(VENV, "bin", "python")
    if os.path.realpath(sys.prefix) == os.path.realpath(VENV):
        return
    if not os.path.exists(python):
        subprocess.run([sys.executable, "-m", "venv", VENV], check=True)
    check = subprocess.run([python, "-c", "import numpy, xatlas"], capture_output=True)
    if check.returncode != 0:
        subprocess.run([python, "-m", "pip", "install", "-q", "numpy", "xatlas"], check=True)
    os.execv(python, [python] + sys.argv)


def ours(scene, padding):
    out = subprocess.run([STATS, scene, "--padding", str(padding)], check=True,
                         capture_output=True, text=True).stdout
    return json.loads(out)


def xatlas_efficiency(stats, padding):
    import numpy as np
    import xatlas

    atlas = xatlas.Atlas()
    texel = stats["texel_size_m"]
    for mesh in stats["meshes"]:
        scale = texel / mesh["texel_size_m"]
        positions = np.array(mesh["positions"], dtype=np.float32).reshape(-1, 3) * scale
        triangles = np.array(mesh["triangles"], dtype=np.uint32).reshape(-1, 3)
        atlas.add_mesh(positions, triangles)
    pack = xatlas.PackOptions()
    pack.padding = padding
    pack.bilinear = True
    pack.bruteForce = True
    pack.texels_per_unit = 1.0 / texel
    atlas.generate(pack_options=pack)
    width, height = atlas.width, atlas.height
    used = 0.0
    for i in range(atlas.mesh_count):
        _, indices, uvs = atlas[i]
        a, b, c = (uvs[indices[:, k]].astype(np.float64) for k in range(3))
        e1, e2 = b - a, c - a
        used += 0.5 * np.abs(e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]).sum()
    used *= width * height
    return {"width": width, "height": height, "charts": atlas.chart_count,
            "efficiency": used / (width * height), "used_texels": used}


def cell(result):
    return f"{result['width']}x{result['height']}, {result['charts']} charts, " \
           f"**{100 * result['efficiency']:.1f}%**"


def main():
    ensure_venv()
    if not os.path.exists(STATS):
        sys.exit(f"{STATS} is missing: cmake --build build --target bench_atlas_stats")
    scenes = sorted(f for f in os.listdir(os.path.join(ROOT, "scenes")) if f.endswith(".toml"))
    header = ["scene", "texel (mm)", "triangles", "ours default (padding 3)"]
    for p, q in PAIRS:
        header += [f"ours, padding {p}", f"xatlas, padding {q}"]
    print("| " + " | ".join(header) + " |")
    print("|" + "---|" * len(header))
    ratios = {pair: [] for pair in PAIRS}
    for name in scenes:
        scene = os.path.join(ROOT, "scenes", name)
        default = ours(scene, 3)
        row = [name[:-5], f"{1000 * default['texel_size_m']:.1f}",
               str(sum(len(m["triangles"]) // 3 for m in default["meshes"])), cell(default)]
        for p, q in PAIRS:
            mine = ours(scene, p)
            theirs = xatlas_efficiency(mine, q)
            # Same surfaces at the same density: the used areas must agree (xatlas's LSCM
            # charts may stretch a little), or the comparison is not like for like.
            assert abs(theirs["used_texels"] / mine["used_texels"] - 1) < 0.02, (name, mine,
                                                                                   theirs)
            ratios[(p, q)].append(mine["efficiency"] / theirs["efficiency"])
            row += [cell(mine), cell(theirs)]
        print("| " + " | ".join(row) + " |", flush=True)
    for (p, q), r in ratios.items():
        print(f"\nours (padding {p}) / xatlas (padding {q}) efficiency: min {min(r):.3f}, "
              f"median {sorted(r)[len(r) // 2]:.3f}, max {max(r):.3f}")


if __name__ == "__main__":
    main()
