#!/bin/bash
# The oracle over each scene and screen, in the folder run.sh wrote: o-GROUP.csv (rows) and
# p-GROUP.csv (prices). Usage: PYTHON=venv/bin/python ./oracle-runs.sh (a Python with the
# penumbra package, numpy and PIL: target/python-venv after scripts/python-test.sh)
P=${PYTHON:-python3}; O=$(cd "$(dirname "$0")" && pwd)/oracle.py
for g in canopy-market-256 default-128 canopy-market-128 pergola-garden-128; do
  "$P" "$O" 0.03,0.02,0.012 $g-*/ > o-$g.csv 2> p-$g.csv
done
# pergola-garden at 256²: sets of at most 4 settings (the search over all sets did not finish)
ORACLE_MAX_SET=4 "$P" "$O" 0.03,0.02,0.012 pergola-garden-256-*/ > o-pergola-garden-256.csv 2> p-pergola-garden-256.csv
