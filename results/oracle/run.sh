#!/bin/bash
# `penumbra oracle` on each scene and screen of the list on stdin ("SCENE RES [FLAGS...]" lines),
# one run each into SCENE-RES/ (a folder already holding oracle.csv is kept: the script resumes),
# then every run's rows joined into oracle.csv here.
# Usage: PENUMBRA=target/release/penumbra results/oracle/run.sh < results/oracle/runs.txt
bin=$(realpath "${PENUMBRA:-$(command -v penumbra)}")
cd "$(dirname "$0")" || exit 1
while read -r scene res flags; do
  case "$scene" in ''|'#'*) continue ;; esac
  o=$scene-$res
  [ -f "$o/oracle.csv" ] && continue
  echo "$(date -u +%T) $o $flags"
  # shellcheck disable=SC2086
  "$bin" oracle --scene "$scene" --resolutions "$res" $flags --out "$o" > "$o.log" 2>&1 || echo "FAIL $o"
done
awk 'FNR > 1 || NR == 1' */oracle.csv > oracle.csv
echo "$(date -u +%T) done"
