#!/bin/bash
# A real test of scripts/slurm/ on this machine: installs Slurm and munge from the Debian
# packages (slurm-wlm, munge) if missing, starts munged, slurmctld and slurmd on localhost, runs
# the spec single-process, submits it as 4 shards plus the merge job, waits, and checks that the
# merged rows equal the single-process rows in everything but timings. Needs root (it installs
# and starts system daemons), so it is not part of CI; see docs/sharding.md.
#
#   sudo scripts/slurm-local-test.sh [SPEC] [sweep arguments…]
#
# Defaults: scripts/slurm/sweep-default-24.toml on `default` at --set resolution=128 --repeats 1.
# The local node has no gres GPU: the test sets GRES empty (lavapipe runs on the CPUs).
# Daemons it started are stopped at the end unless KEEP_SLURM=1. It prints which build it tested:
# the checkout's git hash (`-dirty` when the tree has changes) and the binary's version and git hash.
set -euo pipefail
cd "$(dirname "$(realpath "$0")")/.."
spec=$(realpath "${1:-scripts/slurm/sweep-default-24.toml}")
shift || true
args=("$@")
[ ${#args[@]} -gt 0 ] || args=(--set resolution=128 --repeats 1)
work=${WORK:-$(mktemp -d /tmp/penumbra-slurm.XXXXXX)}
mkdir -p "$work"
as_root() { if [ "$(id -u)" = 0 ]; then "$@"; else sudo "$@"; fi; }
now() { date +%s.%N; }
since() { printf '%.1f' "$(echo "$(now) - $1" | bc)"; }

t0=$(now)
if ! command -v slurmctld >/dev/null || ! command -v munged >/dev/null; then
    as_root env DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends slurm-wlm munge bc jq >/dev/null
fi
command -v jq >/dev/null && command -v bc >/dev/null || as_root env DEBIAN_FRONTEND=noninteractive apt-get install -y jq bc >/dev/null
echo "install: $(since "$t0") s"

# munge: a key, then the daemon.
t1=$(now)
if [ ! -s /etc/munge/munge.key ]; then
    as_root mkdir -p /etc/munge
    as_root dd if=/dev/urandom of=/etc/munge/munge.key bs=1024 count=1 status=none
fi
as_root chown munge:munge /etc/munge/munge.key && as_root chmod 400 /etc/munge/munge.key
as_root mkdir -p /run/munge /var/log/munge /var/lib/munge && as_root chown munge:munge /run/munge /var/log/munge /var/lib/munge
started=()
if ! munge -n >/dev/null 2>&1; then
    as_root runuser -u munge -- /usr/sbin/munged
    started+=(munged)
fi
munge -n | unmunge >/dev/null

# Slurm: one node (this host), one partition, no cgroups, no accounting; the node has no GPU.
host=$(hostname -s)
cpus=$(nproc)
mem=$(awk '/MemTotal/ { print int($2 / 1024 * 0.9) }' /proc/meminfo)
conf=/etc/slurm/slurm.conf
if [ -e "$conf" ] && ! grep -q "penumbra-local" "$conf"; then
    echo "$conf exists and was not written by this script: run it on a disposable machine, not a configured cluster" >&2
    exit 1
fi
if [ ! -e "$conf" ]; then
    as_root mkdir -p /etc/slurm /var/spool/slurmctld /var/spool/slurmd /var/log/slurm
    as_root tee "$conf" >/dev/null <<CONF
# penumbra-local: written by scripts/slurm-local-test.sh
ClusterName=penumbra-local
SlurmctldHost=$host
SlurmUser=root
AuthType=auth/munge
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
SchedulerType=sched/backfill
StateSaveLocation=/var/spool/slurmctld
SlurmdSpoolDir=/var/spool/slurmd
SlurmctldLogFile=/var/log/slurm/slurmctld.log
SlurmdLogFile=/var/log/slurm/slurmd.log
SlurmctldPidFile=/run/slurmctld.pid
SlurmdPidFile=/run/slurmd.pid
ReturnToService=2
MinJobAge=600
NodeName=$host NodeAddr=127.0.0.1 CPUs=$cpus RealMemory=$mem State=UNKNOWN
PartitionName=local Nodes=$host Default=YES MaxTime=INFINITE State=UP
CONF
fi
if ! scontrol ping 2>/dev/null | grep -q UP; then
    as_root /usr/sbin/slurmctld
    started+=(slurmctld)
fi
if ! pgrep -x slurmd >/dev/null; then
    as_root /usr/sbin/slurmd
    started+=(slurmd)
fi
stop() {
    [ "${KEEP_SLURM:-0}" = 1 ] && return
    for d in "${started[@]}"; do
        case $d in
            slurmd) [ -s /run/slurmd.pid ] && as_root kill "$(cat /run/slurmd.pid)" ;;
            slurmctld) [ -s /run/slurmctld.pid ] && as_root kill "$(cat /run/slurmctld.pid)" ;;
            munged) [ -s /run/munge/munged.pid ] && as_root kill "$(cat /run/munge/munged.pid)" ;;
        esac
    done
}
trap stop EXIT
for _ in $(seq 60); do
    sinfo -h -o %T 2>/dev/null | grep -qE '^(idle|mixed|allocated)' && break
    sleep 1
done
sinfo -h -o "%P %D %T %c" | grep -qE 'idle|mixed' || { echo "slurm node is not up: $(sinfo)" >&2; exit 1; }
echo "daemons up: $(since "$t1") s ($(sinfo -h -o '%N, %c CPUs, %T'))"

cargo build --release --quiet
export PENUMBRA_CACHE="$work/cache" PENUMBRA_NO_PROGRESS=1
# Which build is tested: the checkout (its hash, `-dirty` when the tree differs from it; under sudo
# the tree belongs to another user, hence safe.directory) and the git hash the binary was built
# from (`--version`; the same as every row's `version.git`).
git_() { git -c safe.directory="$PWD" "$@"; }
tree=$(git_ rev-parse --short=12 HEAD 2>/dev/null || echo "no git checkout")
[ -z "$(git_ status --porcelain 2>/dev/null)" ] || tree+="-dirty"
echo "checkout: $tree; binary: $(target/release/penumbra --version)"

t2=$(now)
target/release/penumbra sweep --spec "$spec" "${args[@]}" --out "$work/single" >"$work/single.log" 2>&1
single_s=$(since "$t2")
echo "single process: $single_s s wall clock ($(wc -l <"$work/single/results.jsonl") rows; reference traced here)"
built=$(jq -r '.version.git' "$work/single/results.jsonl" | sort -u | paste -sd ';')
[[ $tree == "$built"* ]] || echo "note: the rows' git hash $built is not the checkout's $tree" >&2

# The shards get a cold cache of their own, so they trace the reference once between them.
export PENUMBRA_CACHE="$work/cache-shards"
t3=$(now)
read -r array merge < <(GRES= scripts/slurm/submit.sh "$spec" "$work/sharded" 4 "${args[@]}")
echo "submitted array job $array (4 shards) and merge job $merge (afterok:$array)"
while squeue -h -j "$array,$merge" 2>/dev/null | grep -q .; do sleep 1; done
sharded_s=$(since "$t3")
state=$(scontrol show job "$merge" 2>/dev/null | grep -o 'JobState=[A-Z]*' | head -1)
[ -s "$work/sharded/results.jsonl" ] || { echo "merge job $merge: $state, no merged results; logs in $work/sharded" >&2; exit 1; }
echo "slurm, 4 shards + merge: $sharded_s s wall clock (submit to merged), $state"
traced=$(grep -l '"cached": false' "$work"/sharded/shards/*/reference.json | wc -l)
echo "shards that traced the reference: $traced of 4"

strip='del(.frame_ms, .frame_ms_min, .frame_ms_max, .frame_ms_runs, .stages_ms, .setup_ms, .provenance.spec.shard)'
if diff <(jq -cS "$strip" "$work/single/results.jsonl") <(jq -cS "$strip" "$work/sharded/results.jsonl") >"$work/diff.txt"; then
    echo "OK: the merged rows equal the single-process rows in everything but timings ($(wc -l <"$work/sharded/results.jsonl") rows)"
else
    echo "FAIL: merged rows differ from the single-process rows: $work/diff.txt" >&2
    exit 1
fi
[ "$traced" = 1 ] || { echo "FAIL: $traced shards traced the reference (expected 1)" >&2; exit 1; }
echo "outputs: $work (single/, sharded/report.html); tested build: penumbra $built, checkout $tree"
