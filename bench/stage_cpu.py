#!/usr/bin/python3
"""CPU seconds (user + system, every thread) of a lightbake command per progress stage.

    bench/stage_cpu.py -- build/app/lightbake bake scenes/room.toml -o BAKE

Reads the command's progress lines ("1.23 s  STAGE  40%") on stderr and the process's CPU time
(/proc/PID/stat) whenever the stage changes; the time after the last stage's 100% line is
"after the last stage" (the bake's last filters, its files, exit). Linux only. Complements
bench/profile_stages.py, which splits by function, not by stage.
"""

import os
import re
import subprocess
import sys

PROGRESS = re.compile(r"\s*[\d.]+ s\s+([a-z][a-z0-9 :\-]*[a-z])")


def main():
    command = sys.argv[1:]
    if command[:1] == ["--"]:
        command = command[1:]
    if not command:
        sys.exit(__doc__)
    child = subprocess.Popen(command, stderr=subprocess.PIPE, stdout=subprocess.DEVNULL)
    tick = os.sysconf("SC_CLK_TCK")

    def cpu_seconds():
        try:
            with open(f"/proc/{child.pid}/stat") as stat:
                fields = stat.read().rsplit(")", 1)[1].split()
            return (int(fields[11]) + int(fields[12])) / tick
        except (OSError, IndexError, ValueError):
            return None

    marks = [(0.0, "start-up (before the first stage)")]
    finished = None  # CPU seconds when the latest stage printed 100%
    line = b""
    while True:
        byte = child.stderr.read(1)
        if not byte:
            break
        if byte not in b"\r\n":
            line += byte
            continue
        text = line.decode(errors="replace")
        line = b""
        match = PROGRESS.match(text)
        if not match:
            continue
        now = cpu_seconds()
        if now is None:
            continue
        if match.group(1) != marks[-1][1]:
            marks.append((now, match.group(1)))
            finished = None
        if "100%" in text:
            finished = now
    usage = os.wait4(child.pid, 0)[2]
    total = usage.ru_utime + usage.ru_stime
    if finished is not None:
        marks.append((finished, "after the last stage (filters, files, exit)"))
    marks.append((total, ""))
    print(f"| stage | CPU s |  (`{' '.join(command)}`: {total:.2f} CPU s)")
    print("| --- | --- |")
    for (start, name), (end, _) in zip(marks, marks[1:]):
        print(f"| {name} | {end - start:.2f} |")


if __name__ == "__main__":
    main()
