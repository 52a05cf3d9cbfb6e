#!/usr/bin/python3
"""The floors of docs/architecture.md, checked on the sources: a module includes only its own
headers and those of modules on lower floors; the third-party libraries stay behind the modules
that own them. A debt taken on knowingly goes in DEBTS with its reason (none today); each listed
debt must still exist, and nothing else may climb or cross a floor.

    check_floors.py SOURCE_DIR        # exit 1 listing every violation, one a line
"""

import os
import re
import sys

FLOORS = {
    "core": 0,  # bake/*.h, *.cpp
    "io": 1,
    "shards": 2,
    "illumination": 2, "radiosity": 2, "transport": 2,
    "lightmap": 3, "hq": 3, "reference": 3, "metrics": 3,
    "pipeline": 4, "probes": 3, "export": 4,
    "viewer": 5,
    "app": 6,
}

# (from, to): climbs taken on knowingly, each with its reason; docs/architecture.md lists them.
DEBTS = {
}

# Third-party headers (by prefix) and the modules allowed to include them.
OWNERS = {
    "embree3/": {"core:bake/accel.cpp"},
    "OpenMesh/": {"io", "illumination", "radiosity", "viewer"},
    "glad/": {"viewer"},
    "GLFW/": {"viewer"},
    "GL/": {"viewer"},
    "imgui": {"viewer"},
    "toml++/": {"io"},
    "tiny_gltf.h": {"io", "export"},
    "CLI/": {"app"},
}

INCLUDE = re.compile(r'^\s*#\s*include\s*([<"])([^>"]+)[>"]')


def module_of(relative):
    parts = relative.split("/")
    if parts[0] in ("viewer", "app"):
        return parts[0]
    if parts[0] == "bake":
        return "core" if len(parts) == 2 else parts[1]
    return None


def sources(root):
    for top in ("bake", "viewer", "app"):
        for folder, _, files in os.walk(os.path.join(root, top)):
            for name in sorted(files):
                if name.endswith((".h", ".cpp")):
                    path = os.path.join(folder, name)
                    yield os.path.relpath(path, root), path


def main():
    root = sys.argv[1]
    problems, seen_debts = [], set()
    for relative, path in sources(root):
        module = module_of(relative)
        if module not in FLOORS:
            problems.append(f"{relative}: module '{module}' has no floor in tests/docs/"
                            "check_floors.py (and docs/architecture.md): add it")
            continue
        with open(path, encoding="utf-8", errors="replace") as text:
            for number, line in enumerate(text, 1):
                match = INCLUDE.match(line)
                if not match:
                    continue
                kind, header = match.groups()
                where = f"{relative}:{number}: includes {header}"
                if kind == '"':
                    target = module_of(header)
                    if target is None or target == module:
                        continue
                    if target not in FLOORS:
                        problems.append(f"{where}, module '{target}' has no floor")
                    elif (module, target) in DEBTS:
                        seen_debts.add((module, target))
                    elif FLOORS[target] >= FLOORS[module]:
                        problems.append(f"{where}: {module} (floor {FLOORS[module]}) may not "
                                        f"include {target} (floor {FLOORS[target]})")
                    continue
                for prefix, owners in OWNERS.items():
                    if header.startswith(prefix) and module not in owners and \
                            f"{module}:{relative}" not in owners:
                        problems.append(f"{where}: only {', '.join(sorted(owners))} may")
    for debt, reason in DEBTS.items():
        if debt not in seen_debts:
            problems.append(f"the debt {debt[0]} -> {debt[1]} ({reason}) is paid: remove it from "
                            "tests/docs/check_floors.py and docs/architecture.md")
    for problem in problems:
        print(problem)
    print(f"check_floors: {len(problems)} problem(s)")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
