#!/usr/bin/python3
"""Every link in the project's Markdown files resolves: relative links [text](path#anchor) name
a file or folder that exists (and a heading of it, when an anchor is given), and paths written
in backticks under the source folders (`docs/farm.md`, `bake/pipeline/bake.h`) exist.

    /usr/bin/python3 tests/docs/check_links.py [ROOT]    # prints each broken link; exit 1 if any
"""

import os
import re
import sys

ROOT = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else
                       os.path.join(os.path.dirname(__file__), "..", ".."))
# Folders whose paths the docs name in backticks; build/, out/ and the like are outputs.
SOURCE_DIRS = ("app", "bake", "bench", "deploy", "docs", "fuzz", "scenes", "scripts", "shaders",
               "tests", "viewer")
SKIP_DIRS = {".git", "build", "build-asan", "node_modules", "out"}

LINK = re.compile(r"!?\[[^\]]*\]\(([^)\s]+)(?:\s+\"[^\"]*\")?\)")
CODE = re.compile(r"`([^`\s]+)`")
FENCE = re.compile(r"^\s*(```|~~~)")


def markdown_files():
    for folder, dirs, files in os.walk(ROOT):
        dirs[:] = sorted(d for d in dirs if d not in SKIP_DIRS and not d.startswith("build"))
        for name in sorted(files):
            if name.endswith(".md"):
                yield os.path.join(folder, name)


def slug(heading):
    """GitHub's anchor for a heading: lower case, punctuation dropped, spaces to '-'."""
    text = re.sub(r"[`*_]|\[([^\]]*)\]\([^)]*\)", lambda m: m.group(1) or "", heading)
    text = re.sub(r"[^\w\- ]", "", text.strip().lower())
    return text.replace(" ", "-")


def anchors(path):
    found, counts, fenced = set(), {}, False
    with open(path, encoding="utf-8") as f:
        for line in f:
            if FENCE.match(line):
                fenced = not fenced
            elif not fenced and line.startswith("#"):
                base = slug(line.lstrip("#"))
                n = counts.get(base, 0)
                counts[base] = n + 1
                found.add(base if n == 0 else f"{base}-{n}")
    return found


def check_file(path):
    problems, fenced = [], False
    here = os.path.dirname(path)
    with open(path, encoding="utf-8") as f:
        lines = f.readlines()
    for number, line in enumerate(lines, 1):
        if FENCE.match(line):
            fenced = not fenced
            continue
        if fenced:
            continue
        where = f"{os.path.relpath(path, ROOT)}:{number}"
        for target in LINK.findall(line):
            if re.match(r"^[a-z][a-z0-9+.-]*:", target):  # http:, https:, mailto:
                continue
            file_part, _, anchor = target.partition("#")
            resolved = os.path.normpath(os.path.join(here, file_part)) if file_part else path
            if not os.path.exists(resolved):
                problems.append(f"{where}: link to {target}: no such file")
            elif anchor and resolved.endswith(".md") and anchor not in anchors(resolved):
                problems.append(f"{where}: link to {target}: no such heading")
        for span in CODE.findall(line):
            candidate = re.sub(r":\d+$", "", span.rstrip(".,:;"))  # file.cpp:112
            if (candidate.split("/")[0] in SOURCE_DIRS and "/" in candidate
                    and not re.search(r"[*?<>{}$]|\.\.\.|[A-Z]{4,}|_N\b", candidate)
                    and not os.path.exists(os.path.join(ROOT, candidate))
                    and not os.path.exists(os.path.join(ROOT, candidate + ".cpp"))):  # a program
                problems.append(f"{where}: path {candidate}: no such file")
    return problems


def main():
    problems = [p for path in markdown_files() for p in check_file(path)]
    for problem in problems:
        print(problem)
    print(f"check_links: {len(problems)} broken link(s)", file=sys.stderr)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
