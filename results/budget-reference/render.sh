#!/bin/bash
# Renders what reference.py reads for one scene at 128²: auto's ladder among the frontier's fixed
# settings (centred grids n = 2-6 and 8, pcss, msm at 512² and 1024² maps) and the finest grid
# auto may choose (17×17 centred at 2048²), each with its visibility.exr and the ground truth.
# Usage (in this folder): PENUMBRA=bin ./render.sh SCENE OUT   (writes OUT/SCENE/{512,1024,512-msm,1024-msm,ref})
bin=${PENUMBRA:-penumbra}
scene=$1; out=$2/$scene
mkdir -p "$out"
ladder=regular:n=2,layout=centred,regular:n=3,layout=centred,regular:n=4,layout=centred,regular:n=5,layout=centred,regular:n=6,layout=centred,regular:n=8,layout=centred,pcss
for size in 512 1024; do
  PENUMBRA_NO_PROGRESS=1 "$bin" compare --scene "$scene" --set resolution=128 --set shadow_map_size=$size \
    --methods "$ladder" --repeats 1 --out "$out/$size" > "$out/$size.log" 2>&1 || { echo "$scene $size failed: $(tail -1 "$out/$size.log")" >&2; exit 1; }
  # msm refuses a ball light (as auto's default filters leave it out there): its own run, allowed to refuse.
  PENUMBRA_NO_PROGRESS=1 "$bin" compare --scene "$scene" --set resolution=128 --set shadow_map_size=$size \
    --methods msm --repeats 1 --out "$out/$size-msm" > "$out/$size-msm.log" 2>&1 ||
    grep -q "is not supported" "$out/$size-msm.log" || { echo "$scene $size msm failed: $(tail -1 "$out/$size-msm.log")" >&2; exit 1; }
done
PENUMBRA_NO_PROGRESS=1 "$bin" compare --scene "$scene" --set resolution=128 --set shadow_map_size=2048 \
  --methods regular:n=17,layout=centred --repeats 1 --out "$out/ref" > "$out/ref.log" 2>&1 || { echo "$scene ref failed: $(tail -1 "$out/ref.log")" >&2; exit 1; }
