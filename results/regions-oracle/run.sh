#!/bin/bash
# one compare per (scene, resolution, map size): seven culled centred grids
B=/work/wt-oracle6/target/release/penumbra
M=""
for n in 1 2 3 4 6 8 11; do M="$M --methods regular:n=$n,layout=centred,cull=on"; done
for sr in default:128 canopy-market:128 pergola-garden:128 canopy-market:256 pergola-garden:256; do
  s=${sr%:*}; r=${sr#*:}
  rep=3; [ $r = 256 ] && rep=1
  for z in 512 1024 2048; do
    o=$s-$r-$z
    [ -f $o/results.jsonl ] && continue
    echo "$(date -u +%T) $o"
    $B compare --scene $s --set resolution=$r --set shadow_map_size=$z $M --repeats $rep --out $o > $o.log 2>&1 || echo "FAIL $o"
  done
done
echo "$(date -u +%T) done"
