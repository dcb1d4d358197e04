#!/usr/bin/env python3
"""A finer grid as a truth-free reference for auto's choice (penumbra.analysis.budget). In this folder:
  python3 reference.py render SCENE OUT          auto's ladder at 512² and 1024², msm apart, and R (PENUMBRA=bin)
  python3 reference.py rows OUT SCENE... > rows.csv   (oracles and times from ../budget-promise/SCENE/frontier.jsonl)
  python3 reference.py counts [rows.csv | -]
The ladder: centred n = 2-6 and 8, pcss and msm, at 512² and 1024²; R: the finest grid auto may choose."""
import argparse, os, sys
from penumbra.analysis import binary, budget, build_line, read, write_csv
from penumbra.analysis.engine import method_params
from penumbra.analysis.frontier import read_frontier

here = os.path.dirname(os.path.abspath(__file__))
LADDER = [f'regular:n={n},layout=centred' for n in (2, 3, 4, 5, 6, 8)] + ['pcss']
SIZES = [512, 1024]
p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
p.add_argument('command', choices=['render', 'rows', 'counts'])
p.add_argument('args', nargs='*')
p.add_argument('--resolution', type=int, default=128)
p.add_argument('--frontiers', default=os.path.join(here, '..', 'budget-promise'), help='the folder of SCENE/frontier.jsonl')
a = p.parse_intermixed_args()
if a.command == 'render':
    (scene, out), bin_ = a.args, binary.find()
    auto = method_params('auto')
    runs = [(str(z), LADDER, z, True) for z in SIZES] + [(f'{z}-msm', ['msm'], z, False) for z in SIZES] + [('ref', [budget.reference_grid()], auto['max_size'], True)]
    for name, methods, size, must in runs:
        r = binary.compare(bin_, scene, methods, os.path.join(out, scene, name), {'resolution': a.resolution, 'shadow_map_size': size}, 1)
        # msm refuses a ball light (as auto's default filters leave it out there).
        if not r.ok and (must or 'is not supported' not in r.log):
            sys.exit(f'{scene} {name} failed: {r.last_line()}')
elif a.command == 'rows':
    out, scenes = a.args[0], a.args[1:]
    rows = [row for s in scenes for row in budget.reference_rows(out, s, read_frontier(os.path.join(a.frontiers, s, 'frontier.jsonl')), LADDER + ['msm'], SIZES)]
    write_csv(sys.stdout, budget.REFERENCE_HEADER, rows)
else:
    rows = read(a.args[0] if a.args else os.path.join(here, 'rows.csv'))
    print(build_line([rows]))
    print(budget.reference_counts(rows))
