#!/usr/bin/python3
"""Mean baked radiance on either side of a plane x = X, as an engine draws it from an export.

    lightmap_sides.py OUT.glb OUT.lightmap.exr MESH X GAP   ->  {"lit": ..., "dark": ...}

Points are spread over MESH's triangles in proportion to their area (seeded, 2000 per m^2),
each looked up in the lightmap with bilinear filtering at its TEXCOORD_1, clamped to the edge
(what a GPU does with the export's sampler); "lit" is the mean over points with x < X - GAP,
"dark" over x > X + GAP, in W/(sr m^2) (E/pi, the red channel). The EXR is read through
OpenImageIO's Python module, the .glb with the standard library.
"""

import json
import struct
import sys

import numpy as np
import OpenImageIO as oiio  # Debian's python3-openimageio (scripts/setup.sh)


def read_glb(path):
    data = open(path, "rb").read()
    magic, _, _ = struct.unpack_from("<III", data, 0)
    if magic != 0x46546C67:
        sys.exit(f"{path}: not a .glb")
    offset, gltf, binary = 12, None, None
    while offset < len(data):
        length, kind = struct.unpack_from("<II", data, offset)
        chunk = data[offset + 8: offset + 8 + length]
        if kind == 0x4E4F534A:
            gltf = json.loads(chunk)
        elif kind == 0x004E4942:
            binary = chunk
        offset += 8 + length
    return gltf, binary


def accessor(gltf, binary, index):
    a = gltf["accessors"][index]
    view = gltf["bufferViews"][a["bufferView"]]
    components = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4}[a["type"]]
    dtype = {5126: np.float32, 5125: np.uint32, 5123: np.uint16}[a["componentType"]]
    start = view.get("byteOffset", 0) + a.get("byteOffset", 0)
    count = a["count"] * components
    stride = view.get("byteStride", 0)
    if stride and stride != components * np.dtype(dtype).itemsize:
        sys.exit("interleaved accessors are not read here")
    return np.frombuffer(binary, dtype, count, start).reshape(a["count"], components)


def read_image(path):
    """The image's pixels, top row first (as glTF reads images), float64."""
    image = oiio.ImageBuf(path)
    if image.has_error:
        sys.exit(f"{path}: {image.geterror()}")
    return np.asarray(image.get_pixels(oiio.FLOAT), dtype=np.float64)


def bilinear(image, uv):
    height, width = image.shape[:2]
    x = uv[:, 0] * width - 0.5
    y = uv[:, 1] * height - 0.5  # glTF: v = 0 is the image's top row
    x0, y0 = np.floor(x).astype(int), np.floor(y).astype(int)
    fx, fy = x - x0, y - y0
    def at(i, j):
        return image[np.clip(j, 0, height - 1), np.clip(i, 0, width - 1), 0]
    return ((1 - fx) * (1 - fy) * at(x0, y0) + fx * (1 - fy) * at(x0 + 1, y0) +
            (1 - fx) * fy * at(x0, y0 + 1) + fx * fy * at(x0 + 1, y0 + 1))


def main():
    glb, exr, mesh_name, plane_x, gap = sys.argv[1:6]
    plane_x, gap = float(plane_x), float(gap)
    gltf, binary = read_glb(glb)
    image = read_image(exr)
    node = next(n for n in gltf["nodes"] if n.get("name") == mesh_name and "mesh" in n)
    primitive = gltf["meshes"][node["mesh"]]["primitives"][0]
    positions = accessor(gltf, binary, primitive["attributes"]["POSITION"]).astype(np.float64)
    uvs = accessor(gltf, binary, primitive["attributes"]["TEXCOORD_1"]).astype(np.float64)
    triangles = accessor(gltf, binary, primitive["indices"]).reshape(-1, 3)
    rng = np.random.default_rng(1)
    sums = {"lit": [0.0, 0], "dark": [0.0, 0]}
    for tri in triangles:
        p, t = positions[tri], uvs[tri]
        area = 0.5 * np.linalg.norm(np.cross(p[1] - p[0], p[2] - p[0]))
        n = max(1, int(round(area * 2000)))
        r1, r2 = rng.random(n), rng.random(n)
        s = np.sqrt(r1)
        b = np.stack([1 - s, s * (1 - r2), s * r2], axis=1)
        x = b @ p[:, 0]
        values = bilinear(image, b @ t)
        for side, keep in (("lit", x < plane_x - gap), ("dark", x > plane_x + gap)):
            sums[side][0] += float(values[keep].sum())
            sums[side][1] += int(keep.sum())
    print(json.dumps({side: total / max(1, count) for side, (total, count) in sums.items()}))


if __name__ == "__main__":
    main()
