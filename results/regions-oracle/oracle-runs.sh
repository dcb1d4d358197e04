P=/work/main/target/python-venv/bin/python; O=/work/wt-oracle6/results/regions-oracle/oracle.py
for g in canopy-market-256 default-128 canopy-market-128 pergola-garden-128; do $P $O 0.03,0.02,0.012 $g-*/ > o-$g.csv 2> p-$g.csv; done
ORACLE_MAX_SET=4 $P $O 0.03,0.02,0.012 pergola-garden-256-*/ > o-pergola-garden-256.csv 2> p-pergola-garden-256.csv
echo done > ora2.done
