#!/usr/bin/env bash
# Integration check of the farm files (deploy/slurm, docs/farm.md) on a real scheduler: starts a
# one-node Slurm cluster on 127.0.0.1 from Debian's slurm-wlm and munge, submits a sharded HQ
# render through deploy/slurm/submit.sh (bake job, render array, merge job) and checks the
# merged image bit for bit against the unsharded render of the same bake; then a sharded bake
# through deploy/slurm/submit-bake.sh (pass-1 array, merge job) against the unsharded bake.
# Not part of ctest:
#   scripts/slurm-check.sh [SCENE] [SHARDS]     (as root; installs slurm-wlm and munge)
#   RENDER_OPTIONS="--size 640x480 --spp 64" scripts/slurm-check.sh   (default 320x240, 16 spp)
#   BAKE_OPTIONS="--quality high" scripts/slurm-check.sh              (default: the scene's)
# Leaves the run in build/slurm-check/ and stops the daemons it started.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)
scene=$(realpath "${1:-scenes/cornell_glass.toml}")
shards=${2:-4}
read -r -a render_options <<< "${RENDER_OPTIONS:---size 320x240 --spp 16}"
read -r -a bake_options <<< "${BAKE_OPTIONS:-}"
work="$root/build/slurm-check"
lightbake="$root/build/app/lightbake"
[[ -x $lightbake ]] || { echo "build first (scripts/test.sh or cmake --build build)" >&2; exit 1; }

if ! command -v slurmctld > /dev/null || ! command -v munged > /dev/null; then
  DEBIAN_FRONTEND=noninteractive apt-get install -y -q slurm-wlm munge > /dev/null
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

export PATH="$root/build/app:$PATH"
start=$(date +%s)
merge_job=$(deploy/slurm/submit.sh "$scene" "$work/out" "$shards" "${render_options[@]}")
echo "submitted  bake, $shards-task render array, merge (job $merge_job)"
while squeue -h | grep -q .; do sleep 2; done
echo "finished   in $(($(date +%s) - start)) s wall"
[[ -f $work/out/render.exr ]] || { echo "no merged render; logs in $work/out" >&2; exit 1; }

"$lightbake" render "$scene" "$work/out/bake" "${render_options[@]}" -o "$work/whole.exr" -q \
  > /dev/null
result=$("$lightbake" compare "$work/out/render.exr" "$work/whole.exr")
echo "compare    $result"
python3 - "$work" "$shards" "$result" << 'PY'
import json, sys
work, shards, result = sys.argv[1], int(sys.argv[2]), json.loads(sys.argv[3])
parts = [json.load(open(f"{work}/out/shard_{i}.json"))["render_seconds"] for i in range(shards)]
whole = json.load(open(f"{work}/whole.json"))["render_seconds"]
print(f"seconds    shards {', '.join(f'{s:.2f}' for s in parts)}; whole {whole:.2f}; "
      f"largest shard / (whole / {shards}) = {max(parts) / (whole / shards):.2f}")
if result["differing_values"] != 0:
    sys.exit(f"FAIL: merged render differs from the whole in {result['differing_values']} values")
print("PASS: the merged shards have the bits of the unsharded render")
PY

# The bake itself in shards: a pass-1 array and the merge job, against the unsharded bake.
start=$(date +%s)
merge_job=$(deploy/slurm/submit-bake.sh "$scene" "$work/bake-out" "$shards" "${bake_options[@]}")
echo "submitted  $shards-task pass-1 array, merge (job $merge_job)"
while squeue -h | grep -q .; do sleep 2; done
echo "finished   in $(($(date +%s) - start)) s wall"
[[ -f $work/bake-out/bake/manifest.json ]] || { echo "no merged bake; logs in $work/bake-out" >&2; exit 1; }
"$lightbake" bake "$scene" "${bake_options[@]}" -o "$work/whole-bake" -q > /dev/null
differing=0
for map in illumination.exr soft_light.exr; do
  [[ -f $work/whole-bake/$map ]] || continue
  result=$("$lightbake" compare "$work/bake-out/bake/$map" "$work/whole-bake/$map")
  echo "compare    $map $result"
  python3 -c 'import json, sys; sys.exit(json.loads(sys.argv[1])["differing_values"] != 0)' \
    "$result" || differing=1
done
for bin in illumination.bin radiosity.bin; do
  cmp -s "$work/bake-out/bake/$bin" "$work/whole-bake/$bin" || { echo "differs    $bin"; differing=1; }
done
python3 - "$work/bake-out" "$shards" << 'PY'
import json, sys
out, shards = sys.argv[1], int(sys.argv[2])
parts = [json.load(open(f"{out}/pass1_{i}.json"))["seconds"] for i in range(shards)]
print(f"seconds    pass-1 shards {', '.join(f'{s:.2f}' for s in parts)}")
PY
[[ $differing == 0 ]] || { echo "FAIL: the merged bake differs from the unsharded one" >&2; exit 1; }
echo "PASS: the merged pass-1 shards have the bits of the unsharded bake"
