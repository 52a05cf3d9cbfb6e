# Builds one test scene in Blender the way an artist would, exports it with Blender's own glTF
# exporter and renders it with Cycles on the CPU as the reference (docs/gltf.md, "Scenes from
# Blender, checked against Cycles").
#
#   blender -b --factory-startup --python tests/blender/make_scene.py -- SCENE OUT_DIR \
#       [--size 96x72] [--samples 512] [--shading lambert|principled] [--no-render]
#
# SCENE is one of SCENES below. Writes OUT_DIR/SCENE.glb and, unless --no-render, two Cycles
# renders OUT_DIR/SCENE_SHADING_a.exr and _b.exr of SAMPLES / 2 samples each with different
# seeds (their mean is the reference, their difference measures its noise), linear, Standard
# view, no denoiser, box pixel filter, and OUT_DIR/SCENE_SHADING.json (what was built, the
# exporter's settings and lighting mode, Cycles' settings and CPU time).
#
# --shading lambert (the default) renders with each Principled BSDF replaced by a Diffuse BSDF
# of the same base colour (plus an Emission of the same strength) after the export: what the
# glTF file means (its diffuse term is Lambert's). --shading principled renders the materials
# as built: Blender 3.4's Principled BSDF has Disney's diffuse lobe, brighter than Lambert's at
# roughness 1 (the factor is measured, docs/gltf.md).
#
# Every scene is one room, 4 x 3 x 2.6 m inside (Blender is Z up; the exporter turns it Y up),
# with a grey floor, a white ceiling, a red wall (-X), a green wall (+X), grey walls and a grey
# block on the floor. Materials are plain diffuse Principled BSDFs: base colour only, roughness
# 1, specular 0 (the exporter writes KHR_materials_specular with a black specular colour: no
# specular layer). Every mesh has two UV maps: "UVMap" (Smart UV Project) and "Lightmap"
# (Lightmap Pack), the second exported as TEXCOORD_1.

import argparse
import json
import math
import os
import sys
import time

import bmesh
import bpy
from mathutils import Matrix, Vector

ROOM = (4.0, 3.0, 2.6)  # x, y, z extent; the floor is z = 0, the room centred on x = y = 0

# Each scene's light. Power in Blender's units: W for point and spot lamps (a spot's watts as
# if it were a point lamp), W/m^2 for the sun, emission strength (W/(sr m^2) per unit colour)
# for the panel.
SCENES = {
    # A 1 x 0.6 m panel (a plane) hanging 0.4 m under the ceiling, emitting from both faces
    # (Cycles does; the exporter writes doubleSided: true).
    "panel": dict(kind="panel", strength=8.0, size=(1.0, 0.6), height=2.2),
    "point": dict(kind="POINT", energy=60.0, location=(-0.6, 0.4, 1.9)),
    # Aimed down and towards the green wall; blend 0.3: the exporter writes
    # innerConeAngle = (1 - blend) x outerConeAngle.
    "spot": dict(kind="SPOT", energy=300.0, location=(-0.8, -0.3, 2.4), target=(0.9, 0.5, 0.0),
                 spot_size_deg=70.0, spot_blend=0.3),
    # Through a 2 x 1.4 m skylight in the ceiling (the only scene with a hole), 25 degrees off
    # the vertical. Light that leaves through the hole is lost in both renderers (black world).
    "sun": dict(kind="SUN", energy=6.0, direction=(0.38, 0.25, -1.0), skylight=(2.0, 1.4),
                skylight_centre=(-0.5, -0.1)),
    # The sun's room with foliage under the skylight: a 2.4 x 1.8 m leaf card 0.3 m below the
    # ceiling, its base colour texture's alpha a checker of 8 x 8 cells cut out by Alpha Clip
    # (the exporter writes alphaMode MASK, alphaCutoff 0.5): the floor gets a dappled shadow
    # and the light the leaves pass and reflect.
    "leaves": dict(kind="SUN", energy=6.0, direction=(0.38, 0.25, -1.0), skylight=(2.0, 1.4),
                   skylight_centre=(-0.5, -0.1), leaves=dict(size=(2.4, 1.8), height=2.3,
                                                             cells=8)),
    # The sun's room with a pane of tinted glass drawn the cheap way, as artists do for windows
    # and gauze: a 1.6 x 1.2 m card 0.3 m below the skylight whose Principled Alpha is 0.4,
    # blend mode Alpha Blend (the exporter writes alphaMode BLEND, baseColorFactor's alpha 0.4):
    # 0.6 of the sun passes it, uncoloured, in Cycles (a mix with a Transparent BSDF) and in
    # lightbake (stochastic transparency).
    "pane": dict(kind="SUN", energy=6.0, direction=(0.38, 0.25, -1.0), skylight=(2.0, 1.4),
                 skylight_centre=(-0.5, -0.1), pane=dict(size=(1.6, 1.2), height=2.3,
                                                         alpha=0.4)),
    # The point room with a textured floor: a checker of two greys (8 x 8 cells)
    # through a Mapping node (scale 3 x 2, rotation 30 deg, offset), which the exporter writes
    # as KHR_texture_transform.
    "textured": dict(kind="POINT", energy=60.0, location=(-0.6, 0.4, 1.9),
                     floor_texture=dict(cells=8, greys=(0.2, 0.7), scale=(3.0, 2.0),
                                        rotation_deg=30.0, offset=(0.1, 0.2))),
    # The point room with its green wall corrugated by a normal map: RIDGES vertical ridges, a
    # sine profile of slopes up to SLOPE_DEG, in an 8-bit Non-Color image through a Normal Map
    # node (tangent space, the UV map "UVMap"); the exporter writes it as normalTexture without
    # tangents, so lightbake makes MikkTSpace ones, as Blender does.
    "bumped": dict(kind="POINT", energy=60.0, location=(-0.6, 0.4, 1.9),
                   normal_map=dict(ridges=12, slope_deg=35.0, texels=192)),
    # The point room furnished as artists build: the block twice more as linked duplicates (one
    # mirrored by a negative scale, one scaled unevenly), a row of three posts by an Array
    # modifier, a pair of shelves by a Mirror modifier, and a collection of two small boxes
    # placed twice as collection instances. The modifiers are applied before the lightmap UVs
    # are packed; the exporter writes the instances as nodes sharing a mesh.
    "instanced": dict(kind="POINT", energy=60.0, location=(-0.6, 0.4, 1.9), furnished=True),
    # The panel's room with a chrome ball (Principled Metallic 1, Roughness 0: the exporter
    # writes metallicFactor 1, roughnessFactor 0, a mirror to lightbake) and a glass ball
    # (Transmission 1, Roughness 0, IOR 1.5: KHR_materials_transmission and KHR_materials_ior,
    # glass), both smooth-shaded UV spheres standing on the floor, where the panel lights them:
    # the floor gets the glass ball's caustic and both balls' reflections. Cycles renders them
    # as built (only the diffuse materials become Diffuse BSDFs).
    # The sun's room without the sun: a world of uniform colour (Background colour x strength:
    # radiance in W/(sr m^2) per channel) lights it through the skylight. Blender's exporter
    # writes no world, so the script writes world.toml beside world.glb: the glb included and
    # its sky given in [sky], as docs/gltf.md tells artists to.
    "world": dict(kind="world", world=(0.9, 1.1, 1.5), skylight=(2.0, 1.4),
                  skylight_centre=(-0.5, -0.1)),
    # The same room under an HDR world: an equirect EXR (written by this script: a sky bright
    # towards the zenith and a warm glow 50 deg up towards Blender's +X +Y) through an
    # Environment Texture node. The script writes hdr_world.toml beside the glb: the image as
    # [sky] with rotation = -90 (Blender's equirect mapping, Z up, against lightbake's, +Y up).
    "hdr_world": dict(kind="world", world_image=dict(size=(128, 64), zenith=(0.25, 0.35, 0.6),
                                                     glow=(6.0, 4.0, 2.0), glow_azimuth=30.0,
                                                     glow_elevation=50.0, glow_width=20.0),
                      skylight=(2.0, 1.4), skylight_centre=(-0.5, -0.1)),
    "specular": dict(kind="panel", strength=8.0, size=(1.0, 0.6), height=2.2,
                     balls=dict(chrome=((-0.2, 0.75), 0.3), glass=((-0.45, -0.15), 0.3))),
}

MATERIALS = {  # name: linear base colour
    "floor": (0.45, 0.45, 0.45),
    "ceiling": (0.8, 0.8, 0.8),
    "wall": (0.6, 0.6, 0.6),
    "red_wall": (0.7, 0.12, 0.08),
    "green_wall": (0.12, 0.55, 0.15),
    "block": (0.5, 0.5, 0.5),
    "props": (0.65, 0.55, 0.35),
}


def parse_args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    parser = argparse.ArgumentParser(prog="make_scene.py")
    parser.add_argument("scene", choices=sorted(SCENES))
    parser.add_argument("out_dir")
    parser.add_argument("--size", default="96x72")
    parser.add_argument("--samples", type=int, default=512, help="both halves together")
    parser.add_argument("--shading", choices=["lambert", "principled"], default="lambert")
    parser.add_argument("--no-render", action="store_true")
    return parser.parse_args(argv)


# ---------------------------------------------------------------------------------------------
# Materials


def principled(name, colour, emission=None, strength=0.0):
    material = bpy.data.materials.new(name)
    material.use_nodes = True
    bsdf = material.node_tree.nodes["Principled BSDF"]
    bsdf.inputs["Base Color"].default_value = (*colour, 1.0)
    bsdf.inputs["Roughness"].default_value = 1.0
    bsdf.inputs["Specular"].default_value = 0.0
    bsdf.inputs["Metallic"].default_value = 0.0
    if emission is not None:
        bsdf.inputs["Emission"].default_value = (*emission, 1.0)
        bsdf.inputs["Emission Strength"].default_value = strength
    return material


def leaf_material(name, colour, cells):
    """Alpha-clipped foliage: an RGBA image texture (COLOUR, alpha a CELLS x CELLS checker) into
    Base Color and Alpha, blend mode Alpha Clip at 0.5."""
    material = principled(name, colour)
    image = bpy.data.images.new(name, cells, cells, alpha=True)
    image.pixels = [v for row in range(cells) for column in range(cells)
                    for v in (*colour, float((row + column) % 2))]
    image.pack()  # the exporter writes it into the .glb
    texture = material.node_tree.nodes.new("ShaderNodeTexImage")
    texture.image = image  # Linear, as lightbake samples every texture
    bsdf = material.node_tree.nodes["Principled BSDF"]
    material.node_tree.links.new(texture.outputs["Color"], bsdf.inputs["Base Color"])
    material.node_tree.links.new(texture.outputs["Alpha"], bsdf.inputs["Alpha"])
    material.blend_method = "CLIP"
    material.alpha_threshold = 0.5
    return material


def pane_material(name, colour, alpha):
    """Alpha-blended: Principled Alpha ALPHA (unlinked), blend mode Alpha Blend."""
    material = principled(name, colour)
    material.node_tree.nodes["Principled BSDF"].inputs["Alpha"].default_value = alpha
    material.blend_method = "BLEND"
    return material


def normal_mapped_material(name, colour, spec):
    """Base colour COLOUR, corrugated by a tangent-space normal map: ridges along v, the height
    a sine of u whose slope peaks at slope_deg."""
    material = principled(name, colour)
    side, ridges = spec["texels"], spec["ridges"]
    peak = math.tan(math.radians(spec["slope_deg"]))
    image = bpy.data.images.new(name + "_normal", side, side, alpha=False)
    image.colorspace_settings.name = "Non-Color"
    pixels = []
    for row in range(side):
        for column in range(side):
            slope = peak * math.cos(2.0 * math.pi * ridges * (column + 0.5) / side)
            n = Vector((-slope, 0.0, 1.0)).normalized()  # dh/du = slope: n = (-h_u, 0, 1)
            pixels += [0.5 * n.x + 0.5, 0.5 * n.y + 0.5, 0.5 * n.z + 0.5, 1.0]
    image.pixels = pixels
    image.pack()
    nodes, links = material.node_tree.nodes, material.node_tree.links
    texture = nodes.new("ShaderNodeTexImage")
    texture.image = image
    normal_map = nodes.new("ShaderNodeNormalMap")
    normal_map.space = "TANGENT"
    normal_map.uv_map = "UVMap"
    links.new(texture.outputs["Color"], normal_map.inputs["Color"])
    links.new(normal_map.outputs["Normal"], nodes["Principled BSDF"].inputs["Normal"])
    return material


def textured_material(name, spec):
    """A checker of two greys (CELLS x CELLS cells, sRGB values) into Base Color through a
    Mapping node (scale, rotation about Z, offset) on the UV map."""
    material = principled(name, (1.0, 1.0, 1.0))
    cells, (dark, light) = spec["cells"], spec["greys"]
    # 8 x 8 texels a cell: with 1-texel cells lightbake's render was 5% brighter than Cycles',
    # with 8 0.9%: the two blend 8-bit sRGB texels differently between texels (Cycles, it
    # seems, before decoding them to linear), which matters only where a lookup straddles two
    # cells.
    side = 8 * cells
    image = bpy.data.images.new(name, side, side, alpha=False)
    image.pixels = [v for row in range(side) for column in range(side)
                    for v in (*([light if (row // 8 + column // 8) % 2 else dark] * 3), 1.0)]
    image.pack()
    nodes, links = material.node_tree.nodes, material.node_tree.links
    coordinates = nodes.new("ShaderNodeTexCoord")
    mapping = nodes.new("ShaderNodeMapping")
    mapping.inputs["Location"].default_value = (*spec["offset"], 0.0)
    mapping.inputs["Rotation"].default_value = (0.0, 0.0, math.radians(spec["rotation_deg"]))
    mapping.inputs["Scale"].default_value = (*spec["scale"], 1.0)
    texture = nodes.new("ShaderNodeTexImage")
    texture.image = image  # Linear interpolation, Blender's default: lightbake reads no sampler
    links.new(coordinates.outputs["UV"], mapping.inputs["Vector"])
    links.new(mapping.outputs["Vector"], texture.inputs["Vector"])
    links.new(texture.outputs["Color"], nodes["Principled BSDF"].inputs["Base Color"])
    return material


# Principled inputs of the two specular materials: a mirror and clear glass. Specular at
# Blender's default 0.5 (F0 0.04, glTF's), which the exporter writes as no
# KHR_materials_specular (principled() sets 0 for the diffuse materials, where it is ignored).
SPECULAR = {
    "chrome": dict(colour=(0.9, 0.9, 0.9),
                   inputs={"Metallic": 1.0, "Roughness": 0.0, "Specular": 0.5}),
    "glass": dict(colour=(1.0, 1.0, 1.0),
                  inputs={"Transmission": 1.0, "Roughness": 0.0, "IOR": 1.5, "Specular": 0.5}),
}


def specular_material(name):
    material = principled(name, SPECULAR[name]["colour"])
    bsdf = material.node_tree.nodes["Principled BSDF"]
    for socket, value in SPECULAR[name]["inputs"].items():
        bsdf.inputs[socket].default_value = value
    material["lightbake_specular"] = True  # kept as built by the Lambert reference
    return material


def replace_with_diffuse_bsdf(material):
    """The same base colour and emission through a Diffuse BSDF (Lambert) and an Emission; an
    alpha-clipped material keeps its cut-outs (a Transparent BSDF where alpha < 0.5), an
    alpha-blended one its transparency (mixed with a Transparent BSDF by alpha)."""
    if material.get("lightbake_specular"):
        return  # mirrors and glass are what they are in both renderers
    tree = material.node_tree
    bsdf = tree.nodes["Principled BSDF"]
    output = tree.nodes["Material Output"]
    colour = tuple(bsdf.inputs["Base Color"].default_value)
    emission = tuple(bsdf.inputs["Emission"].default_value)
    strength = bsdf.inputs["Emission Strength"].default_value
    diffuse = tree.nodes.new("ShaderNodeBsdfDiffuse")
    diffuse.inputs["Color"].default_value = colour
    diffuse.inputs["Roughness"].default_value = 0.0  # Lambert
    for link in bsdf.inputs["Base Color"].links:
        tree.links.new(link.from_socket, diffuse.inputs["Color"])
    for link in bsdf.inputs["Normal"].links:  # a normal map
        tree.links.new(link.from_socket, diffuse.inputs["Normal"])
    shader = diffuse.outputs["BSDF"]
    if material.blend_method == "BLEND" and not bsdf.inputs["Alpha"].links:
        # Principled's Alpha in Cycles: a mix with a Transparent BSDF, whatever the blend mode.
        blend = tree.nodes.new("ShaderNodeMixShader")
        blend.inputs["Fac"].default_value = bsdf.inputs["Alpha"].default_value
        tree.links.new(tree.nodes.new("ShaderNodeBsdfTransparent").outputs["BSDF"],
                       blend.inputs[1])
        tree.links.new(shader, blend.inputs[2])
        shader = blend.outputs["Shader"]
    for link in bsdf.inputs["Alpha"].links:  # Cycles ignores the blend mode: clip by hand
        clip = tree.nodes.new("ShaderNodeMath")
        clip.operation = "GREATER_THAN"
        clip.inputs[1].default_value = material.alpha_threshold - 1e-6
        tree.links.new(link.from_socket, clip.inputs[0])
        cut = tree.nodes.new("ShaderNodeMixShader")
        tree.links.new(clip.outputs["Value"], cut.inputs["Fac"])
        tree.links.new(tree.nodes.new("ShaderNodeBsdfTransparent").outputs["BSDF"],
                       cut.inputs[1])
        tree.links.new(shader, cut.inputs[2])
        shader = cut.outputs["Shader"]
    if strength > 0.0 and max(emission[:3]) > 0.0:
        emit = tree.nodes.new("ShaderNodeEmission")
        emit.inputs["Color"].default_value = emission
        emit.inputs["Strength"].default_value = strength
        add = tree.nodes.new("ShaderNodeAddShader")
        tree.links.new(diffuse.outputs["BSDF"], add.inputs[0])
        tree.links.new(emit.outputs["Emission"], add.inputs[1])
        shader = add.outputs["Shader"]
    tree.links.new(shader, output.inputs["Surface"])


# ---------------------------------------------------------------------------------------------
# Geometry


def mesh_object(name, build, materials):
    """A mesh object from build(bm) -> per-face material index list, with both UV maps."""
    mesh = bpy.data.meshes.new(name)
    bm = bmesh.new()
    build(bm)
    bm.to_mesh(mesh)
    bm.free()
    for material in materials:
        mesh.materials.append(material)
    obj = bpy.data.objects.new(name, mesh)
    bpy.context.scene.collection.objects.link(obj)
    return obj


def add_quad(bm, corners, material_index):
    """A quad from four corners, counter-clockwise seen from the side it faces."""
    face = bm.faces.new([bm.verts.new(c) for c in corners])
    face.material_index = material_index
    return face


def build_room(skylight=None, skylight_centre=(0.0, 0.0)):
    """The room's inside faces; the ceiling as a frame around the skylight when there is one."""
    x, y, z = ROOM[0] / 2, ROOM[1] / 2, ROOM[2]
    index = {name: i for i, name in enumerate(["floor", "ceiling", "wall", "red_wall",
                                                "green_wall"])}

    def build(bm):
        add_quad(bm, [(-x, -y, 0), (x, -y, 0), (x, y, 0), (-x, y, 0)], index["floor"])
        add_quad(bm, [(-x, -y, 0), (-x, y, 0), (-x, y, z), (-x, -y, z)], index["red_wall"])
        add_quad(bm, [(x, -y, 0), (x, -y, z), (x, y, z), (x, y, 0)], index["green_wall"])
        add_quad(bm, [(-x, -y, 0), (-x, -y, z), (x, -y, z), (x, -y, 0)], index["wall"])
        add_quad(bm, [(-x, y, 0), (x, y, 0), (x, y, z), (-x, y, z)], index["wall"])
        if skylight is None:
            add_quad(bm, [(-x, -y, z), (-x, y, z), (x, y, z), (x, -y, z)], index["ceiling"])
        else:  # four quads around the hole, facing down
            hx0 = skylight_centre[0] - skylight[0] / 2
            hx1 = skylight_centre[0] + skylight[0] / 2
            hy0 = skylight_centre[1] - skylight[1] / 2
            hy1 = skylight_centre[1] + skylight[1] / 2
            for (x0, y0, x1, y1) in [(-x, -y, hx0, y), (hx1, -y, x, y), (hx0, -y, hx1, hy0),
                                     (hx0, hy1, hx1, y)]:
                add_quad(bm, [(x0, y0, z), (x0, y1, z), (x1, y1, z), (x1, y0, z)],
                         index["ceiling"])
        bmesh.ops.remove_doubles(bm, verts=bm.verts, dist=1e-5)

    return build


def build_block(bm):
    bmesh.ops.create_cube(bm, size=1.0)
    bmesh.ops.scale(bm, vec=(0.8, 0.8, 1.0), verts=bm.verts)
    bmesh.ops.translate(bm, vec=(0.0, 0.0, 0.5), verts=bm.verts)


def build_panel(size):
    def build(bm):  # facing down (-Z)
        sx, sy = size[0] / 2, size[1] / 2
        add_quad(bm, [(-sx, -sy, 0), (-sx, sy, 0), (sx, sy, 0), (sx, -sy, 0)], 0)
    return build


def build_ball(radius):
    def build(bm):  # standing on z = 0, smooth-shaded
        bmesh.ops.create_uvsphere(bm, u_segments=48, v_segments=24, radius=radius)
        bmesh.ops.translate(bm, vec=(0.0, 0.0, radius), verts=bm.verts)
        for face in bm.faces:
            face.smooth = True
    return build


def build_box(size):
    def build(bm):  # a box standing on z = 0
        bmesh.ops.create_cube(bm, size=1.0)
        bmesh.ops.scale(bm, vec=size, verts=bm.verts)
        bmesh.ops.translate(bm, vec=(0.0, 0.0, size[2] / 2), verts=bm.verts)
    return build


def furnish(scene, block, material):
    """Linked duplicates (negative and uneven scales), Array and Mirror modifiers, collection
    instances; returns the objects whose meshes need UV maps (one per mesh)."""
    mirrored = block.copy()  # shares the block's mesh
    mirrored.location = (-1.2, -0.7, 0.0)
    mirrored.scale = (-0.7, 0.7, 0.6)  # mirrored: the winding flips
    uneven = block.copy()
    uneven.location = (1.3, -0.9, 0.0)
    uneven.scale = (0.4, 0.9, 0.5)
    uneven.rotation_euler = (0.0, 0.0, math.radians(-35.0))
    posts = mesh_object("Posts", build_box((0.12, 0.12, 1.1)), [material])
    posts.location = (-1.6, 0.9, 0.0)
    array = posts.modifiers.new("Array", "ARRAY")
    array.count = 3
    array.relative_offset_displace = (4.0, 0.0, 0.0)
    shelves = mesh_object("Shelves", build_box((0.5, 0.25, 0.04)), [material])
    shelves.data.transform(Matrix.Translation((0.6, 0.0, 0.0)))  # off its origin, so the
    shelves.location = (0.0, 1.35, 1.2)                           # mirror makes a second one
    mirror = shelves.modifiers.new("Mirror", "MIRROR")
    mirror.use_axis = (True, False, False)
    props = bpy.data.collections.new("Props")
    small = bpy.data.objects.new("Crate", bpy.data.meshes.new("Crate"))
    bm = bmesh.new()
    build_box((0.3, 0.3, 0.3))(bm)
    bm.to_mesh(small.data)
    bm.free()
    small.data.materials.append(material)
    props.objects.link(small)
    for location in ((-0.3, -1.0, 0.0), (0.9, 1.0, 0.0)):
        instance = bpy.data.objects.new("Props instance", None)
        instance.instance_type = "COLLECTION"
        instance.instance_collection = props
        instance.location = location
        scene.collection.objects.link(instance)
    for obj in (mirrored, uneven):
        scene.collection.objects.link(obj)
    # The crate is not in the scene: link it a moment for the UV operators, then unlink.
    scene.collection.objects.link(small)
    return [posts, shelves, small]


def add_uv_maps(obj):
    """"UVMap" by Smart UV Project and "Lightmap" by Lightmap Pack, as an artist would."""
    bpy.ops.object.select_all(action="DESELECT")
    obj.select_set(True)
    bpy.context.view_layer.objects.active = obj
    mesh = obj.data
    mesh.uv_layers.new(name="UVMap")
    mesh.uv_layers.new(name="Lightmap")
    bpy.ops.object.mode_set(mode="EDIT")
    bpy.ops.mesh.select_all(action="SELECT")
    mesh.uv_layers.active = mesh.uv_layers["UVMap"]
    bpy.ops.uv.smart_project(island_margin=0.02)
    mesh.uv_layers.active = mesh.uv_layers["Lightmap"]
    bpy.ops.uv.lightmap_pack(PREF_CONTEXT="ALL_FACES", PREF_MARGIN_DIV=0.3)
    bpy.ops.object.mode_set(mode="OBJECT")
    mesh.uv_layers["UVMap"].active_render = True
    mesh.uv_layers.active = mesh.uv_layers["UVMap"]


def look_at(obj, target):
    direction = Vector(target) - obj.location
    obj.rotation_euler = direction.to_track_quat("-Z", "Y").to_euler()


# ---------------------------------------------------------------------------------------------
# The scene


def write_world_image(path, image):
    """An equirect EXR in Blender's mapping: column u looks along azimuth (0.5 - u) x 360 deg
    from +X towards +Y, pixel row v (0 at the bottom) at elevation (v - 0.5) x 180 deg."""
    width, height = image["size"]
    glow_direction = Vector((math.cos(math.radians(image["glow_elevation"])) *
                             math.cos(math.radians(image["glow_azimuth"])),
                             math.cos(math.radians(image["glow_elevation"])) *
                             math.sin(math.radians(image["glow_azimuth"])),
                             math.sin(math.radians(image["glow_elevation"]))))
    pixels = []
    for row in range(height):
        elevation = ((row + 0.5) / height - 0.5) * math.pi
        for column in range(width):
            azimuth = (0.5 - (column + 0.5) / width) * 2.0 * math.pi
            d = Vector((math.cos(elevation) * math.cos(azimuth),
                        math.cos(elevation) * math.sin(azimuth), math.sin(elevation)))
            sky = max(0.0, d.z)
            angle = math.degrees(d.angle(glow_direction))
            glow = math.exp(-(angle / image["glow_width"]) ** 2)
            pixels += [sky * z + glow * g for z, g in zip(image["zenith"], image["glow"])] + [1.0]
    picture = bpy.data.images.new("world", width, height, float_buffer=True)
    # As data: saved as it is (a "Linear" image's EXR gets the sRGB curve applied: 6 -> 2.17).
    picture.colorspace_settings.is_data = True
    picture.pixels = pixels
    picture.filepath_raw = path
    picture.file_format = "OPEN_EXR"
    picture.save()


def build_scene(name, spec):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    materials = {n: principled(n, c) for n, c in MATERIALS.items()}
    room = mesh_object("Room", build_room(spec.get("skylight"), spec.get("skylight_centre",
                                                                          (0.0, 0.0))),
                       [materials[n] for n in ["floor", "ceiling", "wall", "red_wall",
                                               "green_wall"]])
    block = mesh_object("Block", build_block, [materials["block"]])
    block.location = (0.7, 0.35, 0.0)
    block.rotation_euler = (0.0, 0.0, math.radians(20.0))
    objects = [room, block]
    if "floor_texture" in spec:
        room.data.materials[0] = textured_material("checker_floor", spec["floor_texture"])
    if "normal_map" in spec:
        room.data.materials[4] = normal_mapped_material("ridged_green_wall",
                                                        MATERIALS["green_wall"],
                                                        spec["normal_map"])

    # A card under the skylight: foliage (alpha-clipped) or a pane (alpha-blended).
    for key, material in (("leaves", lambda c: leaf_material("leaves", (0.25, 0.45, 0.12),
                                                              c["cells"])),
                          ("pane", lambda c: pane_material("pane", (0.8, 0.85, 0.9),
                                                            c["alpha"]))):
        if key in spec:
            card = mesh_object(key.capitalize(), build_panel(spec[key]["size"]),
                               [material(spec[key])])
            card.location = (*spec["skylight_centre"], spec[key]["height"])
            objects.append(card)

    for kind_, ((x, y), radius) in spec.get("balls", {}).items():
        ball = mesh_object(kind_.capitalize(), build_ball(radius), [specular_material(kind_)])
        ball.location = (x, y, 0.0)
        objects.append(ball)

    kind = spec["kind"]
    if kind == "world":
        pass  # lit by the world alone (below)
    elif kind == "panel":
        emitter = principled("panel", (0.8, 0.8, 0.8), emission=(1.0, 1.0, 1.0),
                             strength=spec["strength"])
        panel = mesh_object("Panel", build_panel(spec["size"]), [emitter])
        panel.location = (-0.5, 0.2, spec["height"])
        objects.append(panel)
    else:
        light = bpy.data.lights.new(name.capitalize(), kind)
        light.energy = spec["energy"]
        if kind == "SUN":
            light.angle = 0.0  # a delta light, as glTF's directional light is
        else:
            light.shadow_soft_size = 0.0  # a point, as glTF's punctual lights are
        if kind == "SPOT":
            light.spot_size = math.radians(spec["spot_size_deg"])
            light.spot_blend = spec["spot_blend"]
            light.show_cone = True
        lamp = bpy.data.objects.new(name.capitalize(), light)
        scene.collection.objects.link(lamp)
        if kind == "SUN":
            lamp.location = (0.0, 0.0, ROOM[2] + 1.0)
            lamp.rotation_euler = Vector(spec["direction"]).to_track_quat("-Z", "Y").to_euler()
        else:
            lamp.location = spec["location"]
            if "target" in spec:
                look_at(lamp, spec["target"])

    furniture = furnish(scene, block, materials["props"]) \
        if spec.get("furnished") else []
    for obj in furniture:
        # Applied before the UVs are packed, as an artist preparing lightmap UVs does: packed
        # before, the copies of an Array or Mirror would share their texels (lightbake
        # would warn and unwrap them anew).
        bpy.context.view_layer.objects.active = obj
        for modifier in list(obj.modifiers):
            bpy.ops.object.modifier_apply(modifier=modifier.name)
    for obj in objects + furniture:
        add_uv_maps(obj)
    for obj in furniture:
        if obj.name == "Crate":
            scene.collection.objects.unlink(obj)  # placed by the collection instances alone

    camera_data = bpy.data.cameras.new("Camera")
    camera_data.lens = 18.0
    camera_data.sensor_width = 36.0
    camera_data.clip_start = 0.05
    camera = bpy.data.objects.new("Camera", camera_data)
    scene.collection.objects.link(camera)
    camera.location = (-1.75, -1.35, 1.6)
    look_at(camera, (1.2, 1.0, 0.7))
    scene.camera = camera

    world = bpy.data.worlds.new("World")  # black unless the scene is lit by its world
    world.use_nodes = True
    radiance = spec.get("world", (0.0, 0.0, 0.0))
    world.node_tree.nodes["Background"].inputs["Color"].default_value = (*radiance, 1.0)
    world.node_tree.nodes["Background"].inputs["Strength"].default_value = 1.0
    if "world_image" in spec:
        environment = world.node_tree.nodes.new("ShaderNodeTexEnvironment")
        environment.image = bpy.data.images.load(spec["world_image"]["path"])
        world.node_tree.links.new(environment.outputs["Color"],
                                  world.node_tree.nodes["Background"].inputs["Color"])
    scene.world = world

    return scene


def export_gltf(path):
    settings = dict(
        filepath=path,
        export_format="GLB",
        export_lights=True,
        export_cameras=True,
        export_yup=True,
        export_texcoords=True,
        export_normals=True,
        export_apply=True,
        convert_lighting_mode="SPEC",  # Standard: W -> cd / lx at 683 lm/W (docs/gltf.md)
    )
    bpy.ops.export_scene.gltf(**settings)
    return {k: v for k, v in settings.items() if k != "filepath"}


def cycles_settings(scene, width, height, samples):
    scene.render.engine = "CYCLES"
    cycles = scene.cycles
    cycles.device = "CPU"
    cycles.samples = samples
    cycles.use_animated_seed = False
    cycles.use_denoising = False
    cycles.use_adaptive_sampling = False
    cycles.max_bounces = 128  # Russian roulette ends paths long before this
    cycles.diffuse_bounces = 128
    cycles.glossy_bounces = 128
    cycles.transmission_bounces = 128
    cycles.sample_clamp_direct = 0.0  # no clamping: unbiased
    cycles.sample_clamp_indirect = 0.0
    cycles.light_sampling_threshold = 0.0
    cycles.pixel_filter_type = "BOX"  # each pixel its own square, as `lightbake render`
    cycles.filter_width = 1.0
    cycles.use_guiding = False
    scene.render.resolution_x = width
    scene.render.resolution_y = height
    scene.render.resolution_percentage = 100
    scene.render.film_transparent = False
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"
    scene.view_settings.exposure = 0.0
    scene.view_settings.gamma = 1.0
    scene.render.image_settings.file_format = "OPEN_EXR"
    scene.render.image_settings.color_mode = "RGB"
    scene.render.image_settings.color_depth = "32"
    scene.render.image_settings.exr_codec = "ZIP"
    return dict(device="CPU", samples_per_half=samples, denoising=False, adaptive=False,
                max_bounces=128, clamp=0, light_sampling_threshold=0, pixel_filter="BOX 1 px",
                view_transform="Standard", width=width, height=height)


def main():
    args = parse_args()
    width, height = (int(v) for v in args.size.lower().split("x"))
    os.makedirs(args.out_dir, exist_ok=True)
    spec = SCENES[args.scene]
    if "world_image" in spec:
        spec["world_image"]["path"] = os.path.join(args.out_dir, args.scene + "_sky.exr")
        write_world_image(spec["world_image"]["path"], spec["world_image"])
    scene = build_scene(args.scene, spec)
    import io_scene_gltf2
    record = dict(scene=args.scene, spec=spec, blender=bpy.app.version_string,
                  exporter=".".join(str(v) for v in io_scene_gltf2.bl_info["version"]),
                  shading=args.shading)
    # Before the export: the exporter writes the render size's aspect ratio into the camera.
    record["cycles"] = cycles_settings(scene, width, height, args.samples // 2)
    record["export"] = export_gltf(os.path.join(args.out_dir, args.scene + ".glb"))
    # The sky the file cannot carry, in a TOML file that includes it.
    if "world" in spec:
        with open(os.path.join(args.out_dir, args.scene + ".toml"), "w") as f:
            f.write(f'include = "{args.scene}.glb"\n\n[sky]\n'
                    f'radiance = [{", ".join(str(c) for c in spec["world"])}]'
                    '  # W/(sr m^2): the world\'s Background colour x strength 1\n')
    if "world_image" in spec:
        with open(os.path.join(args.out_dir, args.scene + ".toml"), "w") as f:
            f.write(f'include = "{args.scene}.glb"\n\n[sky]\n'
                    f'image = "{args.scene}_sky.exr"  # W/(sr m^2), strength 1\n'
                    'rotation = -90  # Blender\'s equirect mapping (Z up) to lightbake\'s\n')
    record_path = os.path.join(args.out_dir, f"{args.scene}_{args.shading}.json")
    if args.no_render:
        with open(record_path, "w") as f:
            json.dump(record, f, indent=1)
        return
    if args.shading == "lambert":
        for material in bpy.data.materials:
            replace_with_diffuse_bsdf(material)
    record["cycles"]["halves"] = []
    for half, seed in (("a", 1), ("b", 2)):
        scene.cycles.seed = seed
        scene.render.filepath = os.path.join(args.out_dir,
                                             f"{args.scene}_{args.shading}_{half}.exr")
        start_wall, start_cpu = time.time(), time.process_time()
        bpy.ops.render.render(write_still=True)
        record["cycles"]["halves"].append(dict(
            file=os.path.basename(scene.render.filepath), seed=seed,
            wall_seconds=round(time.time() - start_wall, 3),
            cpu_seconds=round(time.process_time() - start_cpu, 3)))
    with open(record_path, "w") as f:
        json.dump(record, f, indent=1)


main()
