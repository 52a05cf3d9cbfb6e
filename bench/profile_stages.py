#!/usr/bin/python3
"""Where a lightbake command's CPU time goes, per stage: perf's samples of the command, each
function put in one stage by its name (and library), as a Markdown table of CPU seconds.

    bench/profile_stages.py [--keep FILE] -- build/app/lightbake render scenes/room.toml BAKE ...

Needs perf (Debian: linux-perf) and perf_event_paranoid <= 2 for one's own processes. The
command runs twice: once alone for its user + system CPU seconds (getrusage of the child), once
under perf for the samples; each stage gets its share of the samples of those seconds. Functions are classified by name: a function inlined
into another counts in its caller's stage. The tables in docs/hq.md, docs/illumination.md and
docs/radiosity.md are this script's output.
"""

import argparse
import os
import re
import resource
import subprocess
import sys
import tempfile

# (stage, pattern on "library symbol"), first match wins; the order matters.
STAGES = [
    ("Embree: traversal and BVH build", r"^libembree"),
    ("Embree wrapper: rays in, hits out (bake/accel.cpp)", r"lb::Accel::"),
    ("start-up: dynamic loading (image plugin, GL)", r"^ld-linux"),
    ("image files: EXR/PNG encode and decode", r"^lib(z|OpenEXR|OpenImageIO|png|Imath|deflate)|"
     r"write_exr|read_atlas_exr|write_atlas_exr|lb::Reader::|bake_hash|encode|decode"),
    ("kernel: page faults, threads, files", r"^\[kernel"),
    ("TBB scheduling", r"^libtbb"),
    ("pass 1: light rays, specular paths, splat", r"light_ray|trace_block|trace_paths|"
     r"splat_deposit|Pass1Sums|FixedTally|feeler|find_traced|specular_point|IlluminationPass"),
    ("pass 1: density filter", r"filter_by_density"),
    ("pass 1: atlas (charts, packing, node areas, dilation)", r"build_atlas|label_charts|"
     r"accumulate_node_areas|pack_charts|unfold|dilate|power_to_radiance|Atlas|chart_of"),
    ("pass 2: radiosity shooting", r"Shooter|solve_radiosity|shuffle_pairing|PatchMesh|"
     r"patches|refine"),
    ("soft-light map: footprints, gather, texel fill", r"fill_texel|TexelFootprints|"
     r"cell_samples|make_sample|to_node_space|gather_soft_light|gathered_radiance|soft_light_texels|"
     r"walk_gather_ray|finish_gather_ray|lb::gather_ray|gather_cell_point|"
     r"chart_box_filter|filter_radii|footprint|fill_texels|gather_mean"),
    ("HQ sampling: camera rays, strata, permutations", r"render_tile|ThinLensCamera|sobol|"
     r"lb::Rng::|mix64|hash_seed"),
    ("light choice and light samples", r"DirectLight|AreaLight|segment_ray|LightSources|"
     r"sample_towards|shadow_ray_towards"),
    ("baked terms at a hit: maps, vertex radiosity", r"illumination_at|soft_light_at|atlas_taps|"
     r"atlas_at|vertex_radiosity|interpolate|add_group_terms"),
    ("shading at a hit: surface point, BSDF, specular step", r"HqRenderer::advance|HqRenderer::trace|"
     r"surface_at|receiver_at|reflectance_at|scatter_specular|fresnel|refract|bumped_normal|"
     r"survive_roulette|specular_normal|offset_ray_origin|Frame|triangle_normal|"
     r"square_to_cosine|sample_texture"),
    ("libc, libstdc++: memory, strings", r"^lib(c|stdc\+\+|m)[.-]"),
]


def classify(dso, symbol):
    key = f"{dso} {symbol}"
    for stage, pattern in STAGES:
        if re.search(pattern, key):
            return stage
    return "other"


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--keep", help="keep perf's data in this file")
    parser.add_argument("--frequency", type=int, default=1999, help="samples per second")
    parser.add_argument("command", nargs=argparse.REMAINDER)
    args = parser.parse_args()
    command = args.command[1:] if args.command[:1] == ["--"] else args.command
    if not command:
        parser.error("no command to profile")
    data = args.keep or tempfile.NamedTemporaryFile(suffix=".perf", delete=False).name
    # CPU seconds from a run without perf (perf's own work would count), shares from a second.
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    run = subprocess.run(command, stdout=subprocess.DEVNULL)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    if run.returncode == 0:
        run = subprocess.run(["perf", "record", "-q", "-F", str(args.frequency), "-o", data, "--"]
                             + command, stdout=subprocess.DEVNULL)
    if run.returncode != 0:
        sys.exit(f"profile_stages: the command exited with {run.returncode}")
    report = subprocess.run(["perf", "report", "-i", data, "--no-children", "--sort", "dso,symbol",
                             "-g", "none", "--field-separator", "\t", "--percentage", "relative"],
                            capture_output=True, text=True, check=True).stdout
    if not args.keep:
        os.remove(data)
    shares = {}
    for line in report.splitlines():
        if not line or line.startswith("#"):
            continue
        fields = line.split("\t")
        if len(fields) < 3 or not fields[0].strip().endswith("%"):
            continue
        percent = float(fields[0].strip().rstrip("%"))
        symbol = re.sub(r"^\[\.\]\s*|^\[k\]\s*", "", fields[2].strip())
        stage = classify(fields[1].strip(), symbol)
        shares[stage] = shares.get(stage, 0.0) + percent
    total = sum(shares.values()) or 1.0
    print(f"| stage | CPU s | share |  (`{' '.join(command)}`: {cpu:.2f} CPU s)")
    print("| --- | --- | --- |")
    for stage, percent in sorted(shares.items(), key=lambda kv: -kv[1]):
        share = percent / total
        print(f"| {stage} | {share * cpu:.2f} | {100 * share:.0f}% |")


if __name__ == "__main__":
    main()
