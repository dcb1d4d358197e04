#!/bin/sh
# usage: tgt.sh BIN TAG
for s in pergola-garden canopy-market default cows; do
  $1 compare --scene $s --set resolution=128 --repeats 1 --methods regions:target=0.03,regions:target=0.02,regions:target=0.012 --out OUT/$2-$s >/dev/null 2>&1 || echo fail $s
done
