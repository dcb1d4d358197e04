#!/usr/bin/env python3
"""regions:target=T before and after the maps' share of the target (penumbra.analysis):
  python3 targets.py render OUT TAG [--scenes S,…]   one compare per scene into OUT/TAG-S (PENUMBRA=bin; TAG: before or after)
  python3 targets.py table OUT [--scenes S,…] > target-before-after.csv   each row's RMSE over T, maps and time, before and after"""
import argparse, os, sys
from penumbra.analysis import binary, read, write_csv
from penumbra.analysis.frontier import target_of

p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
p.add_argument('command', choices=['render', 'table'])
p.add_argument('args', nargs='+')
p.add_argument('--scenes', default='pergola-garden,canopy-market,default,cows')
p.add_argument('--targets', default='0.03,0.02,0.012')
p.add_argument('--resolution', type=int, default=128)
a = p.parse_intermixed_args()
scenes = a.scenes.split(',')
if a.command == 'render':
    out, tag = a.args
    for s in scenes:
        run = binary.compare(binary.find(), s, [f'regions:target={t}' for t in a.targets.split(',')], os.path.join(out, f'{tag}-{s}'), {'resolution': a.resolution}, 1)
        if not run.ok:
            print(f'failed: {s}: {run.last_line()}', file=sys.stderr)
else:
    rows = []
    for s in scenes:
        for b, f in zip(*(read(os.path.join(a.args[0], f'{tag}-{s}', 'results.jsonl')) for tag in ('before', 'after'))):
            t = target_of(b)
            side = lambda r: [f"{r.number('rmse'):.5f}", f"{r.number('rmse') / t:.2f}", r.integer('maps'), f"{r.number('frame_ms'):.0f}"]
            rows.append([s, t, *side(b), *side(f)])
    write_csv(sys.stdout, ['scene', 'target', 'before_rmse', 'before_rmse_over_t', 'before_maps', 'before_ms', 'after_rmse', 'after_rmse_over_t', 'after_maps', 'after_ms'], rows)
