#!/usr/bin/python3
"""Writes seam_floor.gltf beside this script: a 3 x 2 m floor, one mesh of 6 x 4 quads at
y = 0, whose lightmap UVs (TEXCOORD_1) come in three islands, as an artist's second UV map
would: x < -0.5 m; x > -0.5 m, z < 0; x > -0.5 m, z > 0. lightbake keeps sound islands as
charts of their own (docs/export.md, "The artist's lightmap UVs"), so the floor has coplanar
seams within one mesh along x = -0.5 and along z = 0 (x > -0.5). Vertices on an island's
border are split (each island its own copy), as glTF needs for per-vertex UVs."""
import base64
import json
import os
import struct

QUAD = 0.5
NX, NZ = 6, 4  # quads along x (from -1.5) and z (from -1)
UV_PER_METRE = 0.25
ISLAND_OFFSET = {0: (0.0, 0.0), 1: (0.3, 0.0), 2: (0.3, 0.3)}  # no overlap in [0, 1]^2
ISLAND_ORIGIN = {0: (-1.5, -1.0), 1: (-0.5, -1.0), 2: (-0.5, 0.0)}


def island(i, k):  # the quad at column i (x), row k (z)
    x = -1.5 + (i + 0.5) * QUAD
    z = -1.0 + (k + 0.5) * QUAD
    return 0 if x < -0.5 else (1 if z < 0.0 else 2)


positions, normals, uvs, indices = [], [], [], []
vertex_of = {}


def vertex(i, k, isl):
    key = (i, k, isl)
    if key not in vertex_of:
        x, z = -1.5 + i * QUAD, -1.0 + k * QUAD
        ox, oz = ISLAND_ORIGIN[isl]
        du, dv = ISLAND_OFFSET[isl]
        vertex_of[key] = len(positions)
        positions.append((x, 0.0, z))
        normals.append((0.0, 1.0, 0.0))
        uvs.append((du + (x - ox) * UV_PER_METRE, dv + (z - oz) * UV_PER_METRE))
    return vertex_of[key]


for k in range(NZ):
    for i in range(NX):
        isl = island(i, k)
        a, b = vertex(i, k, isl), vertex(i, k + 1, isl)
        c, d = vertex(i + 1, k + 1, isl), vertex(i + 1, k, isl)
        indices += [a, b, c, a, c, d]  # counter-clockwise seen from +y

blob = b"".join(struct.pack("<3f", *p) for p in positions)
blob += b"".join(struct.pack("<3f", *n) for n in normals)
blob += b"".join(struct.pack("<2f", *t) for t in uvs)
blob += b"".join(struct.pack("<H", i) for i in indices)
blob += b"\0" * (-len(blob) % 4)
n = len(positions)
views = [(0, 12 * n), (12 * n, 12 * n), (24 * n, 8 * n), (32 * n, 2 * len(indices))]
gltf = {
    "asset": {"version": "2.0", "generator": "tests/data/web/make_seam_floor.py"},
    "scene": 0,
    "scenes": [{"nodes": [0]}],
    "nodes": [{"name": "floor", "mesh": 0}],
    "meshes": [{"name": "floor", "primitives": [{
        "attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_1": 2},
        "indices": 3, "material": 0}]}],
    "materials": [{"name": "floor", "pbrMetallicRoughness": {
        "baseColorFactor": [0.7, 0.7, 0.7, 1.0], "metallicFactor": 0.0}}],
    "buffers": [{"byteLength": len(blob), "uri": "data:application/octet-stream;base64,"
                 + base64.b64encode(blob).decode()}],
    "bufferViews": [{"buffer": 0, "byteOffset": o, "byteLength": l} for o, l in views],
    "accessors": [
        {"bufferView": 0, "componentType": 5126, "count": n, "type": "VEC3",
         "min": [min(p[j] for p in positions) for j in range(3)],
         "max": [max(p[j] for p in positions) for j in range(3)]},
        {"bufferView": 1, "componentType": 5126, "count": n, "type": "VEC3"},
        {"bufferView": 2, "componentType": 5126, "count": n, "type": "VEC2"},
        {"bufferView": 3, "componentType": 5123, "count": len(indices), "type": "SCALAR"}],
}
out = os.path.join(os.path.dirname(os.path.abspath(__file__)), "seam_floor.gltf")
with open(out, "w") as f:
    json.dump(gltf, f, indent=1)
    f.write("\n")
