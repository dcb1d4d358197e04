#!/bin/bash
# Where a frame's time goes at each map size: `penumbra render` of regular:n=N,layout=centred on
# each scene at 128², maps of each size, with the stage timing (a wait after each stage), repeated
# in ROUNDS interleaved rounds. One CSV row per render.
# Usage: PENUMBRA=bin ROUNDS=3 ./frame-split.sh > frame-split.csv
bin=${PENUMBRA:-penumbra}
out=$(mktemp -d)
echo "round,scene,n,map_size,total_ms,shadow_raster_ms,shade_ms,gbuffer_ms,readback_ms"
for round in $(seq 1 "${ROUNDS:-3}"); do
  for scene in ${SCENES:-cows default}; do
    for n in ${SIDES:-3 5}; do
      for size in ${SIZES:-512 1024 2048}; do
        PENUMBRA_NO_PROGRESS=1 "$bin" render --scene "$scene" --set resolution=128 --set shadow_map_size="$size" \
          --method "regular:n=$n,layout=centred" --out "$out/r" > /dev/null 2>&1 || { echo "failed: $scene $n $size" >&2; continue; }
        jq -r --arg r "$round" --arg n "$n" '[$r, .scene, $n, .shadow_map_size, .total_ms, .stages_ms.shadow_raster, .stages_ms.shade, .stages_ms.gbuffer, .stages_ms.readback] | @csv' "$out/r/run.json"
      done
    done
  done
done
rm -rf "$out"
