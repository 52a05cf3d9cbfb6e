# Imports a glTF file written by `lightbake export` with Blender's own glTF importer, checks
# that TEXCOORD_1 arrives as a UV map, and (optionally) wires the lightmap into every material
# as docs/gltf.md says ("The lightmap in Blender") and renders the camera with Cycles, so the
# picture can be compared with lightbake's own render of the same file.
#
#   blender -b --factory-startup --python-exit-code 1 --python tests/blender/import_gltf.py -- \
#       FILE.glb [--render OUT.exr --size 96x72 --samples 16]
#
# Exits non-zero (through --python-exit-code) when the importer fails or a check does not
# hold; prints one JSON line "import_gltf: {...}" with what it found.
#
# Debian 12's Blender 3.4.1 importer fails on every .glb (Blender's own included) with
# "module 'numpy' has no attribute 'bool'": numpy 1.24 removed that alias, which the importer
# uses (gltf2_blender_mesh.py). Restoring it before the import is all it takes.

import argparse
import json
import os
import struct
import sys

import bpy
import numpy as np

if "bool" not in vars(np):
    np.bool = bool  # numpy >= 1.24 dropped the alias Blender 3.4's importer uses

COMPONENTS = {5126: ("f", 4), 5123: ("H", 2), 5121: ("B", 1)}


def parse_args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    parser = argparse.ArgumentParser(prog="import_gltf.py")
    parser.add_argument("file")
    parser.add_argument("--render", help="wire the lightmap and render the camera to this EXR")
    parser.add_argument("--size", default="96x72")
    parser.add_argument("--samples", type=int, default=16)
    return parser.parse_args(argv)


def read_glb(path):
    data = open(path, "rb").read()
    offset, gltf, binary = 12, None, b""
    while offset < len(data):
        length, kind = struct.unpack_from("<II", data, offset)
        chunk = data[offset + 8: offset + 8 + length]
        if kind == 0x4E4F534A:
            gltf = json.loads(chunk)
        elif kind == 0x004E4942:
            binary = chunk
        offset += 8 + length
    return gltf, binary


def read_uvs(gltf, binary, accessor_index):
    """A VEC2 accessor's values (float, or normalised unsigned byte / short)."""
    accessor = gltf["accessors"][accessor_index]
    view = gltf["bufferViews"][accessor["bufferView"]]
    code, size = COMPONENTS[accessor["componentType"]]
    stride = view.get("byteStride", 2 * size)
    start = view.get("byteOffset", 0) + accessor.get("byteOffset", 0)
    scale = 1.0 if code == "f" else 1.0 / (2 ** (8 * size) - 1)
    return [tuple(v * scale for v in struct.unpack_from("<2" + code, binary, start + i * stride))
            for i in range(accessor["count"])]


def fail(message):
    raise SystemExit("import_gltf: " + message)


def check_lightmap_uvs(gltf, binary, report):
    """Every node whose mesh has TEXCOORD_1 became an object whose second UV map holds it."""
    checked = 0
    for node in gltf.get("nodes", []):
        if "mesh" not in node:
            continue
        primitives = gltf["meshes"][node["mesh"]]["primitives"]
        expected = set()
        for primitive in primitives:
            if "TEXCOORD_1" not in primitive["attributes"]:
                continue
            # Blender's v runs up the image, glTF's down: the importer stores 1 - v.
            expected |= {(round(u, 4), round(1.0 - v, 4))
                         for u, v in read_uvs(gltf, binary, primitive["attributes"]["TEXCOORD_1"])}
        if not expected:
            continue
        obj = bpy.data.objects.get(node.get("name", ""))
        if obj is None or obj.type != "MESH":
            fail(f"node '{node.get('name')}' did not arrive as a mesh object")
        layers = obj.data.uv_layers
        if len(layers) < 2:
            fail(f"'{obj.name}' has {len(layers)} UV map(s); TEXCOORD_1 is missing")
        layer = layers[1]
        found = {(round(d.uv[0], 4), round(d.uv[1], 4)) for d in layer.data}
        if found != expected:
            fail(f"'{obj.name}': UV map '{layer.name}' holds {len(found)} distinct UVs, "
                 f"TEXCOORD_1 {len(expected)}; {len(found ^ expected)} differ")
        report["lightmap_uv_maps"][obj.name] = layer.name
        checked += 1
    if checked == 0:
        fail("no mesh with TEXCOORD_1 in the file: nothing was checked")


def wire_lightmap(gltf, glb_path, report):
    """docs/gltf.md, "The lightmap in Blender": emission = base colour x lightmap (through the
    second UV map), added to the material's own emission; the surface shader is dropped when
    the map holds all the light (--contents all)."""
    lightmap_files = {m.get("extras", {}).get("lightbake_lightmap", {}).get("hdr")
                      for m in gltf.get("materials", [])} - {None}
    if len(lightmap_files) != 1:
        fail(f"expected one lightmap EXR named in the materials' extras, got {lightmap_files}")
    image = bpy.data.images.load(os.path.join(os.path.dirname(glb_path), lightmap_files.pop()))
    image.colorspace_settings.name = "Linear"  # radiance, W/(sr m^2) (E/pi)
    wired = 0
    for obj in bpy.data.objects:
        if obj.type != "MESH" or len(obj.data.uv_layers) < 2:
            continue
        for slot in obj.material_slots:
            material = slot.material
            source = next((m for m in gltf["materials"] if m.get("name") == material.name), None)
            if source is None or "MOZ_lightmap" not in source.get("extensions", {}):
                continue
            contents = source["extras"]["lightbake_lightmap"]["contents"]
            tree = material.node_tree
            bsdf = tree.nodes.get("Principled BSDF")
            output = next(n for n in tree.nodes if n.type == "OUTPUT_MATERIAL")
            uv_map = tree.nodes.new("ShaderNodeUVMap")
            uv_map.uv_map = obj.data.uv_layers[1].name
            texture = tree.nodes.new("ShaderNodeTexImage")
            texture.image = image
            texture.interpolation = "Linear"
            texture.extension = "EXTEND"
            tree.links.new(uv_map.outputs["UV"], texture.inputs["Vector"])
            multiply = tree.nodes.new("ShaderNodeMixRGB")
            multiply.blend_type = "MULTIPLY"
            multiply.inputs["Fac"].default_value = 1.0
            base = bsdf.inputs["Base Color"]
            if base.is_linked:
                tree.links.new(base.links[0].from_socket, multiply.inputs["Color1"])
            else:
                multiply.inputs["Color1"].default_value = base.default_value
            tree.links.new(texture.outputs["Color"], multiply.inputs["Color2"])
            baked = tree.nodes.new("ShaderNodeEmission")
            baked.inputs["Strength"].default_value = 1.0
            tree.links.new(multiply.outputs["Color"], baked.inputs["Color"])
            # The material's own glow: Principled's emission, alone.
            glow = tree.nodes.new("ShaderNodeEmission")
            glow.inputs["Color"].default_value = bsdf.inputs["Emission"].default_value
            glow.inputs["Strength"].default_value = bsdf.inputs["Emission Strength"].default_value
            add = tree.nodes.new("ShaderNodeAddShader")
            tree.links.new(baked.outputs["Emission"], add.inputs[0])
            if contents == "all":
                tree.links.new(glow.outputs["Emission"], add.inputs[1])
            else:  # the lamps' and emitters' direct light comes from the BSDF (0 bounces)
                tree.links.new(bsdf.outputs["BSDF"], add.inputs[1])
            tree.links.new(add.outputs["Shader"], output.inputs["Surface"])
            wired += 1
    report["materials_wired"] = wired
    if wired == 0:
        fail("no material with MOZ_lightmap was wired")


def render(path, size, samples):
    scene = bpy.context.scene
    camera = next((o for o in bpy.data.objects if o.type == "CAMERA"), None)
    if camera is None:
        fail("the file has no camera")
    scene.camera = camera
    width, height = (int(v) for v in size.lower().split("x"))
    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = samples
    scene.cycles.seed = 1
    scene.cycles.use_denoising = False
    scene.cycles.use_adaptive_sampling = False
    scene.cycles.max_bounces = 0  # the map holds the bounced light: Cycles adds none
    scene.cycles.pixel_filter_type = "BOX"
    scene.cycles.filter_width = 1.0
    scene.render.resolution_x, scene.render.resolution_y = width, height
    scene.render.resolution_percentage = 100
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"
    scene.render.image_settings.file_format = "OPEN_EXR"
    scene.render.image_settings.color_mode = "RGB"
    scene.render.image_settings.color_depth = "32"
    world = bpy.data.worlds.new("black")
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.0
    scene.world = world
    scene.render.filepath = path
    bpy.ops.render.render(write_still=True)


def main():
    args = parse_args()
    gltf, binary = read_glb(args.file)
    bpy.ops.wm.read_factory_settings(use_empty=True)
    result = bpy.ops.import_scene.gltf(filepath=args.file)
    if result != {"FINISHED"}:
        fail(f"the importer returned {result}")
    report = {"file": args.file, "blender": bpy.app.version_string,
              "objects": len(bpy.data.objects), "lightmap_uv_maps": {}}
    check_lightmap_uvs(gltf, binary, report)
    if args.render:
        wire_lightmap(gltf, args.file, report)
        render(args.render, args.size, args.samples)
        report["render"] = args.render
    print("import_gltf: " + json.dumps(report))


main()
