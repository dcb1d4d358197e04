#!/bin/bash
# Each build's prices and choice, side by side: `penumbra render --method auto:target=T` at 128²
# with the build before and the build after, ROUNDS interleaved rounds; the process's wall clock
# (the pricing is most of what differs), the record's prices per map and its choice. Each after
# build's run.json is kept in runs/ (for why.py).
# Usage: BEFORE=bin AFTER=bin ROUNDS=2 ./prices.sh > prices.csv
out=$(mktemp -d)
mkdir -p runs
echo "round,build,scene,target,process_s,pricing_ms,price_512,price_1024,price_2048,chosen,map_size,maps,total_ms"
for round in $(seq 1 "${ROUNDS:-2}"); do
  for row in ${ROWS:-cows:0.03 cows:0.02 default:0.03 default:0.012 analytic-square:0.012}; do
    scene=${row%%:*}; t=${row##*:}
    for build in before after; do
      bin=$BEFORE; [ "$build" = after ] && bin=$AFTER
      start=$(date +%s.%N)
      PENUMBRA_NO_PROGRESS=1 "$bin" render --scene "$scene" --set resolution=128 --method "auto:target=$t" --out "$out/r" > /dev/null 2>&1 || { echo "failed: $build $scene $t" >&2; continue; }
      s=$(echo "$(date +%s.%N) - $start" | bc)
      jq -r --arg r "$round" --arg b "$build" --arg s "$s" --arg t "$t" '.method_record as $m | [$r, $b, .scene, ($t|tonumber), ($s|tonumber), ($m.map_cost.pricing_ms // ""), $m.map_cost.per_map["512"], $m.map_cost.per_map["1024"], $m.map_cost.per_map["2048"], ($m.renders // $m.chosen.spec), $m.chosen.map_size, .shadow_maps, .total_ms] | @csv' "$out/r/run.json"
      [ "$build" = after ] && cp "$out/r/run.json" "runs/$scene-$t-$round.json"
    done
  done
done
rm -rf "$out"
