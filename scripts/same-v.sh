#!/bin/bash
# Renders every method (and the settings that take other code paths) on `default` and
# `analytic-square` with two binaries and compares V byte for byte (visibility.exr), e.g. before
# and after a restructuring that must not change behaviour:
#
#   scripts/same-v.sh OLD_BINARY NEW_BINARY [WORK_DIR]
#
# Prints one line per (scene, method): `same` or `DIFFERS`, and exits 1 if any differs.
# SAME_V_SCENES and SAME_V_METHODS (space-separated) replace the scenes and the methods, e.g. the
# point-light scenes with the methods that run on a point light.
set -euo pipefail
old=$(realpath "$1")
new=$(realpath "$2")
work=${3:-$(mktemp -d /tmp/penumbra-same-v.XXXXXX)}
methods=(
    hard pcf pcf:kernel=box pcf:kernel=bilinear pcf:kernel=stratified pcf:kernel=rotated pcss
    esm vsm evsm msm csm
    regular:n=5 regular:n=5,layout=centred regular:n=4,layout=jittered regular
    adaptive adaptive:preset=seed adaptive:preset=balanced adaptive:preset=balanced,steer=gpu
    adaptive:preset=balanced,scope=local adaptive:preset=balanced,scope=local,cull=on
    adaptive:scope=local,scissor=on adaptive:p_m=0,max_level=2,weights=coons,layout=centred
    adaptive:tol=0.01 adaptive:p_share=0.001,growth=2
    # hybrid-resolution maps under the methods that read them
    "hard --set maps=hybrid --set base=1024" "pcss --set maps=hybrid --set base=1024"
    "regular:n=5 --set maps=hybrid --set base=1024" "adaptive:preset=balanced --set maps=hybrid --set base=1024"
)
if [ -n "${SAME_V_METHODS:-}" ]; then
    read -r -a methods <<<"$SAME_V_METHODS"
fi
read -r -a scenes <<<"${SAME_V_SCENES:-default analytic-square}"
export PENUMBRA_NO_PROGRESS=1
differ=0
for scene in "${scenes[@]}"; do
    for m in "${methods[@]}"; do
        slug=$(echo "$scene-$m" | tr ':,= ' '____')
        # shellcheck disable=SC2086 # the entry's extra --set arguments split on spaces
        set -- $m
        "$old" render --scene "$scene" --method "$@" --warm-up 0 --out "$work/old/$slug" >/dev/null
        "$new" render --scene "$scene" --method "$@" --warm-up 0 --out "$work/new/$slug" >/dev/null
        if cmp -s "$work/old/$slug/visibility.exr" "$work/new/$slug/visibility.exr"; then
            echo "same     $scene  $m"
        else
            echo "DIFFERS  $scene  $m"
            differ=1
        fi
    done
done
echo "outputs in $work"
exit $differ
