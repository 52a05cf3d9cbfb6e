#!/usr/bin/python3
"""Speed against accuracy: sweeps the settings that matter, measures CPU seconds and error
against a converged reference, writes a CSV and log-log charts (bench only, not ctest).

    /usr/bin/python3 bench/speed_accuracy.py --quick   # ~10 min first, ~4 min cached
    /usr/bin/python3 bench/speed_accuracy.py --level medium --scenes cornell_box  # bench/results/
    /usr/bin/python3 bench/speed_accuracy.py --level full           # every scene, long

For each scene and each run it records the settings, CPU seconds (user + sys of the child
processes, from os.wait4, so other load on this shared machine does not count), wall seconds,
rays (from the bake manifest and the render report), peak memory (ru_maxrss of the child) and
the metrics of `lightbake compare` against the scene's reference (MRE, relMSE, RMSE, sum ratio;
for cornell_glass also inside the caustic's region).

Series (one chart per scene, error against CPU seconds, Pareto front drawn, default starred):
  raster     bake (varied settings) + `lightbake snapshot` (the OpenGL viewer, OSMesa)
  hq         bake (varied settings) + `lightbake render` at varied spp
  hq_gather  the default bake + `lightbake render --final-gather=N` (soft light gathered from
             the bake instead of interpolated vertex radiosity) at varied spp
  reference  the reference renderer alone at increasing spp
  mitsuba    with --mitsuba-series (Cornell scenes): Mitsuba 3 alone, an extra series
The reference image (REFERENCE below: one place to change) is rendered once per scene, size and
sample count and cached under build/bench/references/.
"""

import argparse
import csv
import importlib
import json
import math
import os
import shutil
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
# LIGHTBAKE=path runs another binary (a copy, so that build/ may be rebuilt during a sweep).
LIGHTBAKE = os.environ.get("LIGHTBAKE", os.path.join(ROOT, "build/app/lightbake"))
VENV_PYTHON = os.path.join(ROOT, "build/venv/bin/python")
MITSUBA_SCRIPT = os.path.join(ROOT, "bench/mitsuba/cornell_box.py")

SCENES = {  # name: (image size, caustic region or None)
    "cornell_box": ("256x256", None),
    "cornell_glass": ("256x256", "52,224,84,244"),
    "room": ("320x240", None),
    "room_two_blocks": ("320x240", None),
    "fig3_ring": ("320x240", None),
    "fig4_plates": ("320x240", None),
    "fig5_nine_lights": ("320x240", None),
    "fig6_bump": ("320x240", None),
    "fig7_glass": ("320x240", None),
}
# Scenes whose only non-diffuse pixels are the emitter's: the `diffuse_*` columns compare the
# pixels whose reference red radiance is below this (W/(sr m^2)), less one pixel around the
# rest. The Cornell emitter holds half of the image's energy, which dilutes the whole image's
# sum ratio; its diffuse pixels peak at 0.46, the emitter at 18.4.
DIFFUSE_MASK_BELOW = {"cornell_box": 0.6}
# Mitsuba translates only the Cornell scenes (bench/mitsuba/cornell_box.py).
MITSUBA_SCENES = {"cornell_box", "cornell_glass"}

# ---- The reference: one variable ------------------------------------------------------------
# "reference": `lightbake reference` (bake/reference/, the independent path tracer), once it is
#              on main. "mitsuba": Mitsuba 3's path tracer (Cornell scenes only).
# "hq":        a long `lightbake render` - NOT independent: it converges to HQ mode's own
#              answer, so it measures the noise of the bake and HQ, not their bias. Fallback only.
# `auto` picks reference if the subcommand exists, else mitsuba where it can, else hq.
REFERENCE = "auto"


def have_reference_command():
    text = subprocess.run([LIGHTBAKE, "--help"], capture_output=True, text=True).stdout
    return any(line.split()[:1] == ["reference"] for line in text.splitlines())


def reference_kind(scene, wanted):
    if wanted != "auto":
        return wanted
    if have_reference_command():
        return "reference"
    if scene in MITSUBA_SCENES and os.path.exists(VENV_PYTHON):
        return "mitsuba"
    return "hq"


def reference_command(kind, scene_path, size, spp, seed, out):
    """The command that renders SCENE with the reference renderer at SPP samples per pixel."""
    if kind == "reference":
        return [LIGHTBAKE, "reference", scene_path, "--spp", str(spp), "--size", size,
                "--seed", str(seed), "-o", out, "--report", out[:-4] + ".json"]
    if kind == "mitsuba":
        return [VENV_PYTHON, MITSUBA_SCRIPT, "--scene", scene_path, "--size", size,
                "--single", out, "--spp", str(spp), "--seed", str(seed)]
    if kind == "hq":
        side = int(math.isqrt(min(spp, 256)))
        passes = max(1, spp // (side * side))
        return [LIGHTBAKE, "render", scene_path, "--size", size, "--spp", str(side * side),
                "--passes", str(passes), "--seed", str(seed), "-o", out, "-q"]
    raise ValueError(kind)


# ---- Running and measuring ------------------------------------------------------------------
def run(command):
    """Runs a command; returns CPU seconds (user + sys), wall seconds, peak memory in MB and
    its stdout. os.wait4 gives this child's own rusage, threads included (RUSAGE_CHILDREN would
    fold every earlier child into the peak memory)."""
    with open(os.path.join(ROOT, f"build/bench/last_stdout_{os.getpid()}.txt"), "w+") as out, \
            open(os.path.join(ROOT, f"build/bench/last_stderr_{os.getpid()}.txt"), "w+") as err:
        start = time.monotonic()
        process = subprocess.Popen(command, stdout=out, stderr=err)
        _, status, usage = os.wait4(process.pid, 0)
        process.returncode = os.waitstatus_to_exitcode(status)
        wall = time.monotonic() - start
        out.seek(0)
        err.seek(0)
        if process.returncode != 0:
            sys.exit(f"speed_accuracy: failed ({process.returncode}): {' '.join(command)}\n"
                     f"{err.read()[-2000:]}")
        return usage.ru_utime + usage.ru_stime, wall, usage.ru_maxrss / 1024.0, out.read()


def compare(image, reference, region=None, mask=None):
    command = [LIGHTBAKE, "compare", image, reference]
    if region:
        command += ["--region", region]
    if mask:
        command += ["--mask", mask]
    return json.loads(subprocess.run(command, check=True, capture_output=True,
                                     text=True).stdout)


def scene_facts(scene_path):
    """Largest side of the scene's bounds in metres, and whether it has specular materials
    (else pass 1 does nothing and its settings are not swept), from `lightbake info`."""
    text = subprocess.run([LIGHTBAKE, "info", scene_path], check=True, capture_output=True,
                          text=True).stdout
    line = next(l for l in text.splitlines() if l.startswith("bounds"))
    numbers = [float(x) for x in line.replace("(", " ").replace(")", " ").replace(",", " ")
               .replace("..", " ").split()[1:7]]
    specular = any(len(l.split()) > 1 and l.split()[1] in ("mirror", "glass", "glossy")
                   for l in text.splitlines() if l.startswith("  "))
    return max(numbers[3 + i] - numbers[i] for i in range(3)), specular


# ---- The sweep ------------------------------------------------------------------------------
LEVELS = {
    # Bake variations (one setting at a time around the defaults, plus a few combinations;
    # sizes as divisors of the scene's largest extent), HQ spp on the default bake, the
    # reference's spp, and the converged reference's spp.
    "quick": dict(budgets=[2e5], patch_div=[16], combos=[], rays_side=[128], texel_div=[],
                  hq_spp=[4, 16], ref_spp=[16, 64], converged_spp=1024),
    # The final gather against interpolation on the default bake only (a few CPU minutes).
    "gather": dict(budgets=[], patch_div=[], combos=[], rays_side=[], texel_div=[],
                   hq_spp=[16, 64, 256], gather_spp=[16, 64, 256], gather_rays=[1],
                   ref_spp=[16, 64], converged_spp=1024),
    "medium": dict(budgets=[1e5, 5e5, 1e7], patch_div=[8, 16, 32, 64], combos=[(32, 1e7)],
                   rays_side=[128, 256, 1024], texel_div=[128, 512], hq_spp=[1, 4, 16, 64],
                   ref_spp=[16, 64, 256, 1024], converged_spp=4096, gather_spp=[16, 64, 256]),
    "full": dict(budgets=[1e5, 3e5, 1e6, 6e6, 2e7], patch_div=[8, 16, 32, 64, 128],
                 combos=[(32, 6e6), (64, 2e7), (128, 2e7)],
                 rays_side=[64, 128, 256, 1024, 2048], texel_div=[64, 128, 256, 512, 1024],
                 hq_spp=[1, 4, 16, 64, 256], ref_spp=[16, 64, 256, 1024, 4096],
                 converged_spp=16384, gather_spp=[16, 64, 256], gather_rays=[1, 4]),
}


def bake_variants(level, extent, has_specular):
    variants = [("default", [])]
    variants += [(f"ray_budget={b:g}", ["--ray-budget", str(int(b))]) for b in level["budgets"]]
    variants += [(f"patch_size={extent / d:.4g}", ["--patch-size", f"{extent / d:.6g}"])
                 for d in level["patch_div"]]
    # finer patches need more rays: (patch divisor, ray budget) pairs
    variants += [(f"patch_size={extent / d:.4g}+ray_budget={b:g}",
                  ["--patch-size", f"{extent / d:.6g}", "--ray-budget", str(int(b))])
                 for d, b in level["combos"]]
    if has_specular:
        variants += [(f"rays_per_zone_side={r}", ["--rays-per-zone-side", str(r)])
                     for r in level["rays_side"]]
        variants += [(f"texel_size={extent / d:.4g}", ["--texel-size", f"{extent / d:.6g}"])
                     for d in level["texel_div"]]
    return variants


def sweep_scene(scene, level, work, reference_wanted, rows, mitsuba_series=False):
    size, region = SCENES[scene]
    scene_path = os.path.join(ROOT, "scenes", scene + ".toml")
    kind = reference_kind(scene, reference_wanted)
    refs = os.path.join(ROOT, "build/bench/references")
    os.makedirs(refs, exist_ok=True)
    converged = os.path.join(refs, f"{scene}_{size}_{kind}_{level['converged_spp']}spp.exr")
    if not os.path.exists(converged):
        print(f"{scene}: converged reference ({kind}, {level['converged_spp']} spp) ...",
              file=sys.stderr)
        cpu, wall, _, _ = run(reference_command(kind, scene_path, size, level["converged_spp"],
                                                1000, converged))
        print(f"{scene}: reference took {cpu:.0f} CPU s", file=sys.stderr)
    extent, has_specular = scene_facts(scene_path)
    mask = None
    if scene in DIFFUSE_MASK_BELOW:
        mask = converged[:-4] + "_diffuse_mask.png"
        subprocess.run(["oiiotool", converged, "--ch", "R", "--subc",
                        str(DIFFUSE_MASK_BELOW[scene]), "--mulc", "1e6", "--clamp:min=0:max=1",
                        "--dilate", "3x3", "--mulc", "-1", "--addc", "1", "-d", "uint8",
                        "-o", mask], check=True)
    scene_work = os.path.join(work, scene)
    os.makedirs(scene_work, exist_ok=True)

    # Block error: the MRE of 8 x 8-pixel block means (box-filtered by oiiotool), where the
    # renders' and the reference's noise mostly cancel and the bias of a bake shows.
    width, height = (int(v) for v in size.split("x"))
    block_size = f"{width // 8}x{height // 8}"
    converged_blocks = converged[:-4] + "_blocks8.exr"
    if not os.path.exists(converged_blocks):
        subprocess.run(["oiiotool", converged, "--resize:filter=box", block_size, "-o",
                        converged_blocks], check=True)

    def record(series, settings, is_default, cpu, wall, mem, rays, image):
        row = dict(scene=scene, level=level["name"], series=series, settings=settings,
                   default=int(is_default),
                   cpu_seconds=round(cpu, 3), wall_seconds=round(wall, 3),
                   peak_memory_mb=round(mem, 1), rays=rays, reference=kind,
                   reference_spp=level["converged_spp"])
        metrics = compare(image, converged)
        row.update(mre=metrics["mre"], relmse=metrics["relmse"], rmse=metrics["rmse"],
                   sum_ratio=metrics["sum_ratio_total"])
        blocks = image[:-4] + "_blocks8.exr"
        subprocess.run(["oiiotool", image, "--resize:filter=box", block_size, "-o", blocks],
                       check=True)
        row.update(block_mre=compare(blocks, converged_blocks)["mre"])
        if mask:
            diffuse = compare(image, converged, mask=mask)
            row.update(diffuse_mre=diffuse["mre"], diffuse_sum_ratio=diffuse["sum_ratio_total"])
        if region:
            caustic = compare(image, converged, region)
            row.update(region_mre=caustic["mre"], region_sum_ratio=caustic["sum_ratio_total"])
        rows.append(row)
        print(f"{scene:17s} {series:9s} {settings:32s} {cpu:7.2f} CPU s  MRE {row['mre']:.4f}"
              f"  sum {row['sum_ratio']:.4f}", file=sys.stderr)

    for name, args in bake_variants(level, extent, has_specular):
        bake_dir = os.path.join(scene_work, "bake_" + name.replace("=", "_"))
        bake_cpu, bake_wall, bake_mem, _ = run([LIGHTBAKE, "bake", scene_path, "-o", bake_dir,
                                                "-q", *args])
        manifest = json.load(open(os.path.join(bake_dir, "manifest.json")))
        bake_rays = manifest["illumination"]["rays"] + manifest["radiosity"]["rays"]
        snap = os.path.join(scene_work, f"raster_{name}.exr")
        cpu, wall, mem, _ = run([LIGHTBAKE, "snapshot", scene_path, bake_dir, "--size", size,
                                 "-o", snap])
        record("raster", name, name == "default", bake_cpu + cpu, bake_wall + wall,
               max(bake_mem, mem), bake_rays, snap)
        for spp in level["hq_spp"] if name == "default" else [16]:
            image = os.path.join(scene_work, f"hq_{name}_{spp}spp.exr")
            cpu, wall, mem, _ = run([LIGHTBAKE, "render", scene_path, bake_dir, "--size", size,
                                     "--spp", str(spp), "-o", image, "-q"])
            report = json.load(open(image[:-4] + ".json"))
            rays = bake_rays + report["rays"]["viewing"]["count"] + report["rays"]["shadow"]["count"]
            record("hq", f"{name} spp={spp}", name == "default" and spp == 16, bake_cpu + cpu,
                   bake_wall + wall, max(bake_mem, mem), rays, image)
        for gather in level.get("gather_rays", [1]) if name == "default" else []:
            for spp in level.get("gather_spp", [16]):
                image = os.path.join(scene_work, f"hq_gather{gather}_{name}_{spp}spp.exr")
                cpu, wall, mem, _ = run([LIGHTBAKE, "render", scene_path, bake_dir, "--size",
                                         size, "--spp", str(spp), f"--final-gather={gather}",
                                         "-o", image, "-q"])
                report = json.load(open(image[:-4] + ".json"))
                rays = (bake_rays + report["rays"]["viewing"]["count"] +
                        report["rays"]["shadow"]["count"] + report["rays"]["gather"]["count"])
                record("hq_gather", f"{name} spp={spp} final_gather={gather}", False,
                       bake_cpu + cpu, bake_wall + wall, max(bake_mem, mem), rays, image)
    for spp in level["ref_spp"]:
        image = os.path.join(scene_work, f"reference_{spp}spp.exr")
        cpu, wall, mem, _ = run(reference_command(kind, scene_path, size, spp, 7, image))
        rays = ""
        report = image[:-4] + ".json"
        if os.path.exists(report):
            rays = json.load(open(report)).get("rays", {}).get("total", "")
        record("reference", f"{kind} spp={spp}", False, cpu, wall, mem, rays, image)
    if mitsuba_series and kind != "mitsuba" and scene in MITSUBA_SCENES:
        for spp in level["ref_spp"]:
            image, cpu, wall, mem = mitsuba_alone(scene_path, scene, size, spp)
            record("mitsuba", f"mitsuba spp={spp}", False, cpu, wall, mem, "", image)


def mitsuba_alone(scene_path, scene, size, spp):
    """Mitsuba alone at SPP (seed 7), an extra series beside our reference. Cached with its
    measured CPU seconds (build/bench/references/SCENE_SIZE_mitsuba_alone_SPPspp.{exr,json}),
    since it costs as much as our reference and does not change with our code."""
    image = os.path.join(ROOT, "build/bench/references",
                         f"{scene}_{size}_mitsuba_alone_{spp}spp.exr")
    timing = image[:-4] + ".json"
    if not os.path.exists(timing):
        if not os.path.exists(VENV_PYTHON):
            sys.exit(f"speed_accuracy: --mitsuba-series needs {VENV_PYTHON} "
                     "(docs/speed-accuracy.md)")
        cpu, wall, mem, _ = run(reference_command("mitsuba", scene_path, size, spp, 7, image))
        json.dump(dict(cpu_seconds=cpu, wall_seconds=wall, peak_memory_mb=mem), open(timing, "w"))
    t = json.load(open(timing))
    return image, t["cpu_seconds"], t["wall_seconds"], t["peak_memory_mb"]


# ---- Charts ---------------------------------------------------------------------------------
def pareto(points):
    """The points no other point beats in both CPU seconds and error, sorted by seconds."""
    front, best = [], math.inf
    for p in sorted(points):
        if p[1] < best:
            front.append(p)
            best = p[1]
    return front


def front_at(points, seconds):
    """The Pareto front's error at SECONDS: the least error of any point that cost no more."""
    return min((e for s, e in points if s <= seconds), default=math.inf)


def defaults_against_front(rows, metric="mre"):
    """Issue 11's yardstick: each default point's error over the front of every series (all
    methods together) at the default's own CPU seconds; 1.0 means the default is on the front,
    the target is <= 1.25. Returns rows of (scene, series, seconds, error, front error, the
    point that sets the front, ratio)."""
    table = []
    for scene in dict.fromkeys(r["scene"] for r in rows):
        points = [(r["cpu_seconds"], r[metric], r["series"], r["settings"]) for r in rows
                  if r["scene"] == scene and isinstance(r.get(metric), float) and r[metric] > 0]
        for r in rows:
            if r["scene"] != scene or not r["default"] or not isinstance(r.get(metric), float):
                continue
            cheaper = [p for p in points if p[0] <= r["cpu_seconds"]]
            best = min(cheaper, key=lambda p: p[1])
            table.append((scene, r["series"], r["cpu_seconds"], r[metric], best[1],
                          f"{best[2]} {best[3]}", r[metric] / best[1]))
    return table


def write_front_table(rows, path, metric="mre"):
    table = defaults_against_front(rows, metric)
    with open(path, "w") as f:
        f.write(f"| scene | default | CPU s | {metric} | front at that CPU s | set by | ratio |\n"
                "|---|---|---|---|---|---|---|\n")
        for scene, series, seconds, error, front, by, ratio in table:
            f.write(f"| {scene} | {series} | {seconds:.2f} | {error:.4f} | {front:.4f} | {by} "
                    f"| {ratio:.3f} |\n")
    worst = max((t[-1] for t in table), default=float("nan"))
    print(f"wrote {path}: worst default / front = {worst:.3f} (issue 11's target <= 1.25)",
          file=sys.stderr)


def chart(rows, scene, path, metric="mre", title_extra=""):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    styles = {"raster": ("tab:blue", "o", "bake + raster viewer"),
              "hq": ("tab:orange", "s", "bake + HQ mode"),
              "hq_gather": ("tab:red", "D", "bake + HQ, final gather"),
              "reference": ("tab:green", "^", "reference alone"),
              "mitsuba": ("tab:gray", "v", "Mitsuba 3 alone")}
    kind = next(r["reference"] for r in rows if r["scene"] == scene)
    name = {"reference": "lightbake reference", "mitsuba": "Mitsuba 3", "hq": "HQ"}[kind]
    styles["reference"] = styles["reference"][:2] + (f"reference alone ({name})",)
    fig, ax = plt.subplots(figsize=(6.4, 4.4), dpi=110)
    for series, (colour, marker, label) in styles.items():
        points = [(r["cpu_seconds"], r[metric]) for r in rows
                  if r["scene"] == scene and r["series"] == series
                  and isinstance(r.get(metric), float) and r[metric] > 0]
        if not points:
            continue
        ax.scatter(*zip(*points), color=colour, marker=marker, s=22, alpha=0.6, label=label)
        front = pareto(points)
        ax.step(*zip(*front), where="post", color=colour, lw=1.2)
        for r in rows:
            if r["scene"] == scene and r["series"] == series and r["default"]:
                ax.scatter([r["cpu_seconds"]], [r[metric]], color=colour, marker="*", s=220,
                           edgecolor="black", zorder=5)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("CPU seconds (user + sys)")
    ax.set_ylabel({"mre": "mean relative error", "region_mre": "caustic region MRE",
                   "block_mre": "MRE of 8 x 8-pixel block means"}[metric])
    caveat = " (HQ itself: not independent)" if kind == "hq" else ""
    spp = next(int(r["reference_spp"]) for r in rows if r["scene"] == scene)
    ax.set_title(f"{scene}{title_extra}: against {name} at {spp} spp{caveat}\n"
                 f"(star: default settings, line: Pareto front)", fontsize=9)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)


def read_csv(path):
    if not os.path.exists(path):
        return []
    with open(path) as f:
        return [{k: (float(v) if k in NUMERIC and v != "" else v) for k, v in r.items()}
                for r in csv.DictReader(f)]


def write_csv(path, rows):
    fields = list(dict.fromkeys(k for r in rows for k in r))
    with open(path, "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=fields)
        writer.writeheader()
        writer.writerows(rows)


def ensure_matplotlib():
    try:
        import matplotlib  # noqa: F401
    except ImportError:
        print("speed_accuracy: installing python3-matplotlib (Debian)", file=sys.stderr)
        prefix = [] if os.geteuid() == 0 else ["sudo"]
        subprocess.run(prefix + ["apt-get", "install", "-y", "-q", "python3-matplotlib"],
                       check=True)
        importlib.invalidate_caches()
        try:
            import matplotlib  # noqa: F401,F811
        except ImportError:
            # Debian's package serves Debian's interpreter only (not a pyenv or venv python3).
            sys.exit(f"speed_accuracy: {sys.executable} cannot import matplotlib; run this "
                     "script with /usr/bin/python3")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="= --level quick")
    parser.add_argument("--level", choices=LEVELS, default="medium")
    parser.add_argument("--scenes", nargs="*", default=list(SCENES))
    parser.add_argument("--reference", default=REFERENCE,
                        choices=["auto", "reference", "mitsuba", "hq"])
    parser.add_argument("--out", help="results directory (default: bench/results, "
                                      "build/bench/quick for --quick)")
    parser.add_argument("--converged-spp", type=int,
                        help="the converged reference's spp (default: the level's)")
    parser.add_argument("--ref-spp", type=int, nargs="+",
                        help="the reference-alone series' spp (default: the level's)")
    parser.add_argument("--append", action="store_true",
                        help="add rows to the CSV (replacing the swept scenes' rows)")
    parser.add_argument("--mitsuba-series", action="store_true",
                        help="Cornell scenes: add Mitsuba alone as an extra series (cached)")
    parser.add_argument("--charts-only", action="store_true", help="redraw from the CSV")
    args = parser.parse_args()
    level_name = "quick" if args.quick else args.level
    out = args.out or os.path.join(ROOT, "build/bench/quick" if level_name == "quick"
                                   else "bench/results")
    os.makedirs(out, exist_ok=True)
    os.makedirs(os.path.join(ROOT, "build/bench"), exist_ok=True)
    ensure_matplotlib()
    csv_path = os.path.join(out, "speed_accuracy.csv")
    level = dict(LEVELS[level_name], name=level_name)
    if args.converged_spp:
        level["converged_spp"] = args.converged_spp
    if args.ref_spp:
        level["ref_spp"] = args.ref_spp
    rows = read_csv(csv_path) if (args.charts_only or args.append) else []
    if not args.charts_only:
        work = os.path.join(ROOT, "build/bench/work", level_name)
        for scene in args.scenes:
            shutil.rmtree(os.path.join(work, scene), ignore_errors=True)
            rows = [r for r in rows if r["scene"] != scene]
            sweep_scene(scene, level, work, args.reference, rows, args.mitsuba_series)
            write_csv(csv_path, rows)  # after every scene: a long run keeps what it finished
        print(f"wrote {csv_path}", file=sys.stderr)
    for scene in dict.fromkeys(r["scene"] for r in rows):
        chart(rows, scene, os.path.join(out, f"speed_accuracy_{scene}.png"))
        if any(r.get("block_mre") not in (None, "") for r in rows if r["scene"] == scene):
            chart(rows, scene, os.path.join(out, f"speed_accuracy_{scene}_blocks.png"),
                  "block_mre", " 8x8 blocks")
        if any(r.get("region_mre") not in (None, "") for r in rows if r["scene"] == scene):
            chart(rows, scene, os.path.join(out, f"speed_accuracy_{scene}_caustic.png"),
                  "region_mre", " caustic region")
    write_front_table(rows, os.path.join(out, "defaults_against_front.md"))
    print(f"charts in {out}", file=sys.stderr)


NUMERIC = {"default", "cpu_seconds", "wall_seconds", "peak_memory_mb", "reference_spp", "mre",
           "relmse", "rmse", "sum_ratio", "region_mre", "region_sum_ratio", "diffuse_mre",
           "diffuse_sum_ratio", "block_mre"}

if __name__ == "__main__":
    main()
