# Runs inside Blender: Cycles bakes the lightmap atlas of a `lightbake export` file, so the two
# bakers can be raced on the same texels (bench/cycles_bake_race.py drives it).
#
#   blender -b --factory-startup --python-exit-code 1 --python bench/cycles_bake.py -- \
#       FILE.glb OUT_DIR --runs 16:1,64:2,... [--threads 2]
#
# The file is imported with Blender's glTF importer; each material becomes what the file says
# lightbake renders: a Lambert (Diffuse BSDF) of the base colour, plus the material's emission
# (emissiveFactor x KHR_materials_emissive_strength, read from the file) from the front face
# only unless the material is doubleSided, as glTF says. Every mesh bakes into one float image
# the atlas's size through its second UV map (TEXCOORD_1), bake type Diffuse, direct + indirect,
# no colour: Cycles' diffuse light divided by the albedo, E/pi, what lightbake's map holds
# (docs/export.md). Margin 0, and the image starts at -1, so the texels Cycles covers (centre
# inside a UV triangle) are the ones it wrote.
#
# Each run SAMPLES:SEED writes OUT_DIR/cycles_SAMPLES_sSEED.npy (float32 RGB, the lightmap EXR's
# orientation: row 0 at the top) and its CPU seconds (user + sys of this process over
# bpy.ops.object.bake: scene sync, BVH and the samples) to OUT_DIR/cycles_SAMPLES_sSEED.json.
# Runs already there are kept.

import argparse
import json
import os
import resource
import struct
import sys
import time

import bpy
import numpy as np

if "bool" not in vars(np):
    np.bool = bool  # numpy >= 1.24 dropped the alias Blender 3.4's importer uses


def parse_args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    parser = argparse.ArgumentParser(prog="cycles_bake.py")
    parser.add_argument("file")
    parser.add_argument("out")
    parser.add_argument("--runs", required=True, help="SAMPLES:SEED,...")
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--ao-distance", type=float, default=0.0,
                        help="metres: also bake ambient occlusion within it (cycles_ao.npy)")
    parser.add_argument("--ao-samples", type=int, default=64)
    return parser.parse_args(argv)


def read_gltf_json(path):
    data = open(path, "rb").read()
    length, kind = struct.unpack_from("<II", data, 12)
    if data[:4] != b"glTF" or kind != 0x4E4F534A:
        raise SystemExit(f"cycles_bake: {path}: not a binary glTF")
    return json.loads(data[20:20 + length])


def lightmap_size(gltf, glb_path):
    files = {m.get("extras", {}).get("lightbake_lightmap", {}).get("hdr")
             for m in gltf.get("materials", [])} - {None}
    if len(files) != 1:
        raise SystemExit(f"cycles_bake: expected one lightmap EXR in the extras, got {files}")
    image = bpy.data.images.load(os.path.join(os.path.dirname(glb_path), files.pop()))
    size = tuple(image.size)
    bpy.data.images.remove(image)
    return size


def lambert_material(material, source, target):
    """Diffuse BSDF of the base colour + the file's emission (front only unless doubleSided),
    and the bake target as the active image node."""
    pbr = source.get("pbrMetallicRoughness", {})
    base = pbr.get("baseColorFactor", [1.0, 1.0, 1.0, 1.0])
    if "baseColorTexture" in pbr:
        raise SystemExit(f"cycles_bake: material '{material.name}' has a base colour texture; "
                         "this bench handles plain colours only")
    strength = source.get("extensions", {}).get("KHR_materials_emissive_strength", {}).get(
        "emissiveStrength", 1.0)
    emission = [c * strength for c in source.get("emissiveFactor", [0.0, 0.0, 0.0])]
    material.use_nodes = True
    nodes, links = material.node_tree.nodes, material.node_tree.links
    nodes.clear()
    output = nodes.new("ShaderNodeOutputMaterial")
    diffuse = nodes.new("ShaderNodeBsdfDiffuse")
    diffuse.inputs["Color"].default_value = (*base[:3], 1.0)
    diffuse.inputs["Roughness"].default_value = 0.0  # Oren-Nayar off: Lambert
    shader = diffuse.outputs["BSDF"]
    if max(emission) > 0.0:
        emit = nodes.new("ShaderNodeEmission")
        emit.inputs["Color"].default_value = (*emission, 1.0)
        emit.inputs["Strength"].default_value = 1.0
        emitted = emit.outputs["Emission"]
        if not source.get("doubleSided", False):
            # glTF: a single-sided emitter's back face emits nothing.
            geometry = nodes.new("ShaderNodeNewGeometry")
            black = nodes.new("ShaderNodeEmission")
            black.inputs["Strength"].default_value = 0.0
            front_only = nodes.new("ShaderNodeMixShader")
            links.new(geometry.outputs["Backfacing"], front_only.inputs["Fac"])
            links.new(emitted, front_only.inputs[1])
            links.new(black.outputs["Emission"], front_only.inputs[2])
            emitted = front_only.outputs["Shader"]
        add = nodes.new("ShaderNodeAddShader")
        links.new(shader, add.inputs[0])
        links.new(emitted, add.inputs[1])
        shader = add.outputs["Shader"]
    links.new(shader, output.inputs["Surface"])
    image_node = nodes.new("ShaderNodeTexImage")
    image_node.image = target
    nodes.active = image_node
    image_node.select = True


def set_up(gltf, target):
    by_name = {m.get("name"): m for m in gltf.get("materials", [])}
    meshes = []
    for obj in bpy.data.objects:
        obj.select_set(False)
        if obj.type != "MESH":
            continue
        if len(obj.data.uv_layers) < 2:
            raise SystemExit(f"cycles_bake: '{obj.name}' has no second UV map (TEXCOORD_1)")
        lightmap_uv = obj.data.uv_layers[1]
        obj.data.uv_layers.active = lightmap_uv
        lightmap_uv.active_render = True
        for slot in obj.material_slots:
            source = by_name.get(slot.material.name)
            if source is None:
                raise SystemExit(f"cycles_bake: material '{slot.material.name}' not in the file")
            lambert_material(slot.material, source, target)
        obj.select_set(True)
        meshes.append(obj)
    if not meshes:
        raise SystemExit("cycles_bake: no mesh to bake")
    bpy.context.view_layer.objects.active = meshes[0]


def configure_cycles(scene, threads):
    scene.render.engine = "CYCLES"
    cycles = scene.cycles
    cycles.device = "CPU"
    cycles.use_denoising = False
    cycles.use_adaptive_sampling = False
    cycles.sample_clamp_direct = 0.0
    cycles.sample_clamp_indirect = 0.0
    cycles.light_sampling_threshold = 0.0
    cycles.max_bounces = 128  # Russian roulette ends the paths, as in the corpus's references
    cycles.diffuse_bounces = 128
    cycles.glossy_bounces = 128
    cycles.transmission_bounces = 128
    cycles.transparent_max_bounces = 128
    cycles.caustics_reflective = True
    cycles.caustics_refractive = True
    scene.render.threads_mode = "FIXED"
    scene.render.threads = threads
    scene.world = scene.world or bpy.data.worlds.new("World")
    scene.world.use_nodes = True
    background = scene.world.node_tree.nodes.get("Background")
    if background is not None:
        background.inputs["Strength"].default_value = 0.0  # lightbake's scene has no sky
    bake = scene.render.bake
    bake.use_pass_direct = True
    bake.use_pass_indirect = True
    bake.use_pass_color = False
    bake.margin = 0
    bake.use_clear = False


def cpu_seconds():
    usage = resource.getrusage(resource.RUSAGE_SELF)
    return usage.ru_utime + usage.ru_stime


def bake_into(target, kind, **options):
    """Bakes every selected mesh into TARGET (texels not covered stay -1); returns its RGB
    rows top first (the file's orientation; Blender's rows run up the image, and the importer
    stored v as 1 - v)."""
    width, height = target.size
    target.pixels.foreach_set(np.tile(np.array([-1.0, -1.0, -1.0, 1.0], np.float32),
                                      width * height))
    bpy.ops.object.bake(type=kind, margin=0, use_clear=False, target="IMAGE_TEXTURES",
                        **options)
    pixels = np.empty(width * height * 4, np.float32)
    target.pixels.foreach_get(pixels)
    return np.ascontiguousarray(pixels.reshape(height, width, 4)[::-1, :, :3])


def bake_run(scene, target, samples, seed, path):
    scene.cycles.samples = samples
    scene.cycles.seed = seed
    start_cpu, start_wall = cpu_seconds(), time.time()
    rgb = bake_into(target, "DIFFUSE", pass_filter={"DIRECT", "INDIRECT"})
    cpu, wall = cpu_seconds() - start_cpu, time.time() - start_wall
    np.save(path + ".npy", rgb)  # float32, exact (EXR would be half)
    with open(path + ".json", "w") as f:
        json.dump({"samples": samples, "seed": seed, "cpu_s": cpu, "wall_s": wall,
                   "threads": scene.render.threads}, f)
    print(f"cycles_bake: {samples} samples, seed {seed}: {cpu:.1f} CPU s, {wall:.1f} s",
          flush=True)


def main():
    args = parse_args()
    os.makedirs(args.out, exist_ok=True)
    bpy.ops.wm.read_factory_settings(use_empty=True)
    gltf = read_gltf_json(args.file)
    bpy.ops.import_scene.gltf(filepath=args.file)
    width, height = lightmap_size(gltf, args.file)
    target = bpy.data.images.new("lightmap", width, height, alpha=True, float_buffer=True)
    target.colorspace_settings.name = "Linear"
    set_up(gltf, target)
    scene = bpy.context.scene
    configure_cycles(scene, args.threads)
    ao_path = os.path.join(args.out, "cycles_ao.npy")
    if args.ao_distance > 0.0 and not os.path.exists(ao_path):
        # Texels whose surface is enclosed within a few cm (behind a light hung under the
        # ceiling, in a contact's crevice): the race reports them apart.
        scene.world.light_settings.distance = args.ao_distance
        scene.cycles.samples = args.ao_samples
        scene.cycles.seed = 1
        np.save(ao_path, bake_into(target, "AO"))
    for item in args.runs.split(","):
        samples, seed = (int(x) for x in item.split(":"))
        path = os.path.join(args.out, f"cycles_{samples}_s{seed}")
        if not os.path.exists(path + ".json"):
            bake_run(scene, target, samples, seed, path)


main()
