#!/bin/bash
# rows.csv of the budget rows: scene, target, maps, rmse, measured/T, reported, predicted, ms, search ms, oracle, its rmse, its ms, time/oracle
echo "scene,target,maps,rmse,measured_over_target,target_met,predicted,median_ms,search_ms,tries,oracle,oracle_rmse,oracle_ms,time_over_oracle"
for f in "$@"; do
  jq -rs '
    (map(select(.kind != "error budget" and .failed == null)) ) as $fixed
    | .[] | select(.kind == "error budget" and (.spec | startswith("auto:"))) | . as $b
    | ($b.spec | capture("target=(?<t>[0-9.]+)").t | tonumber) as $t
    | ($fixed | map(select((.spec + " @ " + .map_config) == $b.oracle)) | first) as $o
    | [$b.scene, $t, $b.maps, $b.rmse, ($b.rmse / $t), $b.budget.target_met, $b.budget.predicted, $b.frame_ms, $b.budget.search_ms, $b.budget.tries,
       ($b.oracle // "none reaches it"), ($o.rmse // ""), ($o.frame_ms // ""), (if $o then $b.frame_ms / $o.frame_ms else "" end)]
    | @csv' "$f"
done
