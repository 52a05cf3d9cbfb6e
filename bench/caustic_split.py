#!/usr/bin/python3
"""Caustic map error split into bias and noise (issue 11), on the floor pixels of
cornell_glass's caustic neighbourhood that do not see the glass ball (bench only, not ctest).

    /usr/bin/python3 bench/caustic_split.py REF_SEED1.exr REF_SEED2.exr [--size 256x256] \\
        [--out build/bench/caustic_split] [--mask M.npy] [-- BAKE OPTIONS...]

The neighbourhood: floor pixels whose map term exceeds --threshold, dilated 5 x 5 (saved as
mask.npy; pass --mask to compare bakes over the same pixels). REF_SEED*.exr: two `lightbake reference scenes/cornell_glass.toml --seed 1|2` images of the
same spp; their mean is the reference, half their difference its noise. Two bakes (seeds 1, 2)
with BAKE OPTIONS give the map term (`render --terms map`, a lookup on the floor) and the
raster map term (`snapshot --terms caustic`); the reference's caustic light is its image less
the bake's HQ direct + radiosity terms (64 spp, two render seeds for their noise). Per-channel
relative error |a - b| / (ref + eps), eps = 1% of the masked reference mean (as
`lightbake compare`); RMS errors split in quadrature: bias^2 = total^2 - noise_map^2 -
noise_ref^2. Block errors: the same over 4 x 4 pixel block means (noise averages out).
Prints one JSON line per mode and the bakes' CPU seconds.
"""

import argparse
import json
import math
import os
import resource
import subprocess
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from caustic_neighbourhood import LIGHTBAKE, read_exr  # noqa: E402

SCENE = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))),
                     "scenes/cornell_glass.toml")
# scenes/cornell_box.toml's camera "mitsuba" and cornell_glass.toml's ball (metres).
EYE, FOV_DEG = np.array([0.0, 0.0, 3.9]), 39.3077
BALL_CENTRE, BALL_RADIUS = np.array([-0.5, -0.75, 0.5]), 0.25
FLOOR_Y = -1.0


def run(*args):
    subprocess.run([LIGHTBAKE, *args], check=True, capture_output=True, text=True)


def camera_rays(w, h, sub):
    """Unit view directions, (h, w, sub*sub, 3), top row first (camera looks down -z)."""
    t = math.tan(math.radians(FOV_DEG) / 2)
    offsets = (np.arange(sub) + 0.5) / sub
    ys, xs = np.mgrid[0:h, 0:w]
    ox, oy = np.meshgrid(offsets, offsets)
    px = (2 * (xs[..., None] + ox.ravel()) / w - 1) * t * w / h
    py = (1 - 2 * (ys[..., None] + oy.ravel()) / h) * t
    d = np.stack([px, py, -np.ones_like(px)], axis=-1)
    return d / np.linalg.norm(d, axis=-1, keepdims=True)


def floor_mask(w, h):
    """Pixels all of whose 4 x 4 sub-rays miss the ball and land on the floor, minus a
    one-pixel ring around the ball's silhouette."""
    d = camera_rays(w, h, 4)
    oc = EYE - BALL_CENTRE
    b = (d * oc).sum(-1)
    sees_ball = (b * b - (oc @ oc - BALL_RADIUS ** 2) > 0).any(-1)
    t = (FLOOR_Y - EYE[1]) / np.where(d[..., 1] < 0, d[..., 1], -1e-9)
    p = EYE + t[..., None] * d
    on_floor = ((d[..., 1] < 0) & (np.abs(p[..., 0]) < 1) & (np.abs(p[..., 2]) < 1)).all(-1)
    ring = sees_ball.copy()
    for dy in (-1, 0, 1):
        for dx in (-1, 0, 1):
            ring |= np.roll(np.roll(sees_ball, dy, 0), dx, 1)
    return on_floor & ~ring


def blocks(a, k=4):
    h, w = a.shape[0] // k * k, a.shape[1] // k * k
    return a[:h, :w].reshape(h // k, k, w // k, k, *a.shape[2:]).mean(axis=(1, 3))


def split(maps, ref_pair, nonmap_pair, mask, k=1):
    """RMS and mean relative errors of maps[0] against the reference's caustic, and the noise
    terms, all relative to the reference image + eps, over mask (block means if k > 1)."""
    r1, r2 = ref_pair
    ref = (r1 + r2) / 2
    nonmap = (nonmap_pair[0] + nonmap_pair[1]) / 2
    caustic_ref = ref - nonmap
    m1, m2 = maps
    if k > 1:
        fm = blocks(mask.astype(float), k) == 1.0
        ref, caustic_ref, m1, m2, r1, r2 = (blocks(a, k) for a in (ref, caustic_ref, m1, m2, r1, r2))
        n1, n2 = blocks(nonmap_pair[0], k), blocks(nonmap_pair[1], k)
        mask = fm
    else:
        n1, n2 = nonmap_pair
    eps = 0.01 * ref[mask].mean()
    den = ref[mask] + eps
    rel = (m1[mask] - caustic_ref[mask]) / den
    noise_map = (m1[mask] - m2[mask]) / den / math.sqrt(2)       # one bake's noise
    noise_ref = ((r1[mask] - r2[mask]) / 2 - (n1[mask] - n2[mask]) / 2) / den
    rms = lambda a: float(np.sqrt((a * a).mean()))  # noqa: E731
    total, nm, nr = rms(rel), rms(noise_map), rms(noise_ref)
    bias = math.sqrt(max(0.0, total ** 2 - nm ** 2 - nr ** 2))
    return {"values": int(rel.size), "mre": round(float(np.abs(rel).mean()), 4),
            "rms": round(total, 4), "noise_map_rms": round(nm, 4), "noise_ref_rms": round(nr, 4),
            "bias_rms": round(bias, 4), "mean_signed": round(float(rel.mean()), 4),
            "map_sum_ratio": round(float(m1[mask].sum() / caustic_ref[mask].sum()), 4)}


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("ref1")
    parser.add_argument("ref2")
    parser.add_argument("--size", default="256x256")
    parser.add_argument("--threshold", type=float, default=0.05)
    parser.add_argument("--mask", help=".npy neighbourhood to reuse (else made from the map term "
                        "of the first bake and saved there or in the output folder)")
    parser.add_argument("--out", default=os.path.join(os.path.dirname(LIGHTBAKE),
                                                      "../bench/caustic_split"))
    argv = sys.argv[1:]
    cut = argv.index("--") if "--" in argv else len(argv)
    args, options = parser.parse_args(argv[:cut]), argv[cut + 1:]
    os.makedirs(args.out, exist_ok=True)
    w, h = (int(v) for v in args.size.split("x"))
    o = lambda name: os.path.join(args.out, name)  # noqa: E731
    cpu = []
    for s in (1, 2):
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        run("bake", SCENE, "-o", o(f"bake_s{s}"), "--seed", str(s), "-q", *options)
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        cpu.append(after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime)
        run("render", SCENE, o(f"bake_s{s}"), "--terms", "map", "--spp", "16", "--size",
            args.size, "-o", o(f"map_s{s}.exr"), "-q", "--force")
        run("snapshot", SCENE, o(f"bake_s{s}"), "--terms", "caustic", "--size", args.size,
            "-o", o(f"raster_s{s}.exr"), "-q", "--force")
        run("render", SCENE, o("bake_s1"), "--terms", "direct,radiosity", "--spp", "64",
            "--seed", str(s), "--size", args.size, "-o", o(f"nonmap_s{s}.exr"), "-q", "--force")
    ref_pair = (read_exr(args.ref1), read_exr(args.ref2))
    nonmap_pair = (read_exr(o("nonmap_s1.exr")), read_exr(o("nonmap_s2.exr")))
    hq = (read_exr(o("map_s1.exr")), read_exr(o("map_s2.exr")))
    raster = (read_exr(o("raster_s1.exr")), read_exr(o("raster_s2.exr")))
    if args.mask and os.path.exists(args.mask):
        mask = np.load(args.mask)
    else:
        core = hq[0].mean(axis=2) > args.threshold
        near = np.zeros_like(core)
        for dy in range(-2, 3):
            for dx in range(-2, 3):
                near |= np.roll(np.roll(core, dy, 0), dx, 1)
        mask = near & floor_mask(w, h)
        np.save(args.mask or o("mask.npy"), mask)
    print(json.dumps({"options": options, "pixels": int(mask.sum()),
                      "bake_cpu_seconds": [round(c, 2) for c in cpu]}))
    for name, maps in (("hq_map", hq), ("raster_map", raster)):
        for k in (1, 4):
            print(json.dumps({"mode": name, "block": k,
                              **split(maps, ref_pair, nonmap_pair, mask, k)}))


if __name__ == "__main__":
    main()
