#!/usr/bin/python3
"""Which alphas survive UASTC when a 4x4 block's alpha is constant (rgbm_blocks.h's table).

    uastc_alpha_survival.py MAP.exr BASISU   ->  a line per alpha, then the kept list

Takes 128 blocks of 4x4 texels at random from the map (those above 0.5% of its peak), each
normalised by its largest channel (a block of RGBM's colour), gives every block of one image
row the same alpha, for all 256 alphas, encodes the image as basisu's exporter does (UASTC
level 2, -linear -force_alpha), unpacks it to ASTC, BC7 and ETC2 (-unpack) and counts, per
alpha, the blocks whose alpha came back changed and by how much. Kept: alphas no ASTC or ETC2
block changed in more than 1% of blocks, and BC7 changed in at most 30%, by one code at most.
"""

import glob
import os
import subprocess
import sys
import tempfile

import numpy as np
import OpenImageIO as oiio  # Debian's python3-openimageio (scripts/setup.sh)

BLOCKS = 128


def read(path):
    config = oiio.ImageSpec()
    config.attribute("oiio:UnassociatedAlpha", 1)  # RGBM's alpha is not coverage
    image = oiio.ImageBuf(path, 0, 0, config)
    if image.has_error:
        sys.exit(f"{path}: {image.geterror()}")
    return np.asarray(image.get_pixels(oiio.FLOAT), dtype=np.float64)


def write(path, pixels):
    spec = oiio.ImageSpec(pixels.shape[1], pixels.shape[0], 4, oiio.UINT8)
    spec.attribute("oiio:UnassociatedAlpha", 1)
    out = oiio.ImageOutput.create(path)
    out.open(path, spec)
    out.write_image(np.ascontiguousarray(pixels))
    out.close()


def main():
    source, basisu = sys.argv[1], sys.argv[2]
    radiance = read(source)[..., :3]
    height, width = radiance.shape[0] // 4 * 4, radiance.shape[1] // 4 * 4
    blocks = radiance[:height, :width].reshape(height // 4, 4, width // 4, 4, 3)
    blocks = blocks.transpose(0, 2, 1, 3, 4).reshape(-1, 4, 4, 3)
    blocks = blocks[blocks.max(axis=(1, 2, 3)) > 0.005 * radiance.max()]
    random = np.random.default_rng(3)
    image = np.zeros((256 * 4, BLOCKS * 4, 4), np.uint8)
    for alpha in range(256):
        for j, block in enumerate(blocks[random.integers(0, len(blocks), BLOCKS)]):
            image[alpha * 4: alpha * 4 + 4, j * 4: j * 4 + 4, :3] = np.rint(
                block / block.max() * 255)
            image[alpha * 4: alpha * 4 + 4, j * 4: j * 4 + 4, 3] = alpha
    changed, worst = {}, {}
    with tempfile.TemporaryDirectory() as scratch:
        write(os.path.join(scratch, "alphas.png"), image)
        subprocess.run([basisu, "-ktx2", "-uastc", "-uastc_level", "2", "-linear", "-force_alpha",
                        "-file", "alphas.png", "-output_file", "alphas.ktx2"],
                       cwd=scratch, check=True, capture_output=True)
        subprocess.run([basisu, "-unpack", "-no_ktx", "alphas.ktx2"], cwd=scratch, check=True,
                       capture_output=True)
        for target in ("ASTC", "BC7", "ETC2"):
            path = glob.glob(os.path.join(scratch, f"*_rgba_{target}_RGBA_0_0000.png"))[0]
            alpha = np.rint(read(path)[..., 3] * 255).astype(int)
            off = np.abs(alpha - image[..., 3].astype(int)).reshape(256, 4, BLOCKS, 4)
            off = off.max(axis=(1, 3))
            changed[target], worst[target] = (off > 0).mean(axis=1), off.max(axis=1)
    kept = []
    for alpha in range(256):
        print(alpha, " ".join(f"{t} {changed[t][alpha]:.2f} (max {worst[t][alpha]})"
                              for t in changed))
        if (changed["ASTC"][alpha] <= 0.01 and changed["ETC2"][alpha] <= 0.01
                and changed["BC7"][alpha] <= 0.30 and worst["BC7"][alpha] <= 1):
            kept.append(alpha)
    print("kept:", kept)


if __name__ == "__main__":
    main()
