#!/usr/bin/env python3
"""regions against the frontier (penumbra.analysis.regions):
  python3 regions.py summarize S.jsonl... > budget-rows.csv     each budget row against its matched fixed setting
  python3 regions.py summary S.jsonl... > summary.csv           the same with the oracle (results/frontier-h200-budget-regions/)
  python3 regions.py compare S.jsonl... --out DIR   compare --repeats 5 at the frontier's screen: each regions row beside its match (PENUMBRA=bin)
  python3 regions.py compare-rows DIR/*/results.jsonl > compare-rows.csv
  python3 regions.py where RUN_DIR... > where.csv               one render with stage timing per setting
  python3 regions.py prices prices.csv                          the cost model's prices from culled grids
  python3 regions.py plan-classes RUN.json... > plan-classes.csv
  python3 regions.py plan-windows PREFIX... > plan-windows.csv  (PREFIX.run.json, PREFIX.region_samples.png)"""
import argparse, os, sys
from penumbra.analysis import binary, read, read_json, regions as r, write_csv
from penumbra.analysis.frontier import read_frontier

p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
p.add_argument('command', choices=['summarize', 'summary', 'compare', 'compare-rows', 'where', 'prices', 'plan-classes', 'plan-windows'])
p.add_argument('files', nargs='+')
p.add_argument('--out')
a = p.parse_intermixed_args()
out = lambda header, rows: write_csv(sys.stdout, header, rows)
if a.command == 'summarize':
    out(r.BUDGET_ROWS_HEADER, [row for f in a.files for row in r.budget_rows(read_frontier(f))])
elif a.command == 'summary':
    out(r.SUMMARY_HEADER, [row for f in a.files for row in r.summary_rows(read_frontier(f))])
elif a.command == 'compare':
    bin_ = binary.find()
    for f in a.files:
        for s, size in r.matched_windows(read_frontier(f)):
            name = os.path.join(a.out, f'{s.row.scene}-{s.row.target:g}')
            w, h = s.row.row.raw('resolution')
            run = binary.compare(bin_, s.row.scene, [s.row.spec, s.matched.spec], name, {'width': w, 'height': h, 'shadow_map_size': size}, 5)
            print(f'{name}: ' + ('done' if run.ok else f'failed: {run.last_line()}'))
elif a.command == 'compare-rows':
    out(r.COMPARE_ROWS_HEADER, [r.compare_row(read(f)) for f in a.files])
elif a.command == 'where':
    out(r.WHERE_HEADER, [r.where_row(read_json(os.path.join(d, 'run.json'))) for d in a.files])
elif a.command == 'prices':
    print('\n'.join(r.prices_fit(read(a.files[0]))))
elif a.command == 'plan-classes':
    out(r.PLAN_CLASSES_HEADER, [row for f in a.files for row in r.plan_classes(read_json(f))])
else:
    out(r.PLAN_WINDOWS_HEADER, [row for f in a.files for row in r.plan_windows(read_json(f + '.run.json'), f + '.region_samples.png')])
