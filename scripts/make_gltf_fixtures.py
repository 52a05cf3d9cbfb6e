#!/usr/bin/env python3
"""Writes the glTF test fixtures under tests/data/gltf/ (python3 standard library only).

Run from anywhere:  python3 scripts/make_gltf_fixtures.py
The outputs are committed; tests/io/test_gltf.cpp checks the values chosen here, so change
both together. Every number a test asserts is written out below, not computed by a library.
"""

import base64
import json
import math
import os
import struct
import zlib

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
OUT = os.path.join(ROOT, "tests", "data", "gltf")
BAD = os.path.join(OUT, "bad")

FLOAT, UBYTE, USHORT, UINT = 5126, 5121, 5123, 5125
FORMATS = {FLOAT: "f", UBYTE: "B", USHORT: "H", UINT: "I"}
COMPONENTS = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4}


def png_bytes(width, height, rows):
    """A minimal 8-bit RGB PNG (RGBA with 4-tuples); rows is a list of lists of (r, g, b[, a])."""
    raw = b"".join(b"\x00" + bytes(c for px in row for c in px) for row in rows)
    colour_type = 6 if len(rows[0][0]) == 4 else 2

    def chunk(kind, data):
        return (struct.pack(">I", len(data)) + kind + data +
                struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF))

    header = struct.pack(">IIBBBBB", width, height, 8, colour_type, 0, 0, 0)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) +
            chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))


# The 2x2 base colour texture: top row white, mid grey (sRGB 188 ~ linear 0.5029);
# bottom row black, red.
CHECKER = png_bytes(2, 2, [[(255, 255, 255), (188, 188, 188)], [(0, 0, 0), (255, 0, 0)]])
# A flat tangent-space normal map (0, 0, 1) encoded as (128, 128, 255).
FLAT_NORMAL = png_bytes(1, 1, [[(128, 128, 255)]])


class Gltf:
    """Accumulates one binary buffer with its buffer views and accessors."""

    def __init__(self):
        self.blob = bytearray()
        self.doc = {"asset": {"version": "2.0", "generator": "make_gltf_fixtures.py"},
                    "bufferViews": [], "accessors": []}

    def view(self, data, target=None):
        while len(self.blob) % 4:
            self.blob.append(0)
        view = {"buffer": 0, "byteOffset": len(self.blob), "byteLength": len(data)}
        if target:
            view["target"] = target
        self.blob += data
        self.doc["bufferViews"].append(view)
        return len(self.doc["bufferViews"]) - 1

    def accessor(self, values, kind, component=FLOAT, target=34962):
        n = COMPONENTS[kind]
        flat = [c for v in values for c in (v if isinstance(v, (list, tuple)) else [v])]
        data = struct.pack("<%d%s" % (len(flat), FORMATS[component]), *flat)
        acc = {"bufferView": self.view(data, target), "componentType": component,
               "count": len(flat) // n, "type": kind}
        if kind != "SCALAR" or component == FLOAT:
            acc["min"] = [min(flat[i::n]) for i in range(n)]
            acc["max"] = [max(flat[i::n]) for i in range(n)]
        self.doc["accessors"].append(acc)
        return len(self.doc["accessors"]) - 1

    def indices(self, values, component=USHORT):
        return self.accessor(values, "SCALAR", component, target=34963)

    def write_gltf(self, path, bin_name):
        doc = dict(self.doc)
        doc["buffers"] = [{"uri": bin_name, "byteLength": len(self.blob)}]
        write(path, json.dumps(doc, indent=1).encode())
        write(os.path.join(os.path.dirname(path), bin_name), bytes(self.blob))

    def embedded_doc(self):
        doc = dict(self.doc)
        doc["buffers"] = [{"uri": "data:application/octet-stream;base64," +
                           base64.b64encode(bytes(self.blob)).decode(),
                           "byteLength": len(self.blob)}]
        return doc

    def glb_bytes(self):
        doc = dict(self.doc)
        blob = bytes(self.blob) + b"\x00" * (-len(self.blob) % 4)
        doc["buffers"] = [{"byteLength": len(self.blob)}]
        text = json.dumps(doc).encode()
        text += b" " * (-len(text) % 4)
        total = 12 + 8 + len(text) + 8 + len(blob)
        return (struct.pack("<4sII", b"glTF", 2, total) +
                struct.pack("<I4s", len(text), b"JSON") + text +
                struct.pack("<I4s", len(blob), b"BIN\x00") + blob)


def write(path, data):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "wb") as f:
        f.write(data)


# ---------------------------------------------------------------------------------------------
# A unit quad in z = 0 facing +z, base colour texture, TEXCOORD_1 as lightmap UVs.

QUAD_POSITIONS = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)]
QUAD_UV0 = [(0, 1), (1, 1), (1, 0), (0, 0)]  # glTF v runs down the image
QUAD_UV1 = [(0.125, 0.875), (0.375, 0.875), (0.375, 0.625), (0.125, 0.625)]


def textured_quad(image_in_buffer):
    g = Gltf()
    pos = g.accessor(QUAD_POSITIONS, "VEC3")
    nrm = g.accessor([(0, 0, 1)] * 4, "VEC3")
    uv0 = g.accessor(QUAD_UV0, "VEC2")
    uv1 = g.accessor(QUAD_UV1, "VEC2")
    idx = g.indices([0, 1, 2, 0, 2, 3])
    g.doc["meshes"] = [{"name": "quad", "primitives": [{
        "attributes": {"POSITION": pos, "NORMAL": nrm, "TEXCOORD_0": uv0, "TEXCOORD_1": uv1},
        "indices": idx, "material": 0}]}]
    g.doc["materials"] = [{"name": "checker", "pbrMetallicRoughness": {
        "baseColorFactor": [1, 1, 1, 1], "baseColorTexture": {"index": 0},
        "metallicFactor": 0, "roughnessFactor": 1}}]
    g.doc["textures"] = [{"source": 0}]
    if image_in_buffer:
        g.doc["images"] = [{"bufferView": g.view(CHECKER), "mimeType": "image/png"}]
    else:
        g.doc["images"] = [{"uri": "checker.png"}]
    g.doc["nodes"] = [{"name": "floor", "mesh": 0}]
    g.doc["scenes"] = [{"nodes": [0]}]
    g.doc["scene"] = 0
    return g


# ---------------------------------------------------------------------------------------------
# Alpha: a green leaf card cut by a 4 x 4 alpha checker (MASK, half its area), a pane of alpha
# 0.3 (BLEND), both over a grey floor, under a sun straight down.

LEAF_ALPHA = png_bytes(4, 4, [[(60, 140, 40, 255 * ((r + c) % 2)) for c in range(4)]
                              for r in range(4)])


def alpha_leaf():
    g = Gltf()

    def quad(name, corners, material):
        pos = g.accessor(corners, "VEC3")
        nrm = g.accessor([(0, 1, 0)] * 4, "VEC3")
        uv0 = g.accessor(QUAD_UV0, "VEC2")
        idx = g.indices([0, 1, 2, 0, 2, 3])
        return {"name": name, "primitives": [{
            "attributes": {"POSITION": pos, "NORMAL": nrm, "TEXCOORD_0": uv0},
            "indices": idx, "material": material}]}

    def square(x, z, y, half):
        return [(x - half, y, z + half), (x + half, y, z + half), (x + half, y, z - half),
                (x - half, y, z - half)]

    g.doc["meshes"] = [quad("floor", square(0.5, 0, 0, 2), 0),
                       quad("leaf", square(0, 0, 0.5, 0.5), 1),
                       quad("pane", square(1.5, 0, 0.5, 0.5), 2)]
    g.doc["materials"] = [
        {"name": "floor", "pbrMetallicRoughness": {
            "baseColorFactor": [0.5, 0.5, 0.5, 1], "metallicFactor": 0, "roughnessFactor": 1}},
        {"name": "leaf", "alphaMode": "MASK", "alphaCutoff": 0.5, "doubleSided": True,
         "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "metallicFactor": 0,
                                  "roughnessFactor": 1}},
        {"name": "pane", "alphaMode": "BLEND", "pbrMetallicRoughness": {
            "baseColorFactor": [0.8, 0.8, 0.9, 0.3], "metallicFactor": 0,
            "roughnessFactor": 1}}]
    # Blender's Closest interpolation, and extensions other than Repeat: the sampler round trip.
    g.doc["textures"] = [{"source": 0, "sampler": 0}]
    g.doc["samplers"] = [{"magFilter": 9728, "wrapS": 33071, "wrapT": 33648}]
    g.doc["images"] = [{"bufferView": g.view(LEAF_ALPHA), "mimeType": "image/png"}]
    g.doc["extensionsUsed"] = ["KHR_lights_punctual"]
    g.doc["extensions"] = {"KHR_lights_punctual": {"lights": [
        {"name": "sun", "type": "directional", "intensity": 3.0 * 683}]}}
    sun_down = [-0.7071068, 0, 0, 0.7071068]  # -z turned to -y
    g.doc["nodes"] = [{"name": "floor", "mesh": 0}, {"name": "leaf", "mesh": 1},
                      {"name": "pane", "mesh": 2},
                      {"name": "sun", "rotation": sun_down,
                       "extensions": {"KHR_lights_punctual": {"light": 0}}},
                      {"name": "camera", "camera": 0, "translation": [0.5, 2.5, 2.5],
                       "rotation": [-0.3826834, 0, 0, 0.9238795]}]
    g.doc["cameras"] = [{"type": "perspective", "perspective": {
        "yfov": 0.9, "znear": 0.05, "zfar": 20, "aspectRatio": 1.3333}}]
    g.doc["scenes"] = [{"nodes": [0, 1, 2, 3, 4]}]
    g.doc["scene"] = 0
    return g


# ---------------------------------------------------------------------------------------------
# One slanted triangle used by two nodes: TRS with non-uniform scale, and a mirroring child of a
# matrix parent; plus a perspective camera.

def instanced():
    g = Gltf()
    s = 1 / math.sqrt(3)
    pos = g.accessor([(1, 0, 0), (0, 1, 0), (0, 0, 1)], "VEC3")
    nrm = g.accessor([(s, s, s)] * 3, "VEC3")
    idx = g.indices([0, 1, 2], UBYTE)
    g.doc["meshes"] = [{"name": "tri", "primitives": [{
        "attributes": {"POSITION": pos, "NORMAL": nrm}, "indices": idx, "material": 0}]}]
    g.doc["materials"] = [{"name": "grey", "pbrMetallicRoughness": {
        "baseColorFactor": [0.5, 0.5, 0.5, 1], "metallicFactor": 0}}]
    h = math.sqrt(0.5)
    g.doc["nodes"] = [
        {"name": "A", "mesh": 0, "translation": [1, 2, 3], "rotation": [0, 0, h, h],
         "scale": [2, 1, 1], "extras": {"lightbake_texel_size": 0.05,
                                              "lightbake_caustic_origins": "area"}},
        {"name": "parent", "matrix": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, -5, 1],
         "children": [2]},
        {"name": "B", "mesh": 0, "scale": [-1, 1, 1]},
        {"name": "eye", "camera": 0, "translation": [0, 1, 5], "rotation": [0, h, 0, h]},
    ]
    g.doc["cameras"] = [{"type": "perspective", "name": "cam",
                         "perspective": {"yfov": 0.7, "znear": 0.1, "aspectRatio": 1.5}}]
    g.doc["scenes"] = [{"nodes": [0, 1, 3]}]
    return g


# ---------------------------------------------------------------------------------------------
# One triangle per material: diffuse white, mirror, glossy, glass, emitter, normal-mapped.

MATERIALS = [
    {"name": "white", "pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 1],
                                               "metallicFactor": 0, "roughnessFactor": 0.5}},
    {"name": "mirror", "pbrMetallicRoughness": {"baseColorFactor": [0.9, 0.9, 0.9, 1],
                                                "metallicFactor": 1, "roughnessFactor": 0}},
    {"name": "brushed", "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.6, 0.4, 1],
                                                 "metallicFactor": 1, "roughnessFactor": 0.4}},
    {"name": "glass", "pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 1],
                                               "metallicFactor": 0, "roughnessFactor": 0},
     "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1},
                    "KHR_materials_ior": {"ior": 1.45}}},
    {"name": "lamp", "emissiveFactor": [1, 0.5, 0.25],
     "pbrMetallicRoughness": {"baseColorFactor": [0, 0, 0, 1], "metallicFactor": 0},
     "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 10}}},
    {"name": "bumpy", "pbrMetallicRoughness": {"baseColorFactor": [0.7, 0.7, 0.7, 1],
                                               "metallicFactor": 0},
     "normalTexture": {"index": 0, "scale": 0.5}},
    {"name": "dim_lamp", "emissiveFactor": [0.5, 0, 0],
     "pbrMetallicRoughness": {"metallicFactor": 0}},
]


def materials():
    g = Gltf()
    primitives = []
    for m in range(len(MATERIALS) + 1):
        x = 2.0 * m
        pos = g.accessor([(x, 0, 0), (x + 1, 0, 0), (x, 1, 0)], "VEC3")
        nrm = g.accessor([(0, 0, 1)] * 3, "VEC3")
        attributes = {"POSITION": pos, "NORMAL": nrm}
        if m == 5:    # normal mapped, UVs aligned: tangent +x, w = +1
            attributes["TEXCOORD_0"] = g.accessor([(0, 1), (1, 1), (0, 0)], "VEC2")
        if m == 7:    # same material, u mirrored: tangent -x, w = -1
            attributes["TEXCOORD_0"] = g.accessor([(1, 1), (0, 1), (1, 0)], "VEC2")
        primitives.append({"attributes": attributes, "material": 5 if m == 7 else m})
    g.doc["meshes"] = [{"name": "samples", "primitives": primitives}]
    g.doc["materials"] = MATERIALS
    g.doc["textures"] = [{"source": 0}]
    g.doc["images"] = [{"bufferView": g.view(FLAT_NORMAL), "mimeType": "image/png"}]
    g.doc["nodes"] = [{"name": "samples", "mesh": 0}]
    g.doc["scenes"] = [{"nodes": [0]}]
    g.doc["extensionsUsed"] = ["KHR_materials_transmission", "KHR_materials_ior",
                               "KHR_materials_emissive_strength"]
    return g


# ---------------------------------------------------------------------------------------------
# Accessor variants: a sparse POSITION, a strided interleaved view, normalised unsigned-short
# UVs, a triangle strip, a fan, and no material (the shared default).

def accessor_variants():
    g = Gltf()
    base = g.accessor([(0, 0, 0), (1, 0, 0), (0, 1, 0)], "VEC3")
    sparse_indices = g.view(struct.pack("<H", 2) + b"\x00\x00")
    sparse_values = g.view(struct.pack("<3f", 0, 2, 0))
    g.doc["accessors"][base]["sparse"] = {
        "count": 1, "indices": {"bufferView": sparse_indices, "componentType": USHORT},
        "values": {"bufferView": sparse_values}}
    del g.doc["accessors"][base]["min"], g.doc["accessors"][base]["max"]
    # Interleaved position (3 floats) + UV (2 normalised ushorts, padded): 16-byte stride.
    strip = [((0, 0, 5), (0, 0)), ((1, 0, 5), (65535, 0)), ((0, 1, 5), (0, 65535)),
             ((1, 1, 5), (65535, 65535))]
    data = b"".join(struct.pack("<3f2H", *p, *uv) for p, uv in strip)
    view = g.view(data, 34962)
    g.doc["bufferViews"][view]["byteStride"] = 16
    g.doc["accessors"].append({"bufferView": view, "byteOffset": 0, "componentType": FLOAT,
                               "count": 4, "type": "VEC3", "min": [0, 0, 5], "max": [1, 1, 5]})
    strip_pos = len(g.doc["accessors"]) - 1
    g.doc["accessors"].append({"bufferView": view, "byteOffset": 12, "componentType": USHORT,
                               "normalized": True, "count": 4, "type": "VEC2"})
    strip_uv = len(g.doc["accessors"]) - 1
    fan_pos = g.accessor([(0, 0, 9), (1, 0, 9), (1, 1, 9), (0, 1, 9)], "VEC3")
    g.doc["meshes"] = [{"name": "variants", "primitives": [
        {"attributes": {"POSITION": base}},
        {"attributes": {"POSITION": strip_pos, "TEXCOORD_0": strip_uv}, "mode": 5},
        {"attributes": {"POSITION": fan_pos}, "mode": 6, "indices": g.indices([0, 1, 2, 3], UINT)},
    ]}]
    g.doc["nodes"] = [{"mesh": 0}]
    g.doc["scenes"] = [{"nodes": [0]}]
    return g


# ---------------------------------------------------------------------------------------------
# The paper's Figure 8 room as a Blender-like export (y up, metres): a closed 4 x 3 x 4 room seen
# from inside, a 1 x 1 m ceiling light of radiance 10 W/(sr m^2) (emissiveFactor 1 x strength
# 10), a diffuse block and a glass ball; every mesh has TEXCOORD_1 lightmap UVs.

def add(a, b, k=1.0):
    return tuple(x + k * y for x, y in zip(a, b))


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def unit(a):
    n = math.sqrt(sum(x * x for x in a))
    return tuple(x / n for x in a)


def quads_mesh(g, name, quads, material):
    """quads: (origin, edge_u, edge_v); the front faces along cross(edge_u, edge_v)."""
    pos, nrm, uv0, uv1, idx = [], [], [], [], []
    columns = max(1, math.ceil(math.sqrt(len(quads))))
    for k, (o, eu, ev) in enumerate(quads):
        n = unit(cross(eu, ev))
        base = len(pos)
        cu, cv = (k % columns) / columns, (k // columns) / columns
        for (u, v) in [(0, 0), (1, 0), (1, 1), (0, 1)]:
            pos.append(add(add(o, eu, u), ev, v))
            nrm.append(n)
            uv0.append((u, 1 - v))
            uv1.append((cu + (0.05 + 0.9 * u) / columns, cv + (0.05 + 0.9 * v) / columns))
        idx += [base, base + 1, base + 2, base, base + 2, base + 3]
    return {"name": name, "primitives": [{"attributes": {
        "POSITION": g.accessor(pos, "VEC3"), "NORMAL": g.accessor(nrm, "VEC3"),
        "TEXCOORD_0": g.accessor(uv0, "VEC2"), "TEXCOORD_1": g.accessor(uv1, "VEC2")},
        "indices": g.indices(idx), "material": material}]}


def box_quads(lo, hi, inward):
    (x0, y0, z0), (x1, y1, z1) = lo, hi
    dx, dy, dz = (x1 - x0, 0, 0), (0, y1 - y0, 0), (0, 0, z1 - z0)
    outward = [((x0, y0, z1), dx, dy), ((x1, y0, z0), (-dx[0], 0, 0), dy),  # +z, -z
               ((x1, y0, z1), (0, 0, -dz[2]), dy), ((x0, y0, z0), dz, dy),  # +x, -x
               ((x0, y1, z1), dx, (0, 0, -dz[2])), ((x0, y0, z0), dx, dz)]  # +y, -y
    if not inward:
        return outward
    return [(add(o, eu), tuple(-c for c in eu), ev) for o, eu, ev in outward]


def sphere_mesh(g, name, centre, radius, rings, segments, material):
    pos, nrm, uv0, uv1, idx = [], [], [], [], []
    for r in range(rings + 1):
        theta = math.pi * r / rings
        for s_ in range(segments + 1):
            phi = 2 * math.pi * s_ / segments
            n = (math.sin(theta) * math.cos(phi), math.cos(theta), -math.sin(theta) * math.sin(phi))
            pos.append(add(centre, n, radius))
            nrm.append(n)
            uv0.append((s_ / segments, r / rings))
            uv1.append((0.02 + 0.96 * s_ / segments, 0.02 + 0.96 * r / rings))
    for r in range(rings):
        for s_ in range(segments):
            a, b = r * (segments + 1) + s_, (r + 1) * (segments + 1) + s_
            if r > 0:
                idx += [a, b, a + 1]
            if r < rings - 1:
                idx += [a + 1, b, b + 1]
    return {"name": name, "primitives": [{"attributes": {
        "POSITION": g.accessor(pos, "VEC3"), "NORMAL": g.accessor(nrm, "VEC3"),
        "TEXCOORD_0": g.accessor(uv0, "VEC2"), "TEXCOORD_1": g.accessor(uv1, "VEC2")},
        "indices": g.indices(idx), "material": material}]}


def room():
    g = Gltf()
    g.doc["materials"] = [
        {"name": "walls", "pbrMetallicRoughness": {"baseColorFactor": [0.75, 0.75, 0.75, 1],
                                                   "metallicFactor": 0, "roughnessFactor": 1}},
        {"name": "light", "emissiveFactor": [1, 1, 1],
         "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.8, 0.8, 1], "metallicFactor": 0},
         "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 10}}},
        {"name": "block", "pbrMetallicRoughness": {"baseColorFactor": [0.6, 0.5, 0.4, 1],
                                                   "metallicFactor": 0, "roughnessFactor": 1}},
        {"name": "glass", "pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 1],
                                                   "metallicFactor": 0, "roughnessFactor": 0},
         "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1},
                        "KHR_materials_ior": {"ior": 1.5}}},
    ]
    g.doc["meshes"] = [
        quads_mesh(g, "room", box_quads((0, 0, 0), (4, 3, 4), inward=True), 0),
        # Just below the ceiling, facing down: edges along x then z give a -y normal.
        quads_mesh(g, "light", [((1.5, 2.99, 1.5), (1, 0, 0), (0, 0, 1))], 1),
        quads_mesh(g, "block", box_quads((-0.4, 0, -0.4), (0.4, 1.2, 0.4), inward=False), 2),
        sphere_mesh(g, "ball", (0, 0, 0), 1.0, 16, 32, 3),
    ]
    h = math.sin(math.radians(15))
    c = math.cos(math.radians(15))
    g.doc["nodes"] = [
        {"name": "room", "mesh": 0},
        {"name": "light", "mesh": 1},
        {"name": "block", "mesh": 2, "translation": [1.2, 0, 2.8], "rotation": [0, h, 0, c]},
        {"name": "ball", "mesh": 3, "translation": [2.8, 0.6, 1.4], "scale": [0.6, 0.6, 0.6]},
        {"name": "camera", "camera": 0, "translation": [2, 1.5, 3.95]},
    ]
    g.doc["cameras"] = [{"type": "perspective", "perspective": {"yfov": 1.2, "znear": 0.05}}]
    g.doc["scenes"] = [{"nodes": [0, 1, 2, 3, 4]}]
    g.doc["extensionsUsed"] = ["KHR_materials_emissive_strength", "KHR_materials_transmission",
                               "KHR_materials_ior"]
    return g


# ---------------------------------------------------------------------------------------------
# Bad input and unsupported features.

def single_triangle(indices=None):
    g = Gltf()
    pos = g.accessor([(0, 0, 0), (1, 0, 0), (0, 1, 0)], "VEC3")
    prim = {"attributes": {"POSITION": pos}}
    if indices is not None:
        prim["indices"] = g.indices(indices)
    g.doc["meshes"] = [{"name": "tri", "primitives": [prim]}]
    g.doc["nodes"] = [{"name": "tri", "mesh": 0}]
    g.doc["scenes"] = [{"nodes": [0]}]
    return g


def write_json(path, doc):
    write(path, json.dumps(doc, indent=1).encode())


def bad_inputs():
    write(os.path.join(BAD, "syntax_error.gltf"),
          b'{\n "asset": {"version": "2.0"},\n "meshes": [ {"name": "x",, } ]\n}\n')

    g = single_triangle()
    doc = g.embedded_doc()
    doc["buffers"] = [{"uri": "does_not_exist.bin", "byteLength": len(g.blob)}]
    write_json(os.path.join(BAD, "missing_bin.gltf"), doc)

    glb = textured_quad(image_in_buffer=True).glb_bytes()
    write(os.path.join(BAD, "truncated.glb"), glb[:len(glb) // 2])

    g = single_triangle()
    g.doc["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = 42
    write_json(os.path.join(BAD, "accessor_out_of_range.gltf"), g.embedded_doc())

    g = single_triangle(indices=[0, 1, 7])
    write_json(os.path.join(BAD, "index_out_of_range.gltf"), g.embedded_doc())

    g = single_triangle()
    g.doc["accessors"][0]["count"] = 100  # 1200 bytes wanted from a 36-byte view
    write_json(os.path.join(BAD, "bufferview_overrun.gltf"), g.embedded_doc())

    g = single_triangle()
    g.doc["accessors"][0]["byteOffset"] = 4  # three VEC3 from byte 4 end at 40 > 36
    write_json(os.path.join(BAD, "accessor_offset_overrun.gltf"), g.embedded_doc())

    g = textured_quad(image_in_buffer=False)
    g.doc["images"] = [{"uri": "not_an_image.png"}]
    write_json(os.path.join(BAD, "bad_image.gltf"), g.embedded_doc())
    write(os.path.join(BAD, "not_an_image.png"), b"this file is not a PNG image\n")

    g = textured_quad(image_in_buffer=False)
    g.doc["images"] = [{"uri": "no_such_image.png"}]
    write_json(os.path.join(BAD, "missing_image.gltf"), g.embedded_doc())

    glb = bytearray(textured_quad(image_in_buffer=True).glb_bytes())
    glb[12:16] = struct.pack("<I", 100000)  # a JSON chunk longer than the file
    write(os.path.join(BAD, "bad_chunk.glb"), bytes(glb))

    g = single_triangle()
    g.doc["extensionsUsed"] = ["KHR_draco_mesh_compression"]
    g.doc["extensionsRequired"] = ["KHR_draco_mesh_compression"]
    write_json(os.path.join(BAD, "required_extension.gltf"), g.embedded_doc())

    # Loads, with one warning per unsupported feature.
    g = textured_quad(image_in_buffer=True)
    line_pos = g.accessor([(0, 0, 0), (1, 1, 1)], "VEC3")
    g.doc["meshes"][0]["primitives"].append({"attributes": {"POSITION": line_pos}, "mode": 1})
    material = g.doc["materials"][0]
    material["pbrMetallicRoughness"]["baseColorTexture"]["extensions"] = {
        "KHR_texture_transform": {"scale": [2, 2]}}
    material["extensions"] = {"KHR_materials_clearcoat": {"clearcoatFactor": 1}}
    material["alphaMode"] = "BLEND"
    g.doc["cameras"] = [{"type": "orthographic",
                         "orthographic": {"xmag": 1, "ymag": 1, "znear": 0.1, "zfar": 10}}]
    g.doc["nodes"].append({"name": "ortho", "camera": 0})
    g.doc["nodes"].append({"name": "lamp", "extensions": {"KHR_lights_punctual": {"light": 0}}})
    g.doc["scenes"][0]["nodes"] = [0, 1, 2]
    times = g.accessor([0.0, 1.0], "SCALAR", FLOAT, target=None)
    moves = g.accessor([(0, 0, 0), (0, 1, 0)], "VEC3", target=None)
    g.doc["animations"] = [{"samplers": [{"input": times, "output": moves}],
                            "channels": [{"sampler": 0,
                                          "target": {"node": 0, "path": "translation"}}]}]
    g.doc["extensions"] = {"KHR_lights_punctual": {"lights": [{"type": "point"}]}}
    g.doc["extensionsUsed"] = ["KHR_texture_transform", "KHR_materials_clearcoat",
                               "KHR_lights_punctual"]
    g.doc["extensionsRequired"] = ["KHR_texture_transform"]
    write_json(os.path.join(BAD, "unsupported_features.gltf"), g.embedded_doc())


def main():
    q = textured_quad(image_in_buffer=False)
    q.write_gltf(os.path.join(OUT, "textured_quad.gltf"), "textured_quad.bin")
    write(os.path.join(OUT, "checker.png"), CHECKER)
    write(os.path.join(OUT, "textured_quad.glb"), textured_quad(image_in_buffer=True).glb_bytes())
    instanced().write_gltf(os.path.join(OUT, "instanced.gltf"), "instanced.bin")
    materials().write_gltf(os.path.join(OUT, "materials.gltf"), "materials.bin")
    write_json(os.path.join(OUT, "accessor_variants.gltf"), accessor_variants().embedded_doc())
    write(os.path.join(OUT, "room.glb"), room().glb_bytes())
    write(os.path.join(OUT, "alpha_leaf.glb"), alpha_leaf().glb_bytes())
    bad_inputs()
    print("wrote fixtures under", os.path.relpath(OUT, ROOT))


if __name__ == "__main__":
    main()
