#!/bin/sh
B=./target/release/penumbra
$B compare --scene bunny-seed-framing --set resolution=128 --set shadow_map_size=512 --repeats 5 --methods regions:target=0.02,centre_size=512,regions:target=0.02,regions:target=0.012,centre_size=512,regions:target=0.012 --out OUT/c-bunny >/dev/null 2>&1
for s in pergola-garden canopy-market cows; do
$B compare --scene $s --set resolution=128 --set shadow_map_size=1024 --repeats 3 --methods regions:target=0.02,centre_size=1024,regions:target=0.02 --out OUT/c-$s >/dev/null 2>&1
done
