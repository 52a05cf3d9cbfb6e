#!/usr/bin/python3
"""A `lightbake reference` image averaged over independent renders, with its own noise measured.

    /usr/bin/python3 bench/converged_reference.py SCENE --renders 1000:4096,2001:8192,2002:8192

Each render SEED:SPP (SPP samples a pixel, fewer if --time-limit stops it: its report's count
is used) is cached under build/bench/references/, and their mean weighted by samples,
R = sum n_i X_i / N (N = sum n_i), is written beside them. Its noise comes from the last two
renders A, B: per pixel (variance sigma^2 / n for n samples) (A - B)^2 has expectation
sigma^2 (1/n_A + 1/n_B) and R - T (T the truth) variance sigma^2 / N, so over the compared
pixels, with c = 1 / sqrt(N (1/n_A + 1/n_B)) (1/2 for two equal halves),

    reference MRE     ~ c mean |A - B| / (|R| + eps)          (exact for Gaussian noise)
    reference relMSE  ~ c^2 mean (A - B)^2 / (R^2 + eps^2)    (unbiased)

with eps as `lightbake compare` (1% of R's mean). An image X's error against R is X's own
error and R's noise added in quadrature (independent), so X's relMSE against the truth is its
relMSE against R less the reference's (`rel_rms_less_noise` is the square root of that).
"""

import argparse
import json
import os
import sys

import numpy as np
import OpenImageIO as oiio  # Debian's python3-openimageio (scripts/setup.sh)

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
EPSILON_FRACTION = 0.01  # as `lightbake compare`


def read(path):
    image = oiio.ImageBuf(path)
    if image.has_error:
        sys.exit(f"{path}: {image.geterror()}")
    return image.get_pixels(oiio.FLOAT)[:, :, :3].astype(np.float64)


def write(path, pixels):
    spec = oiio.ImageSpec(pixels.shape[1], pixels.shape[0], pixels.shape[2], oiio.FLOAT)
    out = oiio.ImageBuf(spec)
    out.set_pixels(oiio.ROI(), pixels.astype(np.float32))
    if not out.write(path):
        sys.exit(f"{path}: {out.geterror()}")


def mask_pixels(mask_path, shape):
    if mask_path is None:
        return np.ones(shape[:2], dtype=bool)
    return read(mask_path)[:, :, 0] > 0.5


def noise(renders, mean, mask):
    """The mean image's own MRE and relMSE over `mask`, from its last two renders."""
    (a, n_a), (b, n_b) = renders[-2], renders[-1]
    total = sum(n for _, n in renders)
    c = 1.0 / np.sqrt(total * (1.0 / n_a + 1.0 / n_b))
    diff, r = (a - b)[mask], mean[mask]
    eps = EPSILON_FRACTION * abs(r.mean())
    return {"mre": float(c * np.mean(np.abs(diff) / (np.abs(r) + eps))),
            "relmse": float(c * c * np.mean(diff ** 2 / (r ** 2 + eps ** 2))), "spp": total}


def against(image_path, reference_path, mask_path, reference_noise):
    """MRE and relMSE of an image against the mean reference, and relMSE less its noise."""
    x, r = read(image_path), read(reference_path)
    mask = mask_pixels(mask_path, r.shape)
    x, r = x[mask], r[mask]
    eps = EPSILON_FRACTION * abs(r.mean())
    relmse = float(np.mean((x - r) ** 2 / (r ** 2 + eps ** 2)))
    return {"mre": float(np.mean(np.abs(x - r) / (np.abs(r) + eps))), "relmse": relmse,
            "rel_rms_less_noise": float(np.sqrt(max(relmse - reference_noise["relmse"], 0.0)))}


def samples_of(path, requested):
    """The samples a pixel a cached render holds: its report's count, else what was asked."""
    report = path[:-4] + ".json"
    if os.path.exists(report):
        with open(report) as f:
            return int(json.load(f)["samples_per_pixel"])
    return requested


def converged_reference(run, binary, scene, size, renders, refs, extra=()):
    """Renders (or reuses) each (seed, spp) and writes their mean; returns the mean's path and,
    with two or more renders, a function of a mask path (None: every pixel) giving its noise.
    Seed 1000's render keeps the name the benches used for their single reference."""
    stem = os.path.splitext(os.path.basename(scene))[0]
    images = []
    for seed, spp in renders:
        name = f"{stem}_{size}_reference_{spp}spp" + ("" if seed == 1000 else f"_seed{seed}")
        path = os.path.join(refs, name + ".exr")
        if not os.path.exists(path):
            print(f"reference seed {seed} ({spp} spp) ...", file=sys.stderr, flush=True)
            run([binary, "reference", scene, "--spp", str(spp), "--size", size, "--seed",
                 str(seed), "-o", path, "-q"] + list(extra))
        images.append((read(path), samples_of(path, spp)))
    tag = "_".join(f"{seed}-{n}" for (seed, _), (_, n) in zip(renders, images))
    mean_path = os.path.join(refs, f"{stem}_{size}_reference_mean_{tag}.exr")
    mean = sum(n * image for image, n in images) / sum(n for _, n in images)
    if not os.path.exists(mean_path):
        write(mean_path, mean)
    if len(images) < 2:
        return mean_path, None
    return mean_path, lambda mask: noise(images, mean, mask_pixels(mask, mean.shape))


def parse_renders(text):
    """SEED:SPP,... -> [(seed, spp)]."""
    return [tuple(int(x) for x in item.split(":")) for item in text.split(",")]


def main():
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    from lightmap_density import run  # noqa: E402
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("scene")
    parser.add_argument("--binary", default=os.path.join(ROOT, "build/app/lightbake"))
    parser.add_argument("--renders", default="1000:4096,2001:8192,2002:8192",
                        help="SEED:SPP,... (the last two measure the noise)")
    parser.add_argument("--size", default="256x256")
    parser.add_argument("--mask", default=None)
    args = parser.parse_args()
    refs = os.path.join(ROOT, "build/bench/references")
    os.makedirs(refs, exist_ok=True)
    path, noise_of = converged_reference(run, args.binary, args.scene, args.size,
                                         parse_renders(args.renders), refs)
    print(json.dumps({"reference": path, "noise": noise_of(args.mask) if noise_of else None}))


if __name__ == "__main__":
    main()
