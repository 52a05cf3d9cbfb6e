#!/usr/bin/env bash
# Integration check of the farm files (deploy/slurm, docs/farm.md) on a real scheduler: starts a
# one-node Slurm cluster on 127.0.0.1 from Debian's slurm-wlm and munge and submits, through
# deploy/slurm/submit-shards.sh, each shardable command as an array and a dependent merge job:
#   render     bake job, render array, merge: the image against the unsharded render of that bake
#   bake       pass-1 array, merge: the maps and .bin files against the unsharded bake
#   reference  reference array, merge: the image and the report against the unsharded reference
#   export     export array (--contents all, on the render's bake), merge: the .glb's bytes and
#              its lightmap against the unsharded export
# Every job must end COMPLETED with exit 0:0 and every comparison show no difference. Each
# lightbake process runs under /usr/bin/time (a wrapper first on PATH), so the check prints the
# CPU seconds (user + sys) of the shards, the merges and the unsharded run. Not part of ctest:
#   scripts/slurm-check.sh [SCENE] [SHARDS]     (as root; installs slurm-wlm, munge and time)
#   CHECKS="bake reference"                     (default: render bake reference export)
#   RENDER_OPTIONS="--size 640x480 --spp 64"    (default 320x240, 16 spp)
#   BAKE_OPTIONS="--quality high"               (default: the scene's)
#   REFERENCE_OPTIONS="--size 320x240 --spp 256" (default 160x120, 64 spp)
#   EXPORT_OPTIONS="--direct-samples 8"         (default 2: 16 shadow rays a texel)
# Leaves the run in build/slurm-check/ and stops the daemons it started.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)
scene=$(realpath "${1:-scenes/cornell_glass.toml}")
shards=${2:-4}
read -r -a render_options <<< "${RENDER_OPTIONS:---size 320x240 --spp 16}"
read -r -a bake_options <<< "${BAKE_OPTIONS:-}"
read -r -a reference_options <<< "${REFERENCE_OPTIONS:---size 160x120 --spp 64}"
read -r -a export_options <<< "${EXPORT_OPTIONS:---direct-samples 2}"
read -r -a checks <<< "${CHECKS:-render bake reference export}"
unset BAKE_DIR
work="$root/build/slurm-check"
lightbake="$root/build/app/lightbake"
[[ -x $lightbake ]] || { echo "build first (scripts/test.sh or cmake --build build)" >&2; exit 1; }

if ! command -v slurmctld > /dev/null || ! command -v munged > /dev/null || [[ ! -x /usr/bin/time ]]
then
  DEBIAN_FRONTEND=noninteractive apt-get install -y -q slurm-wlm munge time > /dev/null
fi
rm -rf "$work"
mkdir -p "$work"/{spool/ctld,spool/d,munge,out}
pids=()
cleanup() {
  for pid in "${pids[@]}"; do kill "$pid" 2> /dev/null || true; done
}
trap cleanup EXIT

# munge: its own key, socket and logs under $work (no system service needed).
head -c 1024 /dev/urandom > "$work/munge/munge.key"
chmod 600 "$work/munge/munge.key"
munged --force --key-file="$work/munge/munge.key" --socket="$work/munge/socket" \
  --pid-file="$work/munge/munged.pid" --log-file="$work/munge/munged.log" \
  --seed-file="$work/munge/seed"
pids+=("$(cat "$work/munge/munged.pid")")

cpus=$(nproc)
cat > "$work/slurm.conf" << CONF
ClusterName=lightbake
SlurmctldHost=localhost(127.0.0.1)
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
AuthInfo=socket=$work/munge/socket
CredType=cred/munge
StateSaveLocation=$work/spool/ctld
SlurmdSpoolDir=$work/spool/d
SlurmctldPidFile=$work/slurmctld.pid
SlurmdPidFile=$work/slurmd.pid
SlurmctldLogFile=$work/slurmctld.log
SlurmdLogFile=$work/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
MpiDefault=none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
ReturnToService=2
MinJobAge=3600
DependencyParameters=kill_invalid_depend
NodeName=localhost NodeAddr=127.0.0.1 CPUs=$cpus State=UNKNOWN
PartitionName=main Nodes=localhost Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF="$work/slurm.conf"
slurmctld -D > "$work/slurmctld.out" 2>&1 &
pids+=("$!")
slurmd -D -N localhost > "$work/slurmd.out" 2>&1 &
pids+=("$!")
for _ in $(seq 60); do
  if sinfo -h -o %T 2> /dev/null | grep -qx idle; then break; fi
  sleep 1
done
sinfo -h -o "%P %D %T %c" | sed 's/^/slurm      /'
sinfo -h -o %T | grep -qx idle || { echo "slurm did not come up; see $work/*.log" >&2; exit 1; }

# Every lightbake the jobs and this script run is timed into $work/times.log.
mkdir -p "$work/bin"
cat > "$work/bin/lightbake" << WRAPPER
#!/bin/sh
exec /usr/bin/time -a -o "$work/times.log" -f "%e %U %S \$*" "$lightbake" "\$@"
WRAPPER
chmod +x "$work/bin/lightbake"
export PATH="$work/bin:$PATH"
failed=0
last_job=0

# Submits KIND in shards to OUT_DIR (further arguments: the command's options), waits for the
# queue to empty and prints every job's state and exit code; stops the check unless all
# COMPLETED 0:0 (a merge whose shards failed is cancelled: kill_invalid_depend).
submit() {
  local kind=$1 dir=$2 start
  shift 2
  start=$(date +%s)
  : > "$work/times.log"
  deploy/slurm/submit-shards.sh "$kind" "$scene" "$dir" "$shards" "$@" > /dev/null
  while squeue -h | grep -q .; do sleep 2; done
  echo "$kind: $shards-task array and merge finished in $(($(date +%s) - start)) s wall"
  if ! python3 - "$last_job" "$(scontrol -o show job)" << 'PY'; then
import re, sys
jobs = [dict(re.findall(r"(\w+)=(\S*)", line)) for line in sys.argv[2].splitlines()]
jobs = [j for j in jobs if int(j.get("JobId", 0)) > int(sys.argv[1])]
bad = [j for j in jobs if j["JobState"] != "COMPLETED" or j["ExitCode"] != "0:0"]
names = sorted(j["JobName"] + ("_" + j["ArrayTaskId"] if "ArrayTaskId" in j else "") for j in jobs)
print(f"jobs       {', '.join(names)}: " + ("all COMPLETED, exit 0:0" if jobs and not bad else
      "; ".join(f"{j['JobName']} {j['JobState']} exit {j['ExitCode']}" for j in bad) or "none"))
sys.exit(not jobs or bool(bad))
PY
    echo "FAIL: $kind: a job did not complete; logs in $dir" >&2
    exit 1
  fi
  last_job=$(scontrol -o show job | grep -o '^JobId=[0-9]*' | cut -d= -f2 | sort -n | tail -1)
}

# Prints the CPU seconds (user + sys) of the last submit's shards, merges and unsharded KIND.
seconds() {
  python3 - "$work/times.log" "$1" "$shards" << 'PY'
import sys
log, kind, shards = sys.argv[1], sys.argv[2], int(sys.argv[3])
runs = []
for line in open(log):
    f = line.split()
    if len(f) > 3 and f[0].replace(".", "").isdigit():
        runs.append((float(f[1]) + float(f[2]), f[3], "--shard" in f))
parts = [c for c, cmd, shard in runs if cmd == kind and shard]
merges = [c for c, cmd, _ in runs if cmd == "merge"]
whole = [c for c, cmd, shard in runs if cmd == kind and not shard][-1:]
print(f"cpu        shards {', '.join(f'{c:.2f}' for c in parts)} s (sum {sum(parts):.2f}); "
      f"merge {sum(merges):.2f} s; unsharded {whole[0]:.2f} s; (shards + merge) / unsharded = "
      f"{(sum(parts) + sum(merges)) / whole[0]:.2f}")
# A bake's shards are pass 1 only, its merge the rest of the bake: no per-shard ratio.
if kind != "bake":
    print(f"cpu        largest shard / (unsharded / {shards}) = {max(parts) / (whole[0] / shards):.2f}")
PY
}

# Prints `lightbake compare A B` and fails the check unless no value differs.
same_pixels() {
  local result
  result=$("$lightbake" compare "$1" "$2")
  echo "compare    ${1#"$work"/} $result"
  python3 -c 'import json, sys; sys.exit(json.loads(sys.argv[1])["differing_values"] != 0)' \
    "$result" || { echo "FAIL: ${1#"$work"/} differs from ${2#"$work"/}"; failed=1; }
}

same_bytes() {
  if cmp -s "$1" "$2"; then
    echo "cmp        ${1#"$work"/}: the bytes of ${2#"$work"/}"
  else
    echo "FAIL: ${1#"$work"/} differs from ${2#"$work"/}"
    failed=1
  fi
}

check_render() {
  submit render "$work/out" "${render_options[@]}"
  lightbake render "$scene" "$work/out/bake" "${render_options[@]}" -o "$work/whole.exr" -q \
    > /dev/null
  seconds render
  same_pixels "$work/out/render.exr" "$work/whole.exr"
}

check_bake() {
  submit bake "$work/bake-out" "${bake_options[@]}"
  lightbake bake "$scene" "${bake_options[@]}" -o "$work/whole-bake" -q > /dev/null
  seconds bake
  local map
  for map in illumination.exr soft_light.exr; do
    [[ -f $work/whole-bake/$map ]] && same_pixels "$work/bake-out/bake/$map" "$work/whole-bake/$map"
  done
  for map in illumination.bin radiosity.bin; do
    same_bytes "$work/bake-out/bake/$map" "$work/whole-bake/$map"
  done
}

check_reference() {
  submit reference "$work/reference-out" "${reference_options[@]}"
  mkdir -p "$work/whole-reference"
  lightbake reference "$scene" "${reference_options[@]}" -o "$work/whole-reference/reference.exr" \
    -q > /dev/null
  seconds reference
  same_pixels "$work/reference-out/reference.exr" "$work/whole-reference/reference.exr"
  # The report too: passes, noise estimate, image mean, ray counts; not the seconds.
  local merged="$work/reference-out/reference.json" whole="$work/whole-reference/reference.json"
  if ! python3 - "$merged" "$whole" << 'PY'; then
import json, sys
merged, whole = (json.load(open(path)) for path in sys.argv[1:])
timing = {"cpu_seconds", "wall_seconds", "rays_per_cpu_second", "output"}
fields = sorted(set(whole) - timing)
differ = [f for f in fields if merged.get(f) != whole[f]]
print(f"report     {len(fields) - len(differ)} of {len(fields)} fields equal "
      f"(all but {', '.join(sorted(timing))}){': differ ' + ', '.join(differ) if differ else ''}")
sys.exit(1 if differ else 0)
PY
    echo "FAIL: the merged reference report differs"
    failed=1
  fi
}

check_export() {
  local bake="$work/out/bake"
  if [[ ! -f $bake/manifest.json ]]; then
    bake="$work/export-bake"
    lightbake bake "$scene" -o "$bake" -q > /dev/null
  fi
  BAKE_DIR=$bake submit export "$work/export-out" "${export_options[@]}"
  mkdir -p "$work/whole-export"
  lightbake export "$scene" "$bake" --contents all "${export_options[@]}" \
    -o "$work/whole-export/export.glb" -q > /dev/null
  seconds export
  same_bytes "$work/export-out/export.glb" "$work/whole-export/export.glb"
  same_pixels "$work/export-out/export.lightmap.exr" "$work/whole-export/export.lightmap.exr"
}

for check in "${checks[@]}"; do
  case $check in
    render | bake | reference | export) "check_$check" ;;
    *) echo "unknown check '$check' (render, bake, reference, export)" >&2; exit 2 ;;
  esac
done
[[ $failed == 0 ]] || { echo "FAIL: see above; logs in $work" >&2; exit 1; }
echo "PASS: ${checks[*]}: every merged output has the bits of the unsharded run"
