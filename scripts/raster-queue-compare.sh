#!/bin/bash
# Usage: scripts/raster-queue-compare.sh OLD_BIN NEW_BIN OUT_DIR (llvmpipe, 128² screen)
# Side by side, interleaved: the compute raster before (OLD) and after (NEW) the queue change.
OLD=$1; NEW=$2; OUT=$3; mkdir -p $OUT
echo "round,build,scene,method,raster,map_size,maps,total_ms,raster_ms" > $OUT/rows.csv
for round in 1 2 3; do
 for build in old new; do
  B=$OLD; [ $build = new ] && B=$NEW
  for case in "teapot regular:n=4,layout=centred compute 2048" "teapot regular:n=4,layout=centred hardware 2048" "teapot regions compute 512" "teapot regions hardware 512"; do
   set -- $case
   d=$OUT/run-$build-$round; rm -rf $d
   $B render --scene $1 --method $2 --set raster=$3 --set resolution=128 --set shadow_map_size=$4 --out $d >/dev/null 2>&1 || { echo "failed: $build $case"; continue; }
   python3 -c "
import json;j=json.load(open('$d/run.json'));s=j['stages_ms'];r=s.get('raster_compute',s.get('shadow_raster'))
import csv,sys;csv.writer(sys.stdout,lineterminator='\\n').writerow([$round,'$build','$1','$2','$3',$4,j['shadow_maps'],round(j['total_ms'],1),round(r,1)])" >> $OUT/rows.csv
   rm -rf $d
  done
 done
done
cat $OUT/rows.csv
