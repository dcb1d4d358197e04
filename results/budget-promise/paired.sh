#!/bin/bash
# Side-by-side time/oracle: for each auto row of the frontier.jsonl files given, `penumbra compare`
# renders auto:target=T and its oracle in one window, frames interleaved round by round (the
# oracle's maps set by --set shadow_map_size; auto chooses its own), and the ratio of their median
# frame times is the row's time/oracle. Usage: PENUMBRA=bin ./paired.sh DIR/*/frontier.jsonl > paired.csv
bin=${PENUMBRA:-penumbra}
echo "scene,target,auto_maps,auto_rmse,auto_ms,oracle,oracle_maps,oracle_rmse,oracle_ms,time_over_oracle"
for f in "$@"; do
  jq -r 'select(.kind == "error budget" and (.spec | startswith("auto:")) and .oracle != null) | [.scene, .spec, .oracle] | @tsv' "$f" |
  while IFS=$'\t' read -r scene spec oracle; do
    ospec=${oracle% @ *}; config=${oracle##* @ }; size=${config##* }
    out=$(mktemp -d)
    if PENUMBRA_NO_PROGRESS=1 "$bin" compare --scene "$scene" --set resolution=128 --set shadow_map_size="$size" \
        --methods "$spec,$ospec" --repeats 5 --out "$out" > "$out/log" 2>&1; then
      jq -rs --arg t "${spec#auto:target=}" --arg o "$oracle" '
        [.[0].scene, ($t|tonumber), .[0].shadow_maps, .[0].metrics.rmse, .[0].total_ms, $o, .[1].shadow_maps, .[1].metrics.rmse, .[1].total_ms, (.[0].total_ms / .[1].total_ms)] | @csv' "$out/results.jsonl"
    else
      echo "\"$scene\",${spec#auto:target=},,,,\"$oracle\",,,,\"failed: $(tail -1 "$out/log")\""
    fi
    rm -rf "$out"
  done
done
