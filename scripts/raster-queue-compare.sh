#!/bin/bash
# Usage: scripts/raster-queue-compare.sh OLD_BIN NEW_BIN OUT_DIR (llvmpipe, 128² screen)
# Side by side, interleaved: the compute raster before (OLD) and after (NEW) the queue change.
# ROUNDS (default 3) and CASES ("scene method raster map_size" per line) override the run, so a
# test can drive the script on a small scene.
OLD=$1; NEW=$2; OUT=$3; mkdir -p "$OUT"
ROUNDS=${ROUNDS:-3}
CASES=${CASES:-"teapot regular:n=4,layout=centred compute 2048
teapot regular:n=4,layout=centred hardware 2048
teapot regions compute 512
teapot regions hardware 512"}
echo "round,build,scene,method,raster,map_size,maps,total_ms,raster_ms" > "$OUT/rows.csv"
for round in $(seq 1 "$ROUNDS"); do
 for build in old new; do
  B=$OLD; [ $build = new ] && B=$NEW
  while read -r scene method raster size; do
   [ -n "$scene" ] || continue
   d=$OUT/run-$build-$round; rm -rf "$d"
   "$B" render --scene "$scene" --method "$method" --set raster="$raster" --set resolution=128 --set shadow_map_size="$size" --out "$d" >/dev/null 2>&1 || { echo "failed: $build $scene $method $raster $size"; exit 1; }
   python3 - "$d/run.json" "$round" "$build" "$scene" "$method" "$raster" "$size" >> "$OUT/rows.csv" <<'PY'
import csv, json, sys
path, round_, build, scene, method, raster, size = sys.argv[1:]
j = json.load(open(path))
s = j["stages_ms"]
r = s.get("raster_compute", s.get("shadow_raster"))
csv.writer(sys.stdout, lineterminator="\n").writerow([round_, build, scene, method, raster, size, j["shadow_maps"], round(j["total_ms"], 1), round(r, 1)])
PY
   rm -rf "$d"
  done <<< "$CASES"
 done
done
cat "$OUT/rows.csv"
