#!/usr/bin/python3
"""Light groups (issue 39): what one bake of every group costs, and whether its blend is the
bake of the scaled scene.

    /usr/bin/python3 bench/light_groups.py [--quality standard] [--threads 2]

A 4 x 3 x 4 m room (albedo 0.75, a block, a glass ball for caustics) lit by four 0.5 m ceiling
panels, written four ways:
  one     no groups (the panels 60, 60, 20, 20 W);
  four    each panel its own group, same powers;
  two     panels 1-2 `day`, 3-4 `night`, same powers;
  scaled  no groups, the powers times (day 0.3, night 2): 18, 18, 40, 40 W.
Reports:
  cpu        CPU seconds (user + sys of the child, os.wait4) of `bake` for one and four, and
             their ratio (target <= 1.5);
  memory     the children's peak resident set (ru_maxrss), the bake directories' bytes, and the
             target: four's peak may exceed one's by no more than the four groups' own maps
             (a caustic and a soft-light map each: 2 x 4 x texels x 12 B, as float RGB) and
             vertex radiance (the groupN_radiosity.bin files' bytes);
  linearity  `snapshot --terms radiosity` and `--terms caustic` of two's bake (seed 1) with
             --group-weights day=0.3,night=2 against scaled's bake (seed 2), and of scaled's
             bake with seed 3 against seed 2 (the seed-to-seed noise): `lightbake compare`'s
             mean relative error and sum ratio (targets: MRE <= 1.5%, energy within 0.5%).
"""

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

PANELS = [(-0.8, -0.8), (0.8, -0.8), (-0.8, 0.8), (0.8, 0.8)]


def scene_text(powers, groups):
    lines = ["[materials]", "white = { reflectance = 0.75 }", 'glass = { type = "glass" }']
    for k, (power, group) in enumerate(zip(powers, groups)):
        group_key = f', group = "{group}"' if group else ""
        lines.append(f"panel{k} = {{ reflectance = 0.0, power = {power}{group_key} }}")
    lines += ['[[objects]]', 'name = "room"', 'shape = "box"', "min = [-2, 0, -2]",
              "max = [2, 3, 2]", "inward = true", 'material = "white"',
              '[[objects]]', 'name = "block"', 'shape = "box"', "size = [0.8, 0.8, 0.8]",
              "translate = [-0.8, 0.4, -0.6]", 'material = "white"',
              '[[objects]]', 'name = "ball"', 'shape = "sphere"', "radius = 0.4",
              "translate = [0.7, 0.4, 0.3]", 'material = "glass"']
    for k, (x, z) in enumerate(PANELS):
        lines += ['[[objects]]', f'name = "panel{k}"', 'shape = "quad"', "size = [0.5, 0.5]",
                  "normal = [0, -1, 0]", f"translate = [{x}, 2.98, {z}]",
                  f'material = "panel{k}"']
    lines += ['[[cameras]]', 'name = "view"', "position = [0, 1.5, 1.95]",
              "target = [0, 0.8, -1]", "fov = 60"]
    return "\n".join(lines) + "\n"


def run(command):
    """Runs COMMAND; returns its stdout."""
    process = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    out, err = process.communicate()
    if process.returncode != 0:
        sys.exit(f"failed ({process.returncode}): {' '.join(command)}\n{err}")
    return out


def timed(command):
    """Runs COMMAND; returns (CPU seconds, peak resident MiB) of the child."""
    pid = os.fork()
    if pid == 0:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, 1)
        os.execv(command[0], command)
    _, status, usage = os.wait4(pid, 0)
    if os.waitstatus_to_exitcode(status) != 0:
        sys.exit(f"failed: {' '.join(command)}")
    return usage.ru_utime + usage.ru_stime, usage.ru_maxrss / 1024.0


def directory_bytes(path):
    return sum(os.path.getsize(os.path.join(path, f)) for f in os.listdir(path))


def group_data_mib(bake_dir):
    """The bake's light groups' own maps and vertex radiance in memory, MiB: per group a
    caustic and a soft-light map of float RGB texels, and its vertex radiance."""
    with open(os.path.join(bake_dir, "manifest.json")) as f:
        manifest = json.load(f)
    groups = len(manifest.get("light_groups", []))
    texels = manifest["illumination"]["width"] * manifest["illumination"]["height"]
    maps = 2 * groups * texels * 12
    vertices = sum(os.path.getsize(os.path.join(bake_dir, name))
                   for name in os.listdir(bake_dir) if name.endswith("_radiosity.bin"))
    return maps / 2**20, vertices / 2**20


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--binary", default=os.path.join(ROOT, "build/app/lightbake"))
    parser.add_argument("--quality", default="standard")
    parser.add_argument("--threads", default="2")
    args = parser.parse_args()
    work = tempfile.mkdtemp(prefix="light_groups_")
    powers = [60, 60, 20, 20]
    variants = {
        "one": (powers, [None] * 4),
        "four": (powers, ["g1", "g2", "g3", "g4"]),
        "two": (powers, ["day", "day", "night", "night"]),
        "scaled": ([0.3 * p for p in powers[:2]] + [2.0 * p for p in powers[2:]], [None] * 4),
    }
    scenes = {}
    for name, (p, g) in variants.items():
        scenes[name] = os.path.join(work, name + ".toml")
        with open(scenes[name], "w") as f:
            f.write(scene_text(p, g))

    def bake(name, seed=1):
        out = os.path.join(work, f"{name}_{seed}")
        cpu, rss = timed([args.binary, "bake", scenes[name], "-o", out, "-q", "--force",
                          "--quality", args.quality, "--seed", str(seed),
                          "--threads", args.threads])
        return out, cpu, rss

    one, cpu_one, rss_one = bake("one")
    four, cpu_four, rss_four = bake("four")
    maps_mib, vertex_mib = group_data_mib(four)
    two, _, _ = bake("two")
    # The references with seeds of their own: the blend (seed 1) shares no random stream with
    # them, so their difference is noise plus whatever the blend gets wrong.
    scaled1, _, _ = bake("scaled", 2)
    scaled2, _, _ = bake("scaled", 3)
    result = {
        "quality": args.quality,
        "cpu_seconds": {"one": round(cpu_one, 2), "four": round(cpu_four, 2),
                        "ratio": round(cpu_four / cpu_one, 3)},
        "peak_resident_mib": {"one": round(rss_one, 1), "four": round(rss_four, 1),
                              "growth": round(rss_four - rss_one, 1),
                              "groups_maps": round(maps_mib, 1),
                              "groups_vertex_radiance": round(vertex_mib, 2),
                              "target_met": rss_four - rss_one <= maps_mib + vertex_mib},
        "bake_bytes": {"one": directory_bytes(one), "four": directory_bytes(four)},
        "linearity": {},
    }
    for term in ("radiosity", "caustic"):
        def snap(scene, bake_dir, name, extra):
            image = os.path.join(work, f"{name}_{term}.exr")
            run([args.binary, "snapshot", scene, bake_dir, "--terms", term, "--size", "320x240",
                 "-o", image, "-q", "--force"] + extra)
            return image
        blend = snap(scenes["two"], two, "blend", ["--group-weights", "day=0.3,night=2"])
        ref = snap(scenes["scaled"], scaled1, "scaled1", [])
        other = snap(scenes["scaled"], scaled2, "scaled2", [])
        result["linearity"][term] = {
            "blend_vs_scaled": json.loads(run([args.binary, "compare", blend, ref])),
            "seed_to_seed": json.loads(run([args.binary, "compare", other, ref])),
        }
    print(json.dumps(result, indent=1))
    shutil.rmtree(work)  # the scenes, bakes and frames (some 150 MB)


if __name__ == "__main__":
    main()
