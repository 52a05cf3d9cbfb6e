#!/usr/bin/env python3
"""Cross-check of lightbake against Mitsuba 3 on the bundled Cornell box (bench only, not ctest).

Writes the scene in Mitsuba 3's dict format *generated from our TOML file* (one source of
numbers: scenes/cornell_box.toml, itself read from mitsuba.cornell_box()), renders it with
Mitsuba's path tracer twice with different seeds (two independent halves give the noise), and
compares lightbake's image with the average using `lightbake compare`.

Conventions matched:
- radiance: Mitsuba's area emitter `radiance` is W/(sr m^2) per channel in the rgb variants,
  as our `emission`; 'rgb' values are used as they are (no spectral upsampling in *_rgb);
- pixel filter: box of one pixel (`rfilter = box`), as our stratified jitter inside the pixel;
- camera: our `fov` is vertical, so fov_axis = 'y'; look_at from position to target with up;
- glass: dielectric with ext_ior 1.0 (Mitsuba's default is air, 1.000277);
- integrator: `path` without a depth cut (max_depth -1, Russian roulette from depth 5).
Only what the Cornell scenes use is translated: quads (size, normal, translate), boxes (size,
rotate about Y, translate), spheres (analytic in Mitsuba, 32 x 64 triangles in ours).

Install once: python3 -m venv build/venv && build/venv/bin/pip install mitsuba
Run:          build/venv/bin/python bench/mitsuba/cornell_box.py [--spp 1024] [--ours OURS.exr]
"""

import argparse
import json
import math
import os
import subprocess
import sys
import time
import tomllib

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def colour(value):
    return [float(value)] * 3 if isinstance(value, (int, float)) else [float(v) for v in value]


def rotation_to(src, dst):
    """Rotation matrix taking unit vector src to dst, the same rule as scene_toml.cpp."""
    src = np.array(src, float) / np.linalg.norm(src)
    dst = np.array(dst, float) / np.linalg.norm(dst)
    c = float(src @ dst)
    if c > 0.999999:
        return np.eye(3)
    if c < -0.999999:
        axis = np.array([1.0, 0, 0]) if abs(src[0]) < 0.9 else np.array([0, 0, 1.0])
        return axis_angle(np.cross(src, axis), math.pi)
    return axis_angle(np.cross(src, dst), math.acos(c))


def axis_angle(axis, angle):
    x, y, z = np.array(axis, float) / np.linalg.norm(axis)
    c, s = math.cos(angle), math.sin(angle)
    return np.array([
        [c + x * x * (1 - c), x * y * (1 - c) - z * s, x * z * (1 - c) + y * s],
        [y * x * (1 - c) + z * s, c + y * y * (1 - c), y * z * (1 - c) - x * s],
        [z * x * (1 - c) - y * s, z * y * (1 - c) + x * s, c + z * z * (1 - c)]])


def euler(degrees):
    """Our `rotate = [x, y, z]`: about X, then Y, then Z (R = Rz Ry Rx)."""
    rx, ry, rz = (math.radians(d) for d in degrees)
    return (axis_angle([0, 0, 1], rz) @ axis_angle([0, 1, 0], ry) @ axis_angle([1, 0, 0], rx))


def affine(linear, translate):
    m = np.eye(4)
    m[:3, :3] = linear
    m[:3, 3] = translate
    return m


def load_scene(path):
    """Our TOML with its includes and `remove`, as the subset the Cornell scenes use."""
    with open(path, "rb") as f:
        doc = tomllib.load(f)
    materials, objects, cameras = {}, [], []
    includes = doc.get("include", [])
    for inc in [includes] if isinstance(includes, str) else includes:
        m, o, c = load_scene(os.path.join(os.path.dirname(path), inc))
        materials.update(m)
        objects += o
        cameras += c
    removed = set(doc.get("remove", []))
    objects = [o for o in objects if o.get("name") not in removed]
    materials.update(doc.get("materials", {}))
    for o in doc.get("objects", []):
        names = [x.get("name") for x in objects]
        if o.get("name") in names:
            objects[names.index(o["name"])] = o
        else:
            objects.append(o)
    cameras += doc.get("cameras", [])
    return materials, objects, cameras


def mitsuba_scene(scene_path, width, height, spp, seed, max_depth):
    import mitsuba as mi
    materials, objects, cameras = load_scene(scene_path)
    scene = {"type": "scene",
             "integrator": {"type": "path", "max_depth": max_depth}}
    for name, m in materials.items():
        kind = m.get("type", "diffuse")
        if kind == "diffuse":
            scene["mat_" + name] = {"type": "diffuse",
                           "reflectance": {"type": "rgb", "value": colour(m.get("reflectance", 0.8))}}
        elif kind == "glass":
            scene["mat_" + name] = {"type": "dielectric", "int_ior": float(m.get("ior", 1.5)),
                           "ext_ior": 1.0}
            if "transmittance" in m:
                scene["mat_" + name]["specular_transmittance"] = {"type": "rgb",
                                                         "value": colour(m["transmittance"])}
        else:
            sys.exit(f"{scene_path}: material {name}: type {kind} not translated")
    for i, o in enumerate(objects):
        name = o.get("name", f"objects[{i}]")
        shape = o["shape"]
        t = o.get("translate", [0, 0, 0])
        if shape == "quad":
            w, d = (o["size"], o["size"]) if isinstance(o.get("size", 1), (int, float)) else o["size"]
            r = rotation_to([0, 1, 0], o.get("normal", [0, 1, 0]))
            if "rotate" in o:
                r = euler(o["rotate"]) @ r
            # Mitsuba's rectangle: [-1, 1]^2 in its XY plane facing +z; ours: XZ facing +Y, so
            # local x -> X (w/2), local y -> -Z (d/2), local z -> +Y.
            local = np.array([[w / 2, 0, 0], [0, 0, 1], [0, -d / 2, 0]])
            entry = {"type": "rectangle", "to_world": mi.ScalarTransform4f(affine(r @ local, t))}
        elif shape == "box":
            size = o.get("size", 1)
            size = [size] * 3 if isinstance(size, (int, float)) else size
            r = euler(o.get("rotate", [0, 0, 0]))
            entry = {"type": "cube",
                     "to_world": mi.ScalarTransform4f(affine(r @ np.diag(np.array(size) / 2), t))}
        elif shape == "sphere":
            entry = {"type": "sphere", "center": [float(v) for v in t],
                     "radius": float(o.get("radius", 1))}
        else:
            sys.exit(f"{scene_path}: object {name}: shape {shape} not translated")
        material = materials[o["material"]]
        entry["bsdf"] = {"type": "ref", "id": "mat_" + o["material"]}
        if "emission" in material:
            entry["emitter"] = {"type": "area",
                                "radiance": {"type": "rgb", "value": colour(material["emission"])}}
        elif "power" in material:
            sys.exit(f"{scene_path}: material {o['material']}: give emission, not power")
        scene[name] = entry
    cam = cameras[0]
    scene["sensor"] = {
        "type": "perspective", "fov": float(cam.get("fov", 50)), "fov_axis": "y",
        "to_world": mi.ScalarTransform4f().look_at(origin=cam["position"], target=cam["target"],
                                                   up=cam.get("up", [0, 1, 0])),
        "sampler": {"type": "independent", "sample_count": spp, "seed": seed},
        "film": {"type": "hdrfilm", "width": width, "height": height, "rfilter": {"type": "box"},
                 "pixel_format": "rgb", "component_format": "float32"}}
    return scene


def lightbake(*args):
    return subprocess.run([os.path.join(ROOT, "build/app/lightbake"), *args], check=True,
                          capture_output=True, text=True).stdout


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scene", default=os.path.join(ROOT, "scenes/cornell_box.toml"))
    parser.add_argument("--size", default="256x256")
    parser.add_argument("--spp", type=int, default=1024, help="per half; the average has twice")
    parser.add_argument("--variant", default="scalar_rgb", help="scalar_rgb or llvm_ad_rgb")
    parser.add_argument("--max-depth", type=int, default=-1)
    parser.add_argument("--out", default=os.path.join(ROOT, "build/bench/mitsuba"))
    parser.add_argument("--ours", help="our image (linear EXR) to compare with Mitsuba's")
    parser.add_argument("--ours-b", help="a second, independent image of ours: its noise")
    parser.add_argument("--single", metavar="OUT.exr",
                        help="only render one image with --seed to OUT.exr (for the sweep)")
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()

    import mitsuba as mi
    mi.set_variant(args.variant)
    width, height = (int(v) for v in args.size.split("x"))
    if args.single:
        scene = mi.load_dict(mitsuba_scene(args.scene, width, height, args.spp, args.seed,
                                           args.max_depth))
        mi.Bitmap(mi.render(scene, seed=args.seed)).write(args.single)
        return
    os.makedirs(args.out, exist_ok=True)
    stem = os.path.splitext(os.path.basename(args.scene))[0]
    halves = []
    for seed in (0, 1):
        path = os.path.join(args.out, f"{stem}_mitsuba_{args.spp}spp_seed{seed}.exr")
        if not os.path.exists(path):
            scene = mi.load_dict(mitsuba_scene(args.scene, width, height, args.spp, seed,
                                               args.max_depth))
            start = time.process_time()
            image = mi.render(scene, seed=seed)
            mi.Bitmap(image).write(path)
            print(f"mitsuba {args.variant}: {path}, {time.process_time() - start:.1f} CPU s",
                  file=sys.stderr)
        halves.append(path)
    average = os.path.join(args.out, f"{stem}_mitsuba_{2 * args.spp}spp.exr")
    a, b = (np.array(mi.Bitmap(p), dtype=np.float64) for p in halves)
    mi.Bitmap(((a + b) / 2).astype(np.float32)).write(average)

    report = {"mitsuba": average, "mitsuba_spp": 2 * args.spp, "variant": args.variant,
              # Two independent halves: their difference is sqrt(2) times one half's noise and
              # 2 times the average's; the metrics of one half against the other measure that.
              "mitsuba_half_vs_half": json.loads(lightbake("compare", halves[0], halves[1]))}
    if args.ours:
        report["ours"] = args.ours
        report["ours_vs_mitsuba"] = json.loads(lightbake("compare", args.ours, average))
        error_png = os.path.join(args.out, f"{stem}_ours_vs_mitsuba.png")
        lightbake("compare", args.ours, average, "--error-image", error_png, "--error-max", "0.2")
        report["error_image"] = error_png
    if args.ours_b:
        report["ours_half_vs_half"] = json.loads(lightbake("compare", args.ours, args.ours_b))
    print(json.dumps(report, indent=1))


if __name__ == "__main__":
    main()
