#!/bin/bash
# Submits a sharded sweep: an array job with one task per shard, then a merge job that runs only
# if every shard succeeded. Prints "ARRAY_JOB_ID MERGE_JOB_ID".
#
#   scripts/slurm/submit.sh SPEC OUT SHARDS [sweep arguments…]
#
# GRES: the GPU request of each shard task (default `gpu:1`); set it empty for nodes without a
# gres GPU (lavapipe on CPUs): GRES= scripts/slurm/submit.sh …
# PENUMBRA: the binary (default target/release/penumbra); PENUMBRA_CACHE: the reference cache,
# on a file system every node sees (default ~/.cache/penumbra). Extra sbatch options: SBATCH_ARGS.
set -euo pipefail
if [ $# -lt 3 ]; then
    echo "usage: $0 SPEC OUT SHARDS [sweep arguments…]" >&2
    exit 2
fi
spec=$(realpath "$1")
out=$(realpath -m "$2")
shards=$3
shift 3
case "$shards" in '' | *[!0-9]* | 0) echo "$0: SHARDS must be a positive integer, got '$shards'" >&2; exit 2 ;; esac
export SPEC="$spec" OUT="$out" SHARDS="$shards" SWEEP_ARGS="$*"
export PENUMBRA="${PENUMBRA:-$(realpath target/release/penumbra)}"
export PENUMBRA_CACHE="${PENUMBRA_CACHE:-$HOME/.cache/penumbra}"
export PENUMBRA_NO_PROGRESS=1
GRES="${GRES-gpu:1}"
here=$(dirname "$(realpath "$0")")
mkdir -p "$out"
# shellcheck disable=SC2086
array=$(sbatch --parsable --chdir="$out" --array="0-$((shards - 1))" ${GRES:+--gres="$GRES"} ${SBATCH_ARGS:-} "$here/sweep-array.sbatch")
# shellcheck disable=SC2086
merge=$(sbatch --parsable --chdir="$out" --dependency="afterok:$array" ${SBATCH_ARGS:-} "$here/merge.sbatch")
echo "$array $merge"
