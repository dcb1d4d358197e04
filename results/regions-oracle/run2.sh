#!/bin/bash
# the larger grids the first set lacked: n = 16, 22 on pergola-garden, n = 16 on canopy-market
B=/work/wt-oracle6/target/release/penumbra
for sr in canopy-market:128:16 pergola-garden:128:16,22 canopy-market:256:16 pergola-garden:256:16,22; do
  IFS=: read s r ns <<< "$sr"
  M=""; for n in ${ns//,/ }; do M="$M --methods regular:n=$n,layout=centred,cull=on"; done
  rep=3; [ $r = 256 ] && rep=1
  for z in 512 1024 2048; do
    o=$s-$r-$z-more
    [ -f $o/results.jsonl ] && continue
    echo "$(date -u +%T) $o"
    $B compare --scene $s --set resolution=$r --set shadow_map_size=$z $M --repeats $rep --out $o > $o.log 2>&1 || echo "FAIL $o"
  done
done
echo "$(date -u +%T) done"
