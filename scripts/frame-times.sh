#!/bin/bash
# Median frame times of two binaries, measured in alternating runs (A B A B …) so drift in the
# machine's speed hits both alike: `penumbra render --timing frame --warm-up 1`, total_ms of
# run.json (wall clock), on one scene, for a few methods.
#
#   scripts/frame-times.sh OLD_BINARY NEW_BINARY [SCENE] [RUNS]
set -euo pipefail
old=$(realpath "$1")
new=$(realpath "$2")
scene=${3:-default}
runs=${4:-5}
work=$(mktemp -d /tmp/penumbra-frame-times.XXXXXX)
export PENUMBRA_NO_PROGRESS=1
methods=(hard pcss regular:n=5,layout=centred regular:n=17 adaptive:preset=seed adaptive:preset=balanced adaptive:preset=balanced,scope=local,cull=on)
median() { sort -n | awk '{ v[NR] = $1 } END { print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }
printf '%-46s %12s %12s %7s\n' "method ($scene, wall clock ms)" old new new/old
for m in "${methods[@]}"; do
    : >"$work/old" && : >"$work/new"
    for _ in $(seq "$runs"); do
        for side in old new; do
            bin=$old && [ $side = new ] && bin=$new
            "$bin" render --scene "$scene" --method "$m" --timing frame --warm-up 1 --out "$work/out-$side" >/dev/null
            python3 -c 'import json, sys; print(json.load(open(sys.argv[1]))["total_ms"])' "$work/out-$side/run.json" >>"$work/$side"
        done
    done
    a=$(median <"$work/old") b=$(median <"$work/new")
    printf '%-46s %12.1f %12.1f %7.3f\n' "$m" "$a" "$b" "$(echo "$b / $a" | bc -l)"
done
rm -rf "$work"
