#!/bin/bash
# Retakes the auto rows of this folder's frontiers on the current build, without a new frontier.
# The fixed settings render the same V as on the build that took them (scripts/same-v.sh), so each
# row's oracle (`.oracle` of its auto line in S/frontier.jsonl) stands, and only `auto` is rendered:
# - a row with an oracle: `penumbra compare` renders auto:target=T and the oracle in one window
#   under the oracle's map size, 5 timed frames each, interleaved (as paired.sh does); the ratio of
#   their median frame times is time/oracle, and the oracle's RMSE is rendered again beside the
#   frontier's (oracle_rmse against frontier_oracle_rmse);
# - a row no fixed setting reaches: auto:target=T alone at the frontier's first map size (512), one
#   timed frame (no time/oracle to take), for its maps, RMSE and what it reports.
# What the row reports is its run.json's method_record (target_met, predicted_rmse: the best
# predicted where out of reach; where auto decided by its certified bound, that bound, and the
# decision's time in search_ms) and the out-of-reach line on stderr.
# --alone: the rows whose oracle's maps are not 512², auto:target=T alone at 512², one frame. The
# frontier renders its budget rows at its first map size, and a one-map filter renders at the
# scene's size (a grid at its own), so there a filter's choice and RMSE can differ from the
# paired window's; counts.py takes the row's figures from these and time/oracle from the pairing
# where both rendered the same maps.
# STRETCH=s renders auto:target=T/s instead (the calibrated factors stretched by s, docs/budget.md
# §4) against the same row, its oracle and T: stretch.py reads a sweep of s.
# Usage (in this folder): PENUMBRA=bin ./retake.sh [--alone] S1 S2 ... >> rows-BUILD.csv
# (the header once: ./retake.sh --header > rows-BUILD.csv, and alone-BUILD.csv likewise).
bin=${PENUMBRA:-penumbra}
stretch=${STRETCH:-1}
if [ "$1" = --header ]; then
  echo "scene,target,maps,choice,rmse,measured_over_target,target_met,predicted_rmse,search_ms,tries,out_of_reach,ms,oracle,oracle_maps,oracle_rmse,frontier_oracle_rmse,oracle_ms,time_over_oracle"
  exit 0
fi
alone=no; unpaired="none reaches it"
if [ "$1" = --alone ]; then alone=yes; shift; fi
for scene in "$@"; do
  jq -r 'select(.kind == "error budget" and (.spec | startswith("auto:"))) | [.spec, (.oracle // "-")] | @tsv' "$scene/frontier.jsonl" |
  while IFS=$'\t' read -r spec oracle; do
    t=${spec#auto:target=}
    if [ "$stretch" != 1 ]; then spec="auto:target=$(jq -n --argjson t "$t" --argjson s "$stretch" '$t / $s')"; fi
    if [ $alone = yes ]; then
      case "$oracle" in -|*" 512") continue ;; esac
      oracle=-; unpaired="alone at 512"
    fi
    out=$(mktemp -d)
    if [ "$oracle" = - ]; then
      methods=$spec; size=512; repeats=1; frontier_rmse=null
    else
      ospec=${oracle% @ *}; config=${oracle##* @ }; size=${config##* }
      methods="$spec,$ospec"; repeats=5
      frontier_rmse=$(jq -s --arg o "$oracle" 'map(select(.kind != "error budget" and (.spec + " @ " + .map_config) == $o)) | first | .rmse' "$scene/frontier.jsonl")
    fi
    if PENUMBRA_NO_PROGRESS=1 "$bin" compare --scene "$scene" --set resolution=128 --set shadow_map_size="$size" \
        --methods "$methods" --repeats "$repeats" --out "$out" > "$out/log" 2>&1; then
      reach=$(grep -m1 'out of reach' "$out/log")
      run=$(ls "$out"/images/auto*/run.json)
      # Row 0 of results.jsonl is auto, row 1 (where there is one) its oracle.
      jq -rs --argjson t "$t" --arg o "$oracle" --arg reach "$reach" --arg unpaired "$unpaired" --argjson fr "$frontier_rmse" --slurpfile run "$run" '
        ($run[0].method_record) as $m | .[0] as $a | .[1] as $b
        | [$a.scene, $t, $a.shadow_maps,
           ($m.renders // $m.filter.chosen // "\($m.chosen.spec) @ \($m.chosen.map_size)"),
           $a.metrics.rmse, ($a.metrics.rmse / $t), $m.target_met, ($m.certified.bound // $m.predicted_rmse),
           (([$m.tries[].ms] | add) + ($m.certified.decision_ms // 0)), ($m.tries | length), $reach, $a.total_ms,
           (if $b then $o else $unpaired end), ($b.shadow_maps // ""), ($b.metrics.rmse // ""), ($fr // ""),
           ($b.total_ms // ""), (if $b then $a.total_ms / $b.total_ms else "" end)] | @csv' "$out/results.jsonl"
    else
      echo "\"$scene\",$t,,,,,,,,,\"failed: $(tail -1 "$out/log" | tr '"' "'")\",,\"$oracle\",,,,,"
    fi
    rm -rf "$out"
  done
done
