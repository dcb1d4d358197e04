#!/bin/bash
# Renders every method of `penumbra methods` (and the settings that take other code paths) with
# two binaries and compares V byte for byte (visibility.exr), e.g. before and after a
# restructuring that must not change behaviour:
#
#   scripts/same-v.sh OLD_BINARY NEW_BINARY [WORK_DIR] [ROWS.csv]
#   scripts/same-v.sh --coverage BINARY      only checks that every method it lists has a setting
#
# The area-light methods run on `default` and `analytic-square`, `cascades` on `sun-edge` (a sun),
# the environment methods on `envtest`: the 40² scene of lab/tests/env_twins.rs under its 64x32
# sky, which this script writes (the shipped environment scenes need a fetched panorama). `auto`
# prices its map sizes by texels (`cost=texels`): by default it prices them from its own timed
# frames, so two runs of one build may choose differently.
# Prints one line per (scene, setting): `same` or `DIFFERS`, and ROWS.csv gets them as rows
# (verdict, scene, method). Exits 1 if any differs, 2 if a method the new binary lists has no
# setting here.
# SAME_V_SCENES and SAME_V_METHODS (space-separated) replace the scenes and the methods, e.g. the
# point-light scenes with the methods that run on a point light: then only those run.
set -euo pipefail
coverage=no
if [ "$1" = --coverage ]; then coverage=yes; shift; set -- "$1" "$1"; fi
old=$(realpath "$1")
new=$(realpath "$2")
area=(
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
    # the error budget: the grid it grows to, a one-map filter, no filters; the per-region method
    auto:cost=texels auto:cost=texels,target=0.03 auto:cost=texels,filters=none
    regions regions:target=0.012 regions:merge=off regions:force=3
)
sun=(cascades cascades:filter=pcf cascades:n=2,split=log)
env=(env-pixels env-pixels:at=vertex env-pixels:ssao=on,ao_samples=12 env-shadowmaps ssao env-adaptive)

# Every method the new binary lists (a line that starts with its name) has a setting above.
missing=()
for m in $("$new" methods | awk '/^[a-z]/ { print $1 }'); do
    found=no
    for s in "${area[@]}" "${sun[@]}" "${env[@]}"; do
        s=${s%% *}
        [ "${s%%:*}" = "$m" ] && found=yes && break
    done
    [ $found = yes ] || missing+=("$m")
done
if [ "${#missing[@]}" -gt 0 ]; then
    echo "same-v: no setting here for ${missing[*]}: add them to scripts/same-v.sh" >&2
    exit 2
fi
[ $coverage = no ] || { echo "same-v: every method $new lists has a setting here"; exit 0; }
work=${3:-$(mktemp -d /tmp/penumbra-same-v.XXXXXX)}
rows=${4:-/dev/null}

# The environment methods' scene: lab/tests/env_twins.rs's, its sky a Radiance HDR.
mkdir -p "$work/envtest"
python3 - "$work/envtest" <<'PY'
import math, pathlib, sys
d = pathlib.Path(sys.argv[1])
def rgbe(r, g, b):
    m, e = math.frexp(max(r, g, b))
    s = m * 256 / max(r, g, b)
    return bytes([int(r * s), int(g * s), int(b * s), e + 128])
w, h = 64, 32
sky = bytearray(b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y %d +X %d\n" % (h, w))
for y in range(h):
    for x in range(w):
        l = 2000.0 if 19 <= x < 21 and 7 <= y < 9 else (0.5 + 0.04 * y if y < 16 else 0.05)
        sky += rgbe(l, l * 0.9, l * 0.8)
(d / "sky.hdr").write_bytes(bytes(sky))
(d / "envtest.toml").write_text('''name = "envtest"
[camera]
eye = [0.0, 7.0, 9.0]
target = [0.0, 0.5, 0.0]
fov_y_deg = 45.0
[environment]
panorama = "sky.hdr"
rotation_deg = 30.0
[render]
width = 40
height = 40
shadow_map_size = 128
[[mesh]]
builtin = "plane"
scale = [12.0, 1.0, 12.0]
[[mesh]]
builtin = "box"
translate = [0.0, 1.0, 0.0]
rotate_deg = [0.0, 30.0, 0.0]
scale = [2.0, 2.0, 1.0]
[[mesh]]
builtin = "sphere"
segments = 12
translate = [2.5, 0.8, 1.5]
scale = 1.6
''')
PY

export PENUMBRA_NO_PROGRESS=1
differ=0
echo "verdict,scene,method" >"$rows"
check() { # SCENE SETTING...
    local scene=$1 name
    shift
    for m in "$@"; do
        name=$(basename "$scene" .toml)
        slug=$(echo "$name-$m" | tr ':,= ' '____')
        # shellcheck disable=SC2086 # the entry's extra --set arguments split on spaces
        set -- $m
        "$old" render --scene "$scene" --method "$@" --warm-up 0 --out "$work/old/$slug" >/dev/null
        "$new" render --scene "$scene" --method "$@" --warm-up 0 --out "$work/new/$slug" >/dev/null
        if cmp -s "$work/old/$slug/visibility.exr" "$work/new/$slug/visibility.exr"; then
            verdict=same
        else
            verdict=DIFFERS
            differ=1
        fi
        printf '%-8s %s  %s\n' "$verdict" "$name" "$m"
        echo "$verdict,$name,\"$m\"" >>"$rows"
    done
}
if [ -n "${SAME_V_SCENES:-}${SAME_V_METHODS:-}" ]; then
    chosen=("${area[@]}")
    [ -z "${SAME_V_METHODS:-}" ] || read -r -a chosen <<<"$SAME_V_METHODS"
    read -r -a scenes <<<"${SAME_V_SCENES:-default analytic-square}"
    for scene in "${scenes[@]}"; do
        check "$scene" "${chosen[@]}"
    done
else
    for scene in default analytic-square; do
        check "$scene" "${area[@]}"
    done
    check sun-edge "${sun[@]}"
    check "$work/envtest/envtest.toml" "${env[@]}"
fi
echo "outputs in $work"
exit $differ
