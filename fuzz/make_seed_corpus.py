#!/usr/bin/env python3
"""Writes fuzz/corpus/<target>/: the project's own valid and bad inputs, one case per file.

Run from the repository root after building `lightbake` (the bake_dir seed is a real bake):
    python3 fuzz/make_seed_corpus.py build/app/lightbake
Every input here is written by this script or copied from tests/data (project-written).
Files it does not write (inputs the fuzzers found, named after what they broke) are kept.
"""
import base64
import json
import os
import struct
import subprocess
import sys
import tempfile
import zlib

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CORPUS = os.path.join(ROOT, "fuzz", "corpus")
SEPARATOR = b"\n--lightbake-fuzz-file--\n"  # fuzz_targets.h kBakeFileSeparator


def write(target, name, data):
    os.makedirs(os.path.join(CORPUS, target), exist_ok=True)
    if isinstance(data, str):
        data = data.encode()
    with open(os.path.join(CORPUS, target, name), "wb") as f:
        f.write(data)


# A lamp over a floor; also the scene of the bake_dir target.
BAKE_SCENE = os.path.join(ROOT, "fuzz", "bake_scene.toml")
with open(BAKE_SCENE) as f:
    LIGHT = f.read()


def tower(levels, copies):
    toml = LIGHT + '[[define.d0]]\nshape = "quad"\n'
    for level in range(1, levels):
        for copy in range(copies):
            toml += f'[[define.d{level}]]\ninstance = "d{level - 1}"\ntranslate = [{copy}, 0, 0]\n'
    return toml + f'[[objects]]\ninstance = "d{levels - 1}"\n'


def toml_seeds():
    write("toml", "valid_room", LIGHT + '[[objects]]\nshape = "box"\ninward = true\n')
    write("toml", "fan_out", tower(11, 10))
    write("toml", "deep_chain_64", tower(64, 1))
    write("toml", "deep_chain_65", tower(65, 1))
    write("toml", "cycle", LIGHT + '[[define.a]]\ninstance = "a"\n[[objects]]\ninstance = "a"\n')
    write("toml", "syntax_error", LIGHT + "[materials.wall\nreflectance = 0.5\n")
    write("toml", "reflectance_above_one", LIGHT + "[materials.wall]\nreflectance = 2\n")
    write("toml", "include_device", 'include = "/dev/zero"\n')
    write("toml", "deep_arrays", "a = " + "[" * 300 + "]" * 300 + "\n")
    write("toml", "nan", LIGHT + '[[objects]]\nshape = "quad"\ntranslate = [nan, 0, 0]\n')
    write("toml", "huge_scale", LIGHT + '[[objects]]\nshape = "quad"\nscale = 3e38\n')


def triangle(values=None):
    values = values or [0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 1, 0, 0, 1,
                        0, 0, 1, 0, 0, 1, 0, 1, 2]
    data = struct.pack("<27f", *values)

    def accessor(offset, count, kind):
        return {"bufferView": 0, "byteOffset": offset, "componentType": 5126, "count": count,
                "type": kind}
    return {
        "asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2}}]}],
        "buffers": [{"byteLength": len(data), "uri": "data:application/octet-stream;base64," +
                     base64.b64encode(data).decode()}],
        "bufferViews": [{"buffer": 0, "byteLength": len(data)}],
        "accessors": [accessor(0, 3, "VEC3"), accessor(36, 3, "VEC3"), accessor(72, 3, "VEC2"),
                      accessor(96, 3, "SCALAR")]}


def png_1x1():
    """A valid 1 x 1 grey RGB PNG."""
    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", 1, 1, 8, 2, 0, 0, 0)) +
            chunk(b"IDAT", zlib.compress(b"\x00\x80\x80\xff")) + chunk(b"IEND", b""))


def gltf_seeds():
    def edited(name, edit):
        d = triangle()
        edit(d)
        write("gltf", name, json.dumps(d))
    edited("valid_triangle", lambda d: None)
    write("gltf", "deep_extras", '{"asset": {"version": "2.0"}, "extras": ' + "[" * 600 + "]" * 600 + "}")
    edited("dag_2_20", lambda d: d.update(nodes=[{"children": [i + 1, i + 1]} for i in range(20)] + [{"mesh": 0}]))
    edited("chain_2000", lambda d: d.update(nodes=[{"children": [i + 1], "translation": [0.001, 0, 0]} for i in range(2000)] + [{"mesh": 0}]))
    edited("cycle", lambda d: d.update(nodes=[{"children": [1]}, {"children": [0], "mesh": 0}]))
    edited("version_1", lambda d: d["asset"].update(version="1.0"))
    edited("empty_primitives", lambda d: d["meshes"][0].update(primitives=[]))
    edited("aspect_zero", lambda d: d.update(cameras=[{"type": "perspective", "perspective": {"yfov": 1, "znear": 0.1, "aspectRatio": 0}}]))
    edited("znear_zero_zfar_negative", lambda d: d.update(cameras=[{"type": "perspective", "perspective": {"yfov": 1, "znear": 0, "zfar": -1}}]))
    edited("scene_minus_one", lambda d: d.update(scene=-1))
    edited("float_indices", lambda d: d["meshes"][0]["primitives"][0].update(indices=3))
    edited("absolute_uri", lambda d: d["buffers"][0].update(uri="/etc/passwd"))
    edited("parent_uri", lambda d: d["buffers"][0].update(uri="../outside.bin"))
    edited("unknown_extension", lambda d: d.update(extensionsUsed=["EXT_made_up"], materials=[{"extensions": {"EXT_made_up": {}}}]))
    edited("required_extension", lambda d: d.update(extensionsUsed=["EXT_made_up"], extensionsRequired=["EXT_made_up"]))
    # Blender 4 style (issue 14): animation pointer, a skin without inverseBindMatrices, lamps,
    # a texture transform with a texCoord override; the loader cuts animations and skins.
    edited("blender4_style", lambda d: d.update(
        extensionsUsed=["KHR_animation_pointer", "KHR_lights_punctual", "KHR_texture_transform"],
        extensions={"KHR_lights_punctual": {"lights": [{"type": "point", "intensity": 10}]}},
        nodes=[{"mesh": 0, "skin": 0, "extensions": {"KHR_lights_punctual": {"light": 0}}}],
        skins=[{"joints": [0]}],
        animations=[{"channels": [{"sampler": 0, "target": {"path": "pointer", "extensions": {
            "KHR_animation_pointer": {"pointer": "/materials/0/emissiveFactor"}}}}],
            "samplers": [{"input": 3, "output": 0}]}],
        meshes=[{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2},
                                 "material": 0}]}],
        materials=[{"pbrMetallicRoughness": {"metallicFactor": 0, "baseColorTexture": {"index": 0, "extensions": {
            "KHR_texture_transform": {"offset": [0.5, 0], "rotation": 1, "scale": [2, -1],
                                      "texCoord": 0}}}},
            "normalTexture": {"index": 0}}],
        textures=[{"source": 0}],
        images=[{"uri": "data:image/png;base64," + base64.b64encode(png_1x1()).decode()}]))
    big = [0, 0, 0, 1, 3e38, 0, 0, 1, 0] + [0, 0, 1] * 3 + [0, 0, 1, 0, 0, 1, 0, 1, 2]
    write("gltf", "vertex_3e38", json.dumps(triangle(big)))
    nan = [0, 0, 0, float("nan"), 0, 0, 0, 1, 0] + [0, 0, 1] * 3 + [0, 0, 1, 0, 0, 1, 0, 1, 2]
    write("gltf", "vertex_nan", json.dumps(triangle(nan)).replace("NaN", "0"))  # JSON has no NaN
    png = b"\x89PNG\r\n\x1a\n\0\0\0\x0dIHDR" + struct.pack(">II", 100000, 100000) + b"\x08\x02\0\0\0\0\0\0\0"
    edited("huge_png", lambda d: d.update(
        images=[{"uri": "data:image/png;base64," + base64.b64encode(png).decode()}],
        textures=[{"source": 0}],
        materials=[{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}]))
    # The project's fixtures that stand alone (no external .bin), including .glb files.
    gltf_dir = os.path.join(ROOT, "tests", "data", "gltf")
    for name in ["textured_quad.glb", "room.glb", "bad/truncated.glb", "bad/bad_chunk.glb",
                 "bad/syntax_error.gltf", "bad/required_extension.gltf",
                 "bad/unsupported_features.gltf", "accessor_variants.gltf"]:
        with open(os.path.join(gltf_dir, name), "rb") as f:
            write("gltf", "fixture_" + name.replace("/", "_"), f.read())


def mesh_seeds():
    tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nvn 0 0 1\nf 1/1/1 2/2/1 3/3/1\n"
    write("obj", "valid_triangle", tri)
    write("obj", "coordinate_1e39", "v 0 0 0\nv 1e39 0 0\nv 0 1 0\nf 1 2 3\n")
    write("obj", "vt_past_end", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/2 3/3\n")
    write("obj", "face_index_out_of_range", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n")
    write("obj", "negative_indices", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\n")
    write("obj", "nan", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n")
    corners = " ".join(str(1 + i % 3) for i in range(10001))  # one past the cap, small file
    write("obj", "polygon_10001", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf " + corners + "\n")
    write("obj", "repeated_vertex", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 2\nf 1 2 3\n")

    head = "ply\nformat ascii 1.0\n"
    body = ("property float x\nproperty float y\nproperty float z\nelement face 1\n"
            "property list uchar int vertex_indices\nend_header\n")
    write("ply", "valid_ascii", head + "element vertex 3\n" + body + "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n")
    write("ply", "count_minus_5", head + "element vertex -5\n" + body)
    write("ply", "count_huge", head + "element vertex 4000000000\n" + body)
    binary = ("ply\nformat binary_little_endian 1.0\nelement vertex 3\n" + body).encode()
    write("ply", "valid_binary", binary + struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0) + struct.pack("<B3i", 3, 0, 1, 2))
    write("ply", "truncated_binary", binary + struct.pack("<6f", 0, 0, 0, 1, 0, 0))
    write("ply", "index_out_of_range", head + "element vertex 3\n" + body + "0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n")

    write("stl", "valid_ascii", "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n"
          "vertex 0 1 0\nendloop\nendfacet\nendsolid t\n")
    record = struct.pack("<12fH", 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0)
    write("stl", "valid_binary", b" " * 80 + struct.pack("<I", 1) + record)
    write("stl", "truncated_binary", b" " * 80 + struct.pack("<I", 2) + record)
    write("stl", "count_huge", b" " * 80 + struct.pack("<I", 0xffffffff) + record)
    write("stl", "ascii_nan", "solid t\nfacet normal 0 0 1\nouter loop\nvertex nan 0 0\nvertex 1 0 0\n"
          "vertex 0 1 0\nendloop\nendfacet\nendsolid t\n")


def bake_seeds(lightbake):
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "bake")
        subprocess.run([lightbake, "bake", BAKE_SCENE, "-o", out], check=True,
                       stdout=subprocess.DEVNULL)
        parts = []
        for name in ["manifest.json", "illumination.bin", "radiosity.bin", "illumination.exr"]:
            path = os.path.join(out, name)
            parts.append(open(path, "rb").read() if os.path.exists(path) else b"")
    write("bake_dir", "valid", SEPARATOR.join(parts))
    write("bake_dir", "no_exr", SEPARATOR.join(parts[:3]))
    write("bake_dir", "truncated_radiosity", SEPARATOR.join([parts[0], parts[1], parts[2][:40]]))
    write("bake_dir", "truncated_illumination", SEPARATOR.join([parts[0], parts[1][:30], parts[2]]))
    write("bake_dir", "manifest_only", parts[0])
    write("bake_dir", "empty", b"")


if __name__ == "__main__":
    toml_seeds()
    gltf_seeds()
    mesh_seeds()
    bake_seeds(sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "build", "app", "lightbake"))
