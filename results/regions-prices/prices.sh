#!/bin/sh
B=./target/release/penumbra
for s in default cows bunny-seed-framing; do
$B compare --scene $s --set resolution=128 --set shadow_map_size=512 --repeats 3 --methods regions:target=0.02,regions:target=0.02,map_cost=850000,sample_cost=30,regions:target=0.012,regions:target=0.012,map_cost=850000,sample_cost=30 --out OUT/p-$s >/dev/null 2>&1
done
