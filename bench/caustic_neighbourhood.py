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

Window references and the split (`--split`):

    /usr/bin/python3 bench/caustic_neighbourhood.py scenes/cornell_glass.toml --split \
        --reference FB_S1.exr C_S1.exr --reference2 FB_S2.exr C_S2.exr \
        [--reference-direct D_S1.exr ... --reference-direct2 D_S2.exr ...] [--hq-spp 16,256]

Each reference may be several `lightbake reference --window` images of one seed (0 outside
their windows, read from each image's .json report; they are added); --reference2 the same
windows with another seed. Their mean is the reference, their half difference its noise. Only
neighbourhood pixels inside the windows are compared (the count left out is printed). Two
default bakes (seeds 1, 2), each rendered by HQ (--hq-spp, render seed = bake seed) and the
raster snapshot, against it (--mask M.npy: the same neighbourhood for every bake option; else
made from the first bake and saved in the output folder): per pixel class (caustic_split.py's
geometry: floor seen directly, the ball (all 4 x 4 sub-rays hit it), its rim (some do, or next
to one that does), other; and `light_rim`, within 3 pixels of an emitter pixel, and `caustic`,
the rest: the neighbourhood's dilation brings the ceiling light's edge in), the
MRE as `lightbake compare --mask` (eps = 1% of the neighbourhood's reference mean, the same for
every class), the sum ratio, and RMS errors split into the image's noise (its two seeds), the
reference's noise and the bias left (in quadrature). With --reference-direct(2) (`lightbake
reference --terms direct` windows) also by term: the direct term (`render/snapshot --terms
direct`) against the reference's, and the rest (caustic map + radiosity) against the
reference's rest, both relative to the whole reference + eps.
"""

import argparse
import json
import math
import os
import resource
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


def read_windows(paths):
    """The sum of window images (0 outside each window) and the mask of the pixels they cover
    (a whole image when its report names no window)."""
    total, covered = None, None
    for path in paths:
        image = read_exr(path)
        report = os.path.splitext(path)[0] + ".json"
        window = json.load(open(report)).get("window") if os.path.exists(report) else None
        mine = np.zeros(image.shape[:2], dtype=bool)
        if window:
            mine[window["y0"]:window["y1"], window["x0"]:window["x1"]] = True
        else:
            mine[:] = True
        total = image if total is None else total + image
        covered = mine if covered is None else covered | mine
    return total, covered


def neighbourhood(args, out, base):
    """Pixels whose HQ map term exceeds the threshold, emitters left out, dilated 5 x 5."""
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
    return mask


def light_rim(args, out, base, reach=3):
    """Pixels within `reach` pixels of an emitter pixel (HQ direct >= 5): the neighbourhood's
    dilation brings a ceiling light's edge in, whose error is 16-sample coverage noise, not
    the caustic's."""
    direct = os.path.join(out, "direct.exr")
    if not os.path.exists(direct):
        run("render", args.scene, base, "--size", args.size, "--terms", "direct", "--spp", "16",
            "-o", direct, "-q", "--force")
    emitter = read_exr(direct).max(axis=2) >= 5.0
    rim = emitter.copy()
    for dy in range(-reach, reach + 1):
        for dx in range(-reach, reach + 1):
            rim |= np.roll(np.roll(emitter, dy, 0), dx, 1)
    return rim


def ratio(a, b):
    """Sum ratio, None where the reference holds nothing (a term absent in a class)."""
    return round(float(a.sum() / b.sum()), 4) if b.sum() > 0 else None


def error_split(pair, ref_pair, mask, eps):
    """Errors of pair[0] against the mean of ref_pair over mask, relative to ref + eps; RMS
    split into pair's noise, the reference mean's noise and the bias left."""
    ref = (ref_pair[0] + ref_pair[1]) / 2
    den = ref[mask] + eps
    rel = (pair[0][mask] - ref[mask]) / den
    noise = (pair[0][mask] - pair[1][mask]) / den / math.sqrt(2)
    noise_ref = (ref_pair[0][mask] - ref_pair[1][mask]) / 2 / den
    rms = lambda a: float(np.sqrt((a * a).mean()))  # noqa: E731
    total, n, nr = rms(rel), rms(noise), rms(noise_ref)
    return {"mre": round(float(np.abs(rel).mean()), 4), "rms": round(total, 4),
            "noise_rms": round(n, 4), "ref_noise_rms": round(nr, 4),
            "bias_rms": round(math.sqrt(max(0.0, total ** 2 - n ** 2 - nr ** 2)), 4),
            "signed": round(float(rel.mean()), 4),
            "sum_ratio": ratio(pair[0][mask], ref[mask])}


def pixel_classes(w, h):
    """caustic_split.py's camera and ball: floor seen directly, ball, rim, other."""
    from caustic_split import BALL_CENTRE, BALL_RADIUS, EYE, camera_rays, floor_mask
    d = camera_rays(w, h, 4)
    oc = EYE - BALL_CENTRE
    b = (d * oc).sum(-1)
    hits = b * b - (oc @ oc - BALL_RADIUS ** 2) > 0
    ball, near = hits.all(-1), np.zeros((h, w), dtype=bool)
    for dy in (-1, 0, 1):
        for dx in (-1, 0, 1):
            near |= np.roll(np.roll(hits.any(-1), dy, 0), dx, 1)
    floor = floor_mask(w, h)
    rim = near & ~ball & ~floor
    return {"floor": floor, "ball": ball, "rim": rim, "other": ~(floor | ball | rim)}


def split_main(args):
    """--split: the neighbourhood's error by pixel class, term and noise/bias (docstring)."""
    name = os.path.splitext(os.path.basename(args.scene))[0]
    out = os.path.join(args.out, name + "_split")
    os.makedirs(out, exist_ok=True)
    o = lambda f: os.path.join(out, f)  # noqa: E731
    w, h = (int(v) for v in args.size.split("x"))
    r1, covered = read_windows(args.reference)
    r2, covered2 = read_windows(args.reference2)
    assert (covered == covered2).all(), "--reference and --reference2: not the same windows"
    images, cpu = {}, []
    for s in (1, 2):
        bake = o(f"bake_s{s}")
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        run("bake", args.scene, "-o", bake, "--seed", str(s), "-q", *args.bake_options)
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        cpu.append(after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime)
        if s == 1:
            if args.mask and os.path.exists(args.mask):
                mask = np.load(args.mask)
            else:
                mask = neighbourhood(args, out, bake)
                np.save(args.mask or o("mask.npy"), mask)
        for spp in args.hq_spp:
            for terms in ("all", "direct"):
                f = o(f"hq{spp}_{terms}_s{s}.exr")
                run("render", args.scene, bake, "--size", args.size, "--spp", str(spp), "--seed",
                    str(s), "-o", f, "-q", "--force", *(["--terms", terms] if terms != "all" else []))
                images.setdefault((f"hq{spp}", terms), []).append(read_exr(f))
        for terms in ("all", "direct"):
            f = o(f"raster_{terms}_s{s}.exr")
            run("snapshot", args.scene, bake, "--size", args.size, "--terms", terms, "-o", f, "-q",
                "--force")
            images.setdefault(("raster", terms), []).append(read_exr(f))
    inside = mask & covered
    ref = (r1 + r2) / 2
    eps = 0.01 * ref[inside].mean()
    print(json.dumps({"scene": name, "neighbourhood_pixels": int(mask.sum()),
                      "outside_windows": int((mask & ~covered).sum()), "epsilon": round(eps, 5),
                      "bake_options": args.bake_options,
                      "bake_cpu_seconds": [round(c, 2) for c in cpu]}))
    classes = {"all": inside, **{k: inside & c for k, c in pixel_classes(w, h).items()}}
    rim = light_rim(args, out, o("bake_s1"))
    classes.update({"light_rim": inside & rim, "caustic": inside & ~rim})
    direct = None
    if args.reference_direct:
        d1, _ = read_windows(args.reference_direct)
        d2, _ = read_windows(args.reference_direct2)
        direct = (d1, d2)
    for mode in [f"hq{spp}" for spp in args.hq_spp] + ["raster"]:
        pair = images[(mode, "all")]
        for cls, m in classes.items():
            if not m.any():
                continue
            row = {"mode": mode, "class": cls, "pixels": int(m.sum()),
                   **error_split(pair, (r1, r2), m, eps)}
            if direct:
                dp = images[(mode, "direct")]
                rest = [a - b for a, b in zip(pair, dp)]
                rref = (r1 - direct[0], r2 - direct[1])
                # Both against the whole reference + eps, so they add up to the total error.
                for term, p, rp in (("direct", dp, direct), ("rest", rest, rref)):
                    den = ref[m] + eps
                    rel = (p[0][m] - (rp[0][m] + rp[1][m]) / 2) / den
                    noise = (p[0][m] - p[1][m]) / den / math.sqrt(2)
                    row[term] = {"mre": round(float(np.abs(rel).mean()), 4),
                                 "signed": round(float(rel.mean()), 4),
                                 "noise_rms": round(float(np.sqrt((noise ** 2).mean())), 4),
                                 "sum_ratio": ratio(p[0][m], (rp[0][m] + rp[1][m]) / 2)}
            print(json.dumps(row))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("scene")
    parser.add_argument("--size", default="256x256")
    parser.add_argument("--split", action="store_true", help="window references: class/term/"
                        "noise split of the default bake (see the docstring)")
    parser.add_argument("--reference2", nargs="+", help="--split: the other seed's windows")
    parser.add_argument("--reference-direct", nargs="+", help="--split: --terms direct windows")
    parser.add_argument("--reference-direct2", nargs="+")
    parser.add_argument("--mask", help="--split: .npy neighbourhood to reuse (else made from the "
                        "first bake and saved there or in the output folder)")
    parser.add_argument("--hq-spp", default="16,256", help="--split: HQ samples per pixel")
    parser.add_argument("--bake-options", nargs=argparse.REMAINDER, default=[],
                        help="--split: the rest of the line goes to both bakes")
    parser.add_argument("--reference", nargs="+",
                        help="reference EXR (else rendered and cached); --split: its windows")
    parser.add_argument("--ref-spp", type=int, default=1024)
    parser.add_argument("--spp", type=int, default=16, help="HQ samples per pixel")
    parser.add_argument("--threshold", type=float, default=0.05)
    parser.add_argument("--out", default=os.path.join(ROOT, "build/bench/caustic"))
    args = parser.parse_args()
    if args.split:
        args.hq_spp = [int(v) for v in args.hq_spp.split(",")]
        return split_main(args)
    args.reference = args.reference[0] if args.reference else None
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
    mask = neighbourhood(args, out, os.path.join(out, "filtered"))
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
