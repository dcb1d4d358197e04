#!/bin/bash
# the steps between n = 11 and 16 on canopy-market, where the single grid's step decided T = 0.012
B=/work/wt-oracle6/target/release/penumbra
M=""; for n in 12 13 14; do M="$M --methods regular:n=$n,layout=centred,cull=on"; done
for r in 128 256; do
  rep=3; [ $r = 256 ] && rep=1
  for z in 1024 2048; do
    o=canopy-market-$r-$z-steps
    [ -f $o/results.jsonl ] && continue
    echo "$(date -u +%T) $o"
    $B compare --scene canopy-market --set resolution=$r --set shadow_map_size=$z $M --repeats $rep --out $o > $o.log 2>&1 || echo "FAIL $o"
  done
done
echo "$(date -u +%T) done"
