#!/usr/bin/python3
"""The exported lightmap at game texel densities (issue 36): error against a converged reference
and light leaking through a 1 mm wall, drawn from the exported file alone.

    /usr/bin/python3 bench/lightmap_density.py                    # Cornell box + house, ~5 min
                                  # (+ ~45 CPU min for the reference's renders, once: cached)
    /usr/bin/python3 bench/lightmap_density.py --densities 10,20 --binaries before=/tmp/old

For each texel density (texels/m; 0 = the automatic rule) and binary it bakes, exports with
`--contents all`, draws the file alone (`snapshot out.glb --terms baked`, which the three.js
check shows equal to what a browser draws) and reports:
  cornell  MRE over the Cornell box's diffuse pixels (reference red < 0.6 W/(sr m^2), less one
           pixel around the rest, as bench/speed_accuracy.py) against the mean of `lightbake
           reference` renders --reference SEED:SPP,... (cached under build/bench/references/,
           bench/converged_reference.py), whose own noise the last two renders' difference
           measures (reference_mre); and the relative RMS error less that noise in quadrature
           (cornell_rel_rms_less_noise: the error against the truth);
  leak     a closed 4 x 3 x 2 m house split at x = 2 by a 1 mm wall, one light on the x < 2
           side: mean baked radiance of the dark side's texels over the lit side's, read
           straight from the exported EXR lightmap (texels of the house's own mesh whose
           surface lies at x < 1.99 or x > 2.01).
CPU seconds are user + sys of the children (os.wait4), so other load does not count.
"""

import argparse
import json
import os
import subprocess
import sys
import tempfile

from converged_reference import against, converged_reference, parse_renders

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DIFFUSE_MASK_BELOW = 0.6  # W/(sr m^2): the Cornell box's diffuse pixels peak at 0.46

HOUSE_TOML = """
# A closed 4 x 3 x 2 m house split at x = 2 by a 1 mm wall; one light on the x < 2 side.
[materials]
white = { reflectance = 0.75 }
light = { reflectance = 0.75, emission = 10.0 }

[[objects]]
name = "house"
shape = "box"
min = [0.0, 0.0, 0.0]
max = [4.0, 3.0, 2.0]
inward = true
material = "white"

[[objects]]
name = "wall"
shape = "box"
min = [2.0, 0.0, 0.0]
max = [2.001, 3.0, 2.0]
material = "white"

[[objects]]
name = "light"
shape = "quad"
corner = [0.6, 2.99, 0.6]
edge_u = [0.8, 0.0, 0.0]
edge_v = [0.0, 0.0, 0.8]
material = "light"

[[cameras]]
name = "dark side"
position = [3.8, 1.5, 1.0]
target = [2.0, 1.5, 1.0]
fov = 90
"""


def run(command):
    """Runs COMMAND, returns (CPU seconds of the child, stdout)."""
    process = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    _, status, usage = os.wait4(process.pid, 0)
    out = process.stdout.read()
    err = process.stderr.read()
    if os.waitstatus_to_exitcode(status) != 0:
        sys.exit(f"failed ({status}): {' '.join(command)}\n{err}")
    return usage.ru_utime + usage.ru_stime, out


def export(binary, scene, density, work, name):
    bake = os.path.join(work, name + "_bake")
    glb = os.path.join(work, name + ".glb")
    density_args = ["--texel-density", str(density)] if density > 0 else []
    cpu_bake, _ = run([binary, "bake", scene, "-o", bake, "-q", "--force"] + density_args)
    cpu_export, _ = run([binary, "export", scene, bake, "-o", glb, "--contents", "all", "-q",
                         "--force"])
    return glb, cpu_bake + cpu_export


def cornell(binary, density, work, name, reference, mask, reference_noise):
    scene = os.path.join(ROOT, "scenes/cornell_box.toml")
    glb, cpu = export(binary, scene, density, work, name)
    image = os.path.join(work, name + ".exr")
    run([binary, "snapshot", glb, "--terms", "baked", "--size", "256x256", "-o", image, "-q",
         "--force"])
    _, out = run([binary, "compare", image, reference, "--mask", mask])
    return json.loads(out)["mre"], against(image, reference, mask, reference_noise), cpu


def house_leak(binary, density, work, name, house):
    glb, cpu = export(binary, house, density, work, name)
    # The lightmap texels of the house's own surface, split by side (numpy reads the EXR
    # through OpenImageIO's Python module where present, else oiiotool dumps it).
    lightmap = glb[:-4] + ".lightmap.exr"
    script = os.path.join(ROOT, "bench/lightmap_sides.py")
    _, out = run([sys.executable, script, glb, lightmap, "house", "2.0", "0.01"])
    sides = json.loads(out)
    return sides["dark"] / sides["lit"], cpu


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--densities", default="5,10,20,0")
    parser.add_argument("--binaries", default="now=" + os.path.join(ROOT, "build/app/lightbake"),
                        help="NAME=PATH,... (one run of each)")
    parser.add_argument("--reference", default="1000:4096,2001:8192,2002:8192",
                        help="SEED:SPP,...: independent renders averaged (two or more: their "
                        "noise measured)")
    parser.add_argument("--work", default=None)
    args = parser.parse_args()
    binaries = dict(item.split("=", 1) for item in args.binaries.split(","))
    densities = [int(d) for d in args.densities.split(",")]
    work = args.work or tempfile.mkdtemp(prefix="lightmap_density_")
    os.makedirs(work, exist_ok=True)
    refs = os.path.join(ROOT, "build/bench/references")
    os.makedirs(refs, exist_ok=True)
    first = next(iter(binaries.values()))
    cornell_scene = os.path.join(ROOT, "scenes/cornell_box.toml")
    reference, noise_of = converged_reference(run, first, cornell_scene, "256x256",
                                              parse_renders(args.reference), refs)
    mask = reference[:-4] + "_diffuse_mask.png"
    if not os.path.exists(mask):
        subprocess.run(["oiiotool", reference, "--ch", "R", "--subc", str(DIFFUSE_MASK_BELOW),
                        "--mulc", "1e6", "--clamp:min=0:max=1", "--dilate", "3x3", "--mulc",
                        "-1", "--addc", "1", "-d", "uint8", "-o", mask], check=True)
    reference_noise = noise_of(mask) if noise_of else {"mre": 0.0, "relmse": 0.0}
    house = os.path.join(work, "house.toml")
    with open(house, "w") as f:
        f.write(HOUSE_TOML)
    print("binary,texels_per_m,cornell_diffuse_mre,cornell_rel_rms_less_noise,reference_mre,"
          "cornell_cpu_s,house_dark_over_lit,house_cpu_s")
    for name, binary in binaries.items():
        for density in densities:
            tag = f"{name}_{density}"
            mre, errors, cpu_c = cornell(binary, density, work, "cornell_" + tag, reference, mask,
                                         reference_noise)
            leak, cpu_h = house_leak(binary, density, work, "house_" + tag, house)
            print(f"{name},{density},{mre:.4f},{errors['rel_rms_less_noise']:.4f},"
                  f"{reference_noise['mre']:.4f},{cpu_c:.2f},{leak:.5f},{cpu_h:.2f}", flush=True)


if __name__ == "__main__":
    main()
