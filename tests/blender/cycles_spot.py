#!/usr/bin/env python3
"""Rewrites a Blender-exported .glb so that its spot lamps carry Cycles' spot profile.

    cycles_spot.py IN.glb OUT.glb [--steps K]   ->  one JSON line on stdout

Blender's exporter writes a spot of size S and blend b as outerConeAngle = S / 2 and
innerConeAngle = (1 - b) S / 2, and the file is rendered with glTF's recommended falloff (the
square of a ramp linear in the cosine between the two angles). Cycles 3.4 renders the same lamp
with intensity I cos(theta) smoothstep((cos(theta) - cos(S/2)) / ((1 - cos(S/2)) b)) (its
kernel's spot_attenuation: a cosine falloff inside the whole cone, the blend measured in
cosine). The profiles differ, so the file alone cannot match Cycles' light; this file does,
within glTF: each spot becomes K nested spots on child nodes of its node (glTF allows one light
per node), spot k a near-hard cone at theta_k = k S / (2K) carrying the profile's drop over the
step (the midpoint rule: the staircase equals the profile at each step's middle), so their sum
is Cycles' profile in K steps. Rendering it checks that the profile is the only difference
(tests/blender/run_blender_check.sh); the JSON line gives the power of both profiles per unit
axis intensity, whose ratio explains the original file's light against Cycles (docs/gltf.md).
Standard library only.
"""

import argparse
import json
import math
import struct
import sys


def read_glb(path):
    data = open(path, "rb").read()
    magic, version, _ = struct.unpack_from("<III", data, 0)
    if magic != 0x46546C67 or version != 2:
        sys.exit(f"{path}: not a glTF 2 .glb")
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


def write_glb(path, gltf, binary):
    text = json.dumps(gltf, separators=(",", ":")).encode()
    text += b" " * (-len(text) % 4)
    binary += b"\0" * (-len(binary) % 4)
    body = struct.pack("<II", len(text), 0x4E4F534A) + text
    if binary:
        body += struct.pack("<II", len(binary), 0x004E4942) + binary
    with open(path, "wb") as f:
        f.write(struct.pack("<III", 0x46546C67, 2, 12 + len(body)) + body)


def smoothstep(x):
    x = min(max(x, 0.0), 1.0)
    return x * x * (3.0 - 2.0 * x)


def cycles_profile(theta, outer, blend):
    """Cycles 3.4's spot attenuation at angle theta from the axis."""
    cos_outer = math.cos(outer)
    c = math.cos(theta)
    if c <= cos_outer:
        return 0.0
    spread = (1.0 - cos_outer) * blend
    return c * (smoothstep((c - cos_outer) / spread) if spread > 0.0 else 1.0)


def gltf_profile(theta, inner, outer):
    """KHR_lights_punctual's recommended falloff, as lightbake renders it."""
    c, ci, co = math.cos(theta), math.cos(inner), math.cos(outer)
    if c >= ci:
        return 1.0
    if c <= co:
        return 0.0
    t = (c - co) / (ci - co)
    return t * t


def power(profile, outer, steps=20000):
    """Integral of the profile over the sphere, W per W/sr on the axis."""
    h = outer / steps
    return sum(profile((i + 0.5) * h) * 2.0 * math.pi * math.sin((i + 0.5) * h) * h
               for i in range(steps))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("input")
    parser.add_argument("output")
    parser.add_argument("--steps", type=int, default=24)
    args = parser.parse_args()
    gltf, binary = read_glb(args.input)
    lights = gltf.get("extensions", {}).get("KHR_lights_punctual", {}).get("lights", [])
    report = []
    for node in list(gltf.get("nodes", [])):
        extension = node.get("extensions", {}).get("KHR_lights_punctual")
        if extension is None or lights[extension["light"]].get("type") != "spot":
            continue
        spot = lights[extension["light"]]
        outer = spot["spot"].get("outerConeAngle", math.pi / 4)
        inner = spot["spot"].get("innerConeAngle", 0.0)
        blend = 1.0 - inner / outer  # the exporter's inner = (1 - blend) outer, inverted
        axis_intensity = spot.get("intensity", 1.0)
        del node["extensions"]["KHR_lights_punctual"]
        if not node["extensions"]:
            del node["extensions"]
        step = outer / args.steps
        epsilon = 0.02 * step
        children = node.setdefault("children", [])
        for k in range(1, args.steps + 1):
            # The staircase drops at theta_k from the profile at the middle of step k to the
            # profile at the middle of step k + 1 (0 past the cone).
            here = cycles_profile((k - 0.5) * step, outer, blend)
            after = cycles_profile((k + 0.5) * step, outer, blend) if k < args.steps else 0.0
            if here - after <= 0.0:
                continue
            lights.append({
                "name": f"{spot.get('name', 'spot')}/{k}",
                "type": "spot",
                "color": spot.get("color", [1.0, 1.0, 1.0]),
                "intensity": axis_intensity * (here - after),
                "spot": {"innerConeAngle": k * step - epsilon,
                         "outerConeAngle": k * step + epsilon},
            })
            gltf["nodes"].append({"name": f"{node.get('name', 'spot')}/{k}", "extensions": {
                "KHR_lights_punctual": {"light": len(lights) - 1}}})
            children.append(len(gltf["nodes"]) - 1)
        report.append({
            "node": node.get("name"), "outer_deg": math.degrees(outer),
            "inner_deg": math.degrees(inner), "blend": blend, "steps": args.steps,
            "cycles_power_per_axis_w_sr": power(lambda t: cycles_profile(t, outer, blend), outer),
            "gltf_power_per_axis_w_sr": power(lambda t: gltf_profile(t, inner, outer), outer),
        })
        report[-1]["gltf_over_cycles"] = (report[-1]["gltf_power_per_axis_w_sr"] /
                                          report[-1]["cycles_power_per_axis_w_sr"])
    write_glb(args.output, gltf, binary)
    print(json.dumps({"spots": report}))


if __name__ == "__main__":
    main()
