#!/usr/bin/python3
"""Scaling: bake and render CPU seconds against triangles, lights and map resolution, with
fitted exponents (bench only, not ctest).

    /usr/bin/python3 bench/scaling.py --quick     # minutes: up to 100k triangles, 30 lights
    /usr/bin/python3 bench/scaling.py             # 10k..1M triangles, 1..100 lights
    /usr/bin/python3 bench/scaling.py --level --quick   # the big level: 100k, 300k, 1M
    /usr/bin/python3 bench/scaling.py --level           # ... and 3M (--level-max 1e7: 10M)

Scenes are generated from scenes/room_no_ball.toml under build/bench/scaling/:
  triangles  + a diffuse sphere of rings x 2 rings segments (4 rings^2 triangles)
  lights     the ceiling light replaced by N lights of 150/N W each on a grid
  map        scenes/room.toml (glass ball: a caustic) at texel sizes 4 cm .. 5 mm
Each point: `lightbake bake` then `lightbake render DIR --size 320x240 --spp 16`, CPU seconds
(user + sys, os.wait4), and the bake's peak resident memory from its manifest, whose slopes
against triangles and texels are the memory per triangle and per texel
(bench/results/scaling_memory.txt). The exponent b of a least-squares fit t = a x^b in log-log
is printed and written beside the CSV (bench/results/scaling.csv) and the chart (scaling.png).

`--level` (issue 16): the generated level of bench/make_level.py (10 x 10 rooms, 100 lights,
mirrors, glass, instanced furniture) at N triangles; per point bench/geometry_stages (CPU s of
each geometry stage) and `lightbake bake` (CPU s, peak memory and each pass's seconds from the
manifest); bench/results/scaling_level.csv and scaling_level.txt with the fitted exponent of
bake CPU s against triangles. No render.
"""

import argparse
import csv
import json
import math
import os
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from speed_accuracy import LIGHTBAKE, ROOT, run  # noqa: E402


def write(path, text):
    with open(path, "w") as f:
        f.write(text)
    return path


def triangle_scene(work, rings):
    return write(os.path.join(work, f"triangles_{rings}.toml"), f"""
include = "{ROOT}/scenes/room_no_ball.toml"
[materials]
grey = {{ reflectance = 0.6 }}
[[objects]]
name = "dense_sphere"
shape = "sphere"
radius = 0.45
rings = {rings}
segments = {2 * rings}
translate = [0.6, 0.45, -0.2]
material = "grey"
""")


def light_scene(work, count):
    side = math.ceil(math.sqrt(count))
    text = f"""
include = "{ROOT}/scenes/room_no_ball.toml"
remove = ["light"]
[materials]
small_light = {{ reflectance = 0.0, power = {150.0 / count:.6g} }}
"""
    for i in range(count):
        x = -1.5 + 3.0 * ((i % side) + 0.5) / side
        z = -1.5 + 3.0 * ((i // side) + 0.5) / side
        text += f"""
[[objects]]
name = "light{i}"
shape = "quad"
size = 0.2
normal = [0, -1, 0]
translate = [{x:.4f}, 2.98, {z:.4f}]
material = "small_light"
"""
    return write(os.path.join(work, f"lights_{count}.toml"), text)


def measure(scene, work, name, bake_args=()):
    bake_dir = os.path.join(work, "bake_" + name)
    bake_cpu, _, bake_mem, _ = run([LIGHTBAKE, "bake", scene, "-o", bake_dir, "-q", *bake_args])
    image = os.path.join(work, name + ".exr")
    render_cpu, _, render_mem, _ = run([LIGHTBAKE, "render", scene, bake_dir, "--size",
                                        "320x240", "--spp", "16", "-o", image, "-q"])
    with open(os.path.join(bake_dir, "manifest.json")) as f:
        memory = json.load(f)["memory"]  # the bake's own peak and what it held
    return bake_cpu, render_cpu, max(bake_mem, render_mem), memory


def slope(xs, ys):
    """Least-squares slope of y = a + b x: the marginal cost of one more x."""
    mx, my = sum(xs) / len(xs), sum(ys) / len(ys)
    return (sum((x - mx) * (y - my) for x, y in zip(xs, ys)) /
            sum((x - mx) ** 2 for x in xs))


def memory_report(rows):
    """Bytes per triangle and per texel: the slope of the bake's peak resident memory against
    the scene's triangles (triangle axis) and the atlas's texels (texel axis)."""
    lines = []
    for axis, key, unit in (("triangles", "triangles", "triangle"), ("texel_size_m", "texels",
                                                                     "texel")):
        pts = [r for r in rows if r["axis"] == axis]
        xs = [r[key] for r in pts]
        ys = [r["bake_peak_bytes"] for r in pts]
        lines.append(f"bake peak memory: {slope(xs, ys):.0f} bytes per {unit} "
                     f"({min(xs):.0f}..{max(xs):.0f} {key}; "
                     f"{min(ys) / 2**20:.0f}..{max(ys) / 2**20:.0f} MiB)")
    return "\n".join(lines) + "\n"


def fit(xs, ts):
    """Exponent b of t = a x^b, least squares in log-log."""
    lx = [math.log(x) for x in xs]
    lt = [math.log(t) for t in ts]
    mx, mt = sum(lx) / len(lx), sum(lt) / len(lt)
    return (sum((a - mx) * (b - mt) for a, b in zip(lx, lt)) /
            sum((a - mx) ** 2 for a in lx))


def level_point(work, triangles):
    """One point of the level series: geometry stages, then the default bake."""
    scene = os.path.join(work, f"level_{triangles}.toml")
    subprocess.run(["/usr/bin/python3", os.path.join(ROOT, "bench/make_level.py"), "--triangles",
                    str(triangles), "-o", scene], check=True, capture_output=True)
    stages = subprocess.run([os.path.join(ROOT, "build/bench/geometry_stages"), scene],
                            check=True, capture_output=True, text=True).stdout
    row = dict(target=triangles)
    for line in stages.splitlines():  # "name   0.123 CPU s"
        words = line.split()
        if len(words) >= 4 and words[-2:] == ["CPU", "s"]:
            row["geometry_" + "_".join(words[:-3])] = float(words[-3])
        elif "patches of" in line:
            row["patches"] = int(line.split(" patches of")[0].split()[-1])
    bake_dir = os.path.join(work, f"bake_level_{triangles}")
    cpu, wall, _, _ = run([LIGHTBAKE, "bake", scene, "-o", bake_dir, "-q"])
    with open(os.path.join(bake_dir, "manifest.json")) as f:
        manifest = json.load(f)
    row.update(triangles=manifest["memory"]["triangles"], bake_cpu=cpu, bake_wall=wall,
               peak_bytes=manifest["memory"]["peak_resident_bytes"],
               illumination_s=manifest["illumination"]["seconds"],
               radiosity_s=manifest["radiosity"]["seconds"],
               radiosity_setup_s=manifest["radiosity"]["stats"].get("setup_seconds", 0.0),
               soft_light_s=manifest.get("soft_light", {}).get("seconds", 0.0))
    print(f"level {row['triangles']:>9d} triangles: bake {cpu:7.1f} CPU s, "
          f"{row['peak_bytes'] / 2**30:.2f} GiB, patches {row.get('patches')} "
          f"({row.get('geometry_patches', 0):.2f} CPU s)", file=sys.stderr)
    return row


def level_series(args):
    work = os.path.join(ROOT, "build/bench/scaling")
    os.makedirs(work, exist_ok=True)
    os.makedirs(args.out, exist_ok=True)
    sizes = [s for s in (100_000, 300_000, 1_000_000, 3_000_000, 10_000_000)
             if s <= (1_000_000 if args.quick else args.level_max)]
    done = {}
    if args.level_resume and os.path.exists(os.path.join(args.out, "scaling_level.csv")):
        with open(os.path.join(args.out, "scaling_level.csv")) as f:
            done = {int(r["target"]): {k: float(v) for k, v in r.items() if v != ""}
                    for r in csv.DictReader(f)}
    rows = [done[n] if n in done else level_point(work, n) for n in sizes]
    keys = sorted({k for r in rows for k in r}, key=lambda k: (k not in rows[0], k))
    with open(os.path.join(args.out, "scaling_level.csv"), "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=keys)
        writer.writeheader()
        writer.writerows(rows)
    xs = [r["triangles"] for r in rows]
    lines = ["bench/scaling.py --level" + (" --quick" if args.quick else
                                           f" --level-max {args.level_max:g}")]
    for key in ("bake_cpu", "geometry_patches"):
        ts = [r[key] for r in rows]
        lines.append(f"{key}: exponent {fit(xs, ts):.3f} against triangles "
                     f"({xs[0]:.0f}..{xs[-1]:.0f}; {ts[0]:.2f}..{ts[-1]:.2f} CPU s)")
    lines.append(f"bake peak memory: {slope(xs, [r['peak_bytes'] for r in rows]):.0f} bytes per "
                 f"triangle ({rows[0]['peak_bytes'] / 2**20:.0f}.."
                 f"{rows[-1]['peak_bytes'] / 2**20:.0f} MiB)")
    report = "\n".join(lines) + "\n"
    print(report, end="", file=sys.stderr)
    write(os.path.join(args.out, "scaling_level.txt"), report)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--level", action="store_true", help="the generated big level series")
    parser.add_argument("--level-max", type=float, default=3e6,
                        help="largest level in triangles without --quick (1e7 adds 10M)")
    parser.add_argument("--level-resume", action="store_true",
                        help="keep the points already in scaling_level.csv (same build)")
    parser.add_argument("--out", default=os.path.join(ROOT, "bench/results"))
    parser.add_argument("--charts-only", action="store_true", help="redraw from scaling.csv")
    args = parser.parse_args()
    if args.charts_only:
        with open(os.path.join(args.out, "scaling.csv")) as f:
            rows = [{k: (v if k == "axis" else float(v)) for k, v in r.items()}
                    for r in csv.DictReader(f)]
        return draw(rows, args.out)
    if args.level:
        return level_series(args)
    work = os.path.join(ROOT, "build/bench/scaling")
    os.makedirs(work, exist_ok=True)
    os.makedirs(args.out, exist_ok=True)
    rings = [50, 90, 158] if args.quick else [50, 90, 158, 280, 500]
    lights = [1, 3, 10, 30] if args.quick else [1, 3, 10, 30, 100]
    texels = [0.04, 0.02, 0.01] if args.quick else [0.04, 0.02, 0.01, 0.005]
    rows = []
    def row(axis, x, measured):
        b, t, m, memory = measured
        return dict(axis=axis, x=x, bake_cpu=b, render_cpu=t, mem_mb=m,
                    bake_peak_bytes=memory["peak_resident_bytes"],
                    triangles=memory["triangles"], texels=memory["texels"])
    for r in rings:
        rows.append(row("triangles", 4 * r * r + 26,
                        measure(triangle_scene(work, r), work, f"tri{r}")))
    for n in lights:
        rows.append(row("lights", n, measure(light_scene(work, n), work, f"lights{n}")))
    for s in texels:
        # room.toml's atlas: its texel count grows as 1 / texel_size^2
        rows.append(row("texel_size_m", s, measure(os.path.join(ROOT, "scenes/room.toml"), work,
                                                   f"texel{s}", ["--texel-size", str(s)])))
    for row in rows:
        print(f"{row['axis']:13s} {row['x']:>10g}  bake {row['bake_cpu']:6.2f} CPU s  "
              f"render {row['render_cpu']:6.2f} CPU s  {row['mem_mb']:6.0f} MB", file=sys.stderr)
    with open(os.path.join(args.out, "scaling.csv"), "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    report = memory_report(rows)
    print(report, end="", file=sys.stderr)
    write(os.path.join(args.out, "scaling_memory.txt"), report)
    draw(rows, args.out)


def draw(rows, out):
    """One panel per axis; the legend gives the exponent fitted over all points and the one
    between the two largest (the fixed cost of a run, ~0.5 CPU s, flattens the first)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 3, figsize=(11, 3.6), dpi=100)
    for ax, axis, label in zip(axes, ["triangles", "lights", "texel_size_m"],
                               ["triangles", "lights", "texel size (m)"]):
        pts = [r for r in rows if r["axis"] == axis]
        xs = [r["x"] for r in pts]
        for key, colour in (("bake_cpu", "tab:blue"), ("render_cpu", "tab:orange")):
            ts = [r[key] for r in pts]
            b = fit(xs, ts)
            top = sorted(zip(xs, ts))[-2:]
            b_top = math.log(top[1][1] / top[0][1]) / math.log(top[1][0] / top[0][0])
            ax.plot(xs, ts, "o-", color=colour,
                    label=f"{key.split('_')[0]}: exponent {b:.2f} (top two {b_top:.2f})")
            print(f"{axis}: {key} exponent {b:.3f}, between the top two points {b_top:.3f}",
                  file=sys.stderr)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel(label)
        ax.set_ylabel("CPU seconds")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
    fig.suptitle("scaling (room, 320x240, 16 spp, default bake)", fontsize=9)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "scaling.png"))


if __name__ == "__main__":
    main()
