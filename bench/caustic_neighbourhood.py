#!/usr/bin/python3
"""Caustic neighbourhood error (issue 11): a scene's default bake with and without the caustic
density filter, rendered by HQ mode and the raster viewer, against `lightbake reference`, over
the pixels near the caustic (bench only, not ctest).

    /usr/bin/python3 bench/caustic_neighbourhood.py scenes/cornell_glass.toml --size 256x256 \\
        --reference REF.exr [--ref-spp 2048] [--out build/bench/caustic]

The neighbourhood: pixels whose HQ map term (`render --terms map`, 64 spp, of the filtered
bake) exceeds --threshold W/(sr m^2) and that are not emitters (HQ direct < 5), dilated 5 x 5;
written as mask.png and used with `lightbake compare --mask`. Without --reference, the
reference is rendered with `lightbake reference --spp REF_SPP` and cached in the output folder.
Needs python3-numpy (Debian) and oiiotool (openimageio-tools), both set up by scripts/setup.sh.
"""

import argparse
import json
import os
import subprocess
import tempfile

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
# LIGHTBAKE=PATH runs another build's binary (before/after a change).
LIGHTBAKE = os.environ.get("LIGHTBAKE", os.path.join(ROOT, "build/app/lightbake"))


def run(*args):
    return subprocess.run([LIGHTBAKE, *args], check=True, capture_output=True, text=True).stdout


def read_exr(path):
    """RGB of an EXR, top row first, through oiiotool's FITS writer (float32, big-endian, the
    pixels are the file's last w*h*12 bytes, bottom row first)."""
    fd, tmp = tempfile.mkstemp(suffix=".fits")
    os.close(fd)
    subprocess.run(["oiiotool", path, "--ch", "R,G,B", "-d", "float", "-o", tmp], check=True)
    raw = open(tmp, "rb").read()
    os.remove(tmp)
    cards = [raw[k:k + 80].decode(errors="replace") for k in range(0, 2880, 80)]
    size = {c[:8].strip(): int(c[10:30]) for c in cards if c[:5] == "NAXIS" and c[5] in "23"}
    w, h = size["NAXIS2"], size["NAXIS3"]
    data = np.frombuffer(raw[len(raw) - w * h * 12:], dtype=">f4").reshape(h, w, 3)
    return data[::-1].astype(np.float64)


def write_mask(mask, path):
    h, w = mask.shape
    pgm = path[:-4] + ".pgm"
    with open(pgm, "wb") as f:
        f.write(b"P5\n%d %d\n255\n" % (w, h))
        f.write((mask * 255).astype(np.uint8).tobytes())
    subprocess.run(["oiiotool", pgm, "-o", path], check=True)
    os.remove(pgm)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("scene")
    parser.add_argument("--size", default="256x256")
    parser.add_argument("--reference", help="reference EXR (else rendered and cached)")
    parser.add_argument("--ref-spp", type=int, default=1024)
    parser.add_argument("--spp", type=int, default=16, help="HQ samples per pixel")
    parser.add_argument("--threshold", type=float, default=0.05)
    parser.add_argument("--out", default=os.path.join(ROOT, "build/bench/caustic"))
    args = parser.parse_args()
    name = os.path.splitext(os.path.basename(args.scene))[0]
    out = os.path.join(args.out, name)
    os.makedirs(out, exist_ok=True)
    reference = args.reference or os.path.join(out, f"ref_{args.size}_{args.ref_spp}spp.exr")
    if not os.path.exists(reference):
        run("reference", args.scene, "--spp", str(args.ref_spp), "--size", args.size, "-o",
            reference, "-q")
    bakes = {"filtered": [], "unfiltered": ["--no-caustic-filter"]}
    for kind, options in bakes.items():
        run("bake", args.scene, "-o", os.path.join(out, kind), "-q", *options)
    base = os.path.join(out, "filtered")
    run("render", args.scene, base, "--size", args.size, "--terms", "map", "--spp", "64", "-o",
        os.path.join(out, "map.exr"), "-q", "--force")
    run("render", args.scene, base, "--size", args.size, "--terms", "direct", "--spp", "16",
        "-o", os.path.join(out, "direct.exr"), "-q", "--force")
    core = (read_exr(os.path.join(out, "map.exr")).mean(axis=2) > args.threshold) & (
        read_exr(os.path.join(out, "direct.exr")).max(axis=2) < 5.0)
    mask = np.zeros_like(core)
    for dy in range(-2, 3):
        for dx in range(-2, 3):
            mask |= np.roll(np.roll(core, dy, 0), dx, 1)
    mask_path = os.path.join(out, "mask.png")
    write_mask(mask, mask_path)
    print(json.dumps({"scene": name, "size": args.size, "reference": reference,
                      "neighbourhood_pixels": int(mask.sum())}))
    for kind in bakes:
        bake = os.path.join(out, kind)
        hq = os.path.join(out, f"hq_{kind}.exr")
        raster = os.path.join(out, f"raster_{kind}.exr")
        run("render", args.scene, bake, "--size", args.size, "--spp", str(args.spp), "-o", hq,
            "-q", "--force")
        run("snapshot", args.scene, bake, "--size", args.size, "-o", raster, "-q", "--force")
        for mode, image in (("hq", hq), ("raster", raster)):
            metrics = json.loads(run("compare", image, reference, "--mask", mask_path))
            print(json.dumps({"bake": kind, "mode": mode, "mre": round(metrics["mre"], 4),
                              "relmse": round(metrics["relmse"], 4),
                              "sum_ratio": round(metrics["sum_ratio_total"], 4)}))


if __name__ == "__main__":
    main()
