#!/bin/bash
# One `penumbra compare` per (scene, screen, map size) of culled centred grids, into
# SCENE-RES-SIZE[-SUFFIX]/ in the current folder (a folder already holding results.jsonl is kept).
# Usage: PENUMBRA=bin ./run.sh
# Each line below: scene, screen side, the grids' sides, the map sizes, the folders' suffix.
bin=${PENUMBRA:-penumbra}
while read -r s r ns zs suffix; do
  M=""; for n in ${ns//,/ }; do M="$M --methods regular:n=$n,layout=centred,cull=on"; done
  rep=3; [ "$r" = 256 ] && rep=1
  for z in ${zs//,/ }; do
    o=$s-$r-$z$suffix
    [ -f "$o/results.jsonl" ] && continue
    echo "$(date -u +%T) $o"
    "$bin" compare --scene "$s" --set resolution="$r" --set shadow_map_size="$z" $M --repeats $rep --out "$o" > "$o.log" 2>&1 || echo "FAIL $o"
  done
done <<'SETS'
default        128 1,2,3,4,6,8,11 512,1024,2048
canopy-market  128 1,2,3,4,6,8,11 512,1024,2048
pergola-garden 128 1,2,3,4,6,8,11 512,1024,2048
canopy-market  256 1,2,3,4,6,8,11 512,1024,2048
pergola-garden 256 1,2,3,4,6,8,11 512,1024,2048
canopy-market  128 16             512,1024,2048 -more
pergola-garden 128 16,22          512,1024,2048 -more
canopy-market  256 16             512,1024,2048 -more
pergola-garden 256 16,22          512,1024,2048 -more
canopy-market  128 12,13,14       1024,2048     -steps
canopy-market  256 12,13,14       1024,2048     -steps
SETS
echo "$(date -u +%T) done"
