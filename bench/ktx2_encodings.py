#!/usr/bin/python3
"""Bytes and error of an export's 8-bit lightmap encodings against its float EXR.

    ktx2_encodings.py OUT.glb [BASISU]   ->  one JSON line

Reads the .glb's lightmap PNG (srgb8-scaled or rgbm8, as its extras say), its KTX2 when it has
one (export --ktx2) and the half-float EXR beside it (the extras' "hdr"), and reports for the
PNG and for each KTX2 level: the mean relative error per texel (sum over RGB of |decoded -
EXR| over the EXR's sum) over the texels whose largest channel is above 1% of the map's peak,
and the energy (sum of decoded over sum of the EXR, minus 1) over the same texels. KTX2 levels
are decoded by `basisu -unpack` transcoded to BC7 (as three.js takes UASTC on desktop GPUs and
SwiftShader) and to ASTC (phones; UASTC's lossless transcode) and compared with the EXR's box means at that level (level k's texel covers its
2^k x 2^k texels of level 0, each level the mean of the one above, as an engine's chain is).
"""

import glob
import json
import os
import subprocess
import sys
import tempfile

import numpy as np
import OpenImageIO as oiio  # Debian's python3-openimageio (scripts/setup.sh)

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from lightmap_sides import read_glb  # noqa: E402


def image_bytes(gltf, binary, index):
    view = gltf["bufferViews"][gltf["images"][index]["bufferView"]]
    start = view.get("byteOffset", 0)
    return binary[start: start + view["byteLength"]]


def read_pixels(path):
    """Stored values in [0, 1], alpha left unassociated (RGBM's alpha is not coverage)."""
    config = oiio.ImageSpec()
    config.attribute("oiio:UnassociatedAlpha", 1)
    image = oiio.ImageBuf(path, 0, 0, config)
    if image.has_error:
        sys.exit(f"{path}: {image.geterror()}")
    return np.asarray(image.get_pixels(oiio.FLOAT), dtype=np.float64)


def decode(pixels, encoding, scale):
    if encoding == "rgbm8":
        return pixels[..., :3] * pixels[..., 3:4] * scale
    c = pixels[..., :3]
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4) * scale


def box_level(image, level):
    """Level `level` of the chain each of whose levels is the area mean of the one above."""
    for _ in range(level):
        height, width = image.shape[:2]
        to_h, to_w = max(1, height // 2), max(1, width // 2)
        image = resample(resample(image, width, to_w, 1), height, to_h, 0)
    return image


def resample(image, source, target, axis):
    ratio = source / target
    weights = np.zeros((target, source))
    for i in range(target):
        begin, end = i * ratio, (i + 1) * ratio
        for k in range(int(np.floor(begin)), min(source, int(np.ceil(end)))):
            weights[i, k] = (min(end, k + 1) - max(begin, k)) / ratio
    return np.moveaxis(np.tensordot(weights, np.moveaxis(image, axis, 0), axes=1), 0, axis)


def error(decoded, reference, mask):
    d, r = decoded[mask], reference[mask]
    relative = np.abs(d - r).sum(axis=1) / np.maximum(r.sum(axis=1), 1e-30)
    return {"mre": float(relative.mean()), "energy": float(d.sum() / r.sum() - 1.0),
            "texels": int(mask.sum())}


def main():
    glb = sys.argv[1]
    basisu = sys.argv[2] if len(sys.argv) > 2 else os.environ.get("LIGHTBAKE_BASISU", "basisu")
    gltf, binary = read_glb(glb)
    extras = gltf["materials"][0]["extras"]["lightbake_lightmap"]
    encoding, scale = extras["encoding"], extras["scale"]
    exr = read_pixels(os.path.join(os.path.dirname(glb), extras["hdr"]))[..., :3]
    texture = next(m["extensions"]["MOZ_lightmap"]["index"] for m in gltf["materials"]
                   if "MOZ_lightmap" in m.get("extensions", {}))
    texture = gltf["textures"][texture]
    out = {"file": glb, "encoding": encoding, "glb_bytes": os.path.getsize(glb),
           "map": [exr.shape[1], exr.shape[0]]}
    with tempfile.TemporaryDirectory() as scratch:
        png_path = os.path.join(scratch, "lightmap.png")
        png = image_bytes(gltf, binary, texture["source"])
        open(png_path, "wb").write(png)
        decoded = decode(read_pixels(png_path), encoding, scale)
        mask = exr.max(axis=2) > 0.01 * exr.max()
        out["png"] = {"bytes": len(png), **error(decoded, exr, mask)}
        basis = texture.get("extensions", {}).get("KHR_texture_basisu")
        if basis:
            ktx2 = image_bytes(gltf, binary, basis["source"])
            ktx2_path = os.path.join(scratch, "lightmap.ktx2")
            open(ktx2_path, "wb").write(ktx2)
            subprocess.run([basisu, "-unpack", "-no_ktx", ktx2_path], cwd=scratch, check=True,
                           capture_output=True)
            out["ktx2"] = {"bytes": len(ktx2)}
            for target in ("BC7", "ASTC"):
                levels = []
                for level in range(64):
                    found = glob.glob(os.path.join(scratch,
                                                   f"*_rgba_{target}_RGBA_{level}_*.png"))
                    if not found:
                        break
                    reference = box_level(exr, level)
                    levels.append(error(decode(read_pixels(found[0]), encoding, scale),
                                        reference, reference.max(axis=2) > 0.01 * exr.max()))
                out["ktx2"][target] = levels
    print(json.dumps(out))


if __name__ == "__main__":
    main()
