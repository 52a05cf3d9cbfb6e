#!/usr/bin/python3
"""Chooses which tests the sanitizer suite (scripts/test-sanitize.sh) leaves out, by coverage.

A sanitizer reports faults in the code a test runs, so a test whose every line of the tool's
code (bake/, app/, viewer/) is also run by the tests kept adds time and nothing a sanitizer
could see. This script measures each test's line coverage in a build made with --coverage,
keeps every test that is cheap under the sanitizers, then adds the dear ones greedily by new
lines per sanitizer second while that exceeds --min-lines-per-second (0.1: a test two minutes
long must add a dozen lines), and writes the rest to tests/sanitize_leave_out.txt with their
seconds, and the few lines only they run. New tests are run under the
sanitizers until the list is remade.

    cmake -S . -B build-cov -G Ninja -DCMAKE_BUILD_TYPE=Release -DLIGHTBAKE_BENCHMARKS=OFF \\
      "-DCMAKE_CXX_FLAGS_RELEASE=-O1 -DNDEBUG --coverage" \\
      "-DCMAKE_C_FLAGS_RELEASE=-O1 -DNDEBUG --coverage" -DCMAKE_EXE_LINKER_FLAGS=--coverage \\
      -DCMAKE_SHARED_LINKER_FLAGS=--coverage && ninja -C build-cov
    scripts/install-pypi.sh build-cov
    /usr/bin/python3 scripts/select-sanitized-tests.py --coverage-build build-cov \\
      --sanitizer-build build-asan     # after a full scripts/test-sanitize.sh there: its costs

About an hour of CPU on two cores (every test once, instrumented, then gcov on each).
"""

import argparse
import concurrent.futures
import json
import os
import shutil
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
TOOL_DIRS = ("bake/", "app/", "viewer/")
LEAVE_OUT = os.path.join(ROOT, "tests", "sanitize_leave_out.txt")


def list_tests(build):
    """(index, name, labels) of every test ctest knows in `build`."""
    shown = subprocess.run(["ctest", "--show-only=json-v1"], cwd=build, check=True,
                           capture_output=True, text=True).stdout
    tests = []
    for index, test in enumerate(json.loads(shown)["tests"], start=1):
        labels = []
        for prop in test.get("properties", []):
            if prop["name"] == "LABELS":
                labels = prop["value"]
        tests.append((index, test["name"], labels))
    return tests


def sanitizer_costs(build):
    """Seconds each test took in the sanitizer tree's last runs (ctest's own cost file)."""
    costs = {}
    path = os.path.join(build, "Testing", "Temporary", "CTestCostData.txt")
    with open(path) as cost_file:
        for line in cost_file:
            fields = line.rsplit(maxsplit=2)  # a name may hold spaces: "X/1  # GetParam() = 1"
            if len(fields) == 3 and fields[1].isdigit():
                costs[fields[0]] = float(fields[2])
    # The tests the current list leaves out never run in that tree, so its cost file may lack
    # them: their seconds as the list recorded them, or they would count as cheap and be kept.
    recorded = {}
    with open(LEAVE_OUT) as listed:
        for line in listed:
            name, _, comment = line.partition("#")
            seconds = comment.strip().removesuffix(" s")
            if name.strip() and seconds.isdigit():
                recorded[name.strip()] = float(seconds)
    for _, name, _ in list_tests(build):
        if name not in costs and name.split("  #")[0] in recorded:
            costs[name] = recorded[name.split("  #")[0]]
    return costs


def run_instrumented(build, prefix, indices, jobs=1):
    """Runs tests (ctest numbers) with their .gcda files sent to prefix; True if all passed."""
    shutil.rmtree(prefix, ignore_errors=True)
    os.makedirs(prefix)
    strip = len(os.path.abspath(build).strip("/").split("/"))
    env = dict(os.environ, GCOV_PREFIX=prefix, GCOV_PREFIX_STRIP=str(strip))
    numbers = ",".join(str(i) for i in indices)
    done = subprocess.run(["ctest", "-I", f"0,0,0,{numbers}", "--parallel", str(jobs),
                           "--timeout", "1200"], cwd=build, env=env, capture_output=True,
                          text=True)
    return done.returncode == 0


def source_dir(build):
    """The source tree the build was configured from (its paths are the ones gcov reports)."""
    with open(os.path.join(build, "CMakeCache.txt")) as cache:
        for line in cache:
            if line.startswith("CMAKE_HOME_DIRECTORY:"):
                return line.split("=", 1)[1].strip()
    raise SystemExit(f"{build}/CMakeCache.txt: no CMAKE_HOME_DIRECTORY; is it a CMake build?")


def covered_lines(build, prefix):
    """Set of (source, line) of the tool's own code that the .gcda files under prefix ran."""
    build, source_root = os.path.abspath(build), source_dir(build)
    counters = []
    for folder, _, files in os.walk(prefix):
        if os.path.relpath(folder, prefix).startswith("tests"):
            continue  # the tests' own code is not what the sanitizers are run for
        for gcda in (os.path.join(folder, f) for f in files if f.endswith(".gcda")):
            gcno = os.path.join(build, os.path.relpath(gcda, prefix))[:-5] + ".gcno"
            if os.path.exists(gcno):
                if not os.path.exists(gcda[:-5] + ".gcno"):
                    os.link(gcno, gcda[:-5] + ".gcno")
                counters.append(gcda)
    if not counters:
        return set()
    # -r -s: sources under the tree only, none of the system's headers.
    out = subprocess.run(["gcov", "--json-format", "--stdout", "--relative-only",
                          "--source-prefix", source_root] + counters,
                         cwd=prefix, capture_output=True, check=True).stdout
    lines = set()
    for document in out.decode().splitlines():
        if not document.startswith("{"):
            continue
        for source in json.loads(document)["files"]:
            path = os.path.relpath(os.path.realpath(source["file"]), source_root)
            if path.startswith(TOOL_DIRS):
                lines.update((path, line["line_number"]) for line in source["lines"]
                             if line["count"] > 0)
    return lines


def choose(coverage, costs, seen, min_gain):
    """Dear tests kept, greedily by the lines they add to `seen` a sanitizer second, while
    that is above min_gain."""
    kept, seen, dear = set(), set(seen), set(coverage)
    while True:
        gains = {name: len(coverage[name] - seen) / costs[name] for name in dear}
        best = max(gains, key=gains.get, default=None)
        if best is None or gains[best] <= min_gain:
            return kept, seen
        kept.add(best)
        dear.discard(best)
        seen |= coverage[best]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--coverage-build", required=True)
    parser.add_argument("--sanitizer-build", required=True,
                        help="tree whose CTestCostData.txt gives each test's sanitizer seconds")
    parser.add_argument("--keep-below", type=float, default=4.0,
                        help="sanitizer seconds under which a test is always kept")
    parser.add_argument("--min-lines-per-second", type=float, default=0.1,
                        help="a dear test adding fewer new lines a sanitizer second is left out")
    parser.add_argument("--reuse-counters", action="store_true",
                        help="read the counters of the last run again instead of running tests")
    parser.add_argument("--jobs", type=int, default=os.cpu_count())
    parser.add_argument("--data", help="where the .gcda trees go (default: in the build)")
    args = parser.parse_args()
    data = args.data or os.path.join(args.coverage_build, "coverage-per-test")
    costs = sanitizer_costs(args.sanitizer_build)
    tests = {name: i for i, name, labels in list_tests(args.coverage_build)
             if "external" not in labels}
    # Cheap tests are kept whatever they cover, so they run as one batch into one .gcda tree;
    # each dear one runs alone into its own.
    cheap = [name for name in tests if costs.get(name, 0.0) < args.keep_below]
    dear = [name for name in tests if name not in cheap]
    print(f"{len(tests)} tests run under the sanitizers; {len(dear)} take {args.keep_below} s "
          "or more there, each measured alone", file=sys.stderr)
    failed_log = os.path.join(data, "failed.txt")
    if not args.reuse_counters:
        run_instrumented(args.coverage_build, os.path.join(data, "cheap"),
                         [tests[name] for name in cheap], args.jobs)
        with concurrent.futures.ThreadPoolExecutor(args.jobs) as pool:
            passed = pool.map(lambda name: run_instrumented(
                args.coverage_build, os.path.join(data, str(tests[name])), [tests[name]]), dear)
            with open(failed_log, "w") as log:
                log.writelines(name + "\n" for name, ok in zip(dear, passed) if not ok)
    unmeasured = [name for name in dear
                  if not os.path.isdir(os.path.join(data, str(tests[name])))]
    if unmeasured:  # an empty tree would read as "adds no line" and leave the test out
        raise SystemExit(f"{data}: no counters of {unmeasured[0]} (and {len(unmeasured) - 1} "
                         "more dear tests); run without --reuse-counters")
    with open(failed_log) as log:
        failed = set(log.read().split())
    with concurrent.futures.ThreadPoolExecutor(args.jobs) as pool:
        prefixes = ["cheap"] + [str(tests[name]) for name in dear]
        lines = dict(zip(prefixes, pool.map(lambda p: covered_lines(
            args.coverage_build, os.path.join(data, p)), prefixes)))
    # A dear test that failed here is kept: its coverage may be short.
    for name in (name for name in dear if name in failed):
        print(f"  {name}: failed in the coverage build; kept", file=sys.stderr)
    coverage = {name: lines[str(tests[name])] for name in dear if name not in failed}
    always = lines["cheap"].union(*(lines[str(tests[name])] for name in dear
                                   if name in failed))
    kept, seen = choose(coverage, costs, always, args.min_lines_per_second)
    everything = always.union(*coverage.values())
    left_out = sorted(set(coverage) - kept, key=lambda name: -costs[name])
    saved = sum(costs[name] for name in left_out)
    total = sum(costs.get(name, 0.0) for name in tests)
    print(f"lines of bake/, app/, viewer/ the suite runs: {len(everything)}; the cheap tests: "
          f"{len(always)}; all kept: {len(seen)}", file=sys.stderr)
    print(f"left out {len(left_out)} of {len(tests)} tests: {saved:.0f} of {total:.0f} "
          "sanitizer seconds", file=sys.stderr)
    missed = sorted(everything - seen)
    with open(LEAVE_OUT, "w") as out:
        out.write(HEADER.format(rate=args.min_lines_per_second, count=len(missed)))
        out.writelines(f"#   {path}:{line}\n" for path, line in missed)
        out.write("\n")
        for name in left_out:
            # gtest's "  # GetParam() = ..." after a parameterised name is a comment here.
            out.write(f"{name.split('  #')[0]}  # {costs[name]:.0f} s\n")


HEADER = """\
# Tests the sanitizer suite (scripts/test-sanitize.sh) leaves out; scripts/test.sh runs them all.
# Made by scripts/select-sanitized-tests.py from each test's line coverage: each one runs no
# line of bake/, app/ and viewer/ that the tests kept under AddressSanitizer and
# UndefinedBehaviorSanitizer miss, or adds fewer than {rate} such lines a sanitizer second;
# what they check (bits, accuracy, refusals) the normal suite checks. Seconds: the test's time
# under the sanitizers. Remake the list after large changes (the script's doc says how).
# One ctest name a line; '#' starts a comment.
#
# The {count} lines only left-out tests run, so no sanitizer watches them:
"""

if __name__ == "__main__":
    main()
