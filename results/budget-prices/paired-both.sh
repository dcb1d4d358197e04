#!/bin/bash
# time/oracle before and after the settled-frame price, side by side: results/budget-promise/paired.sh
# run with each build in turn, ROUNDS rounds, on the rows of the frontier.jsonl files given.
# Usage: BEFORE=bin AFTER=bin ROUNDS=2 ./paired-both.sh ../budget-promise/{cows,default}/frontier.jsonl > paired.csv
here=$(cd "$(dirname "$0")" && pwd)
paired=$here/../budget-promise/paired.sh
first=1
for round in $(seq 1 "${ROUNDS:-2}"); do
  for build in before after; do
    bin=$BEFORE; [ "$build" = after ] && bin=$AFTER
    PENUMBRA=$bin "$paired" "$@" | { read -r header; [ $first = 1 ] && echo "round,build,$header"; cat | sed "s/^/$round,$build,/"; }
    first=0
  done
done
