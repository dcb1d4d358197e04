#!/usr/bin/env python3
"""The tables of README.md from pairs.csv and estimates/ (penumbra.analysis.calibration).
Usage: python3 analyze.py [spread|classes|misses|map-order|even|stretch-cost]... [--out DIR]
(all by default; misses.csv, map-order.csv and even/even.csv are written under DIR, this folder
by default). The scene groups below are what the scenes' files hold (which occluders, which
light), listed by hand to read the data, never used by the engine."""
import argparse, glob, os
from penumbra.analysis import build_line, calibration as c, engine, read, write_csv_file

here = os.path.dirname(os.path.abspath(__file__))
GROUPS = {
    'ball light (LightKind::Point)': lambda p: p.light_class == 'cube',
    'closed meshes (a mesh file that shadows itself)': lambda p: p.scene in {'default', 'bunny', 'cows', 'teapot', 'dragon', 'bunny-seed-framing', 'ball-bunny'},
    'foliage (leaf quads)': lambda p: p.scene in {'grove', 'far-grove'},
}
SCENE_CLASS = {'slat-roof': 'periodic', 'lattice-grate': 'periodic', 'far-grove': 'sub-texel', 'grove': 'sub-texel', 'bunny': 'mesh', 'bunny-seed-framing': 'mesh',
               'dragon': 'mesh', 'teapot': 'mesh', 'cows': 'mesh', 'ball-bunny': 'mesh', 'default': 'mesh'}
args = argparse.ArgumentParser(description=__doc__.splitlines()[0])
args.add_argument('parts', nargs='*', default=['spread', 'classes', 'misses', 'map-order', 'even', 'stretch-cost'])
args.add_argument('--out', default=here)
a = args.parse_intermixed_args()
pairs = c.read_pairs(os.path.join(here, 'pairs.csv'))
estimates = sorted(glob.glob(os.path.join(here, 'estimates', '*.jsonl')))
print(build_line(read(p) for p in estimates))
for part in a.parts:
    print(f'\n## {part}\n')
    if part == 'spread':
        print(c.spread(pairs))
    elif part == 'classes':
        # Before the ball lights' own maps' factor: one maps' factor (the plane lights'), the ball
        # lights' sampling factor the least that covers their fitting pairs with it.
        plane = engine.calibration().plane
        ball = c.least_factor([p for p in pairs if p.half == 'fitting' and p.light_class == 'cube'], lambda p, k: p.with_factors(engine.Factors(k, plane.map)) >= p.measured_rmse)
        print(c.classes(pairs, c.read_estimates(estimates), GROUPS, [next(iter(GROUPS))], {'plane': plane, 'cube': engine.Factors(ball, plane.map)})[0])
    elif part == 'misses':
        text, rows = c.misses(pairs, SCENE_CLASS, 'analytic')
        write_csv_file(os.path.join(a.out, 'misses.csv'), c.MISSES_HEADER, rows)
        print(text)
    elif part == 'map-order':
        rows, medians = c.map_order(pairs)
        write_csv_file(os.path.join(a.out, 'map-order.csv'), ['half', 'scene', 'spec', 'measured_order', 'estimate_order'], rows)
        print('\n'.join(medians))
    elif part == 'even':
        text, rows, _ = c.even_sides(c.read_estimates(sorted(glob.glob(os.path.join(here, 'even', 'estimates', '*.jsonl')))), pairs)
        os.makedirs(os.path.join(a.out, 'even'), exist_ok=True)
        write_csv_file(os.path.join(a.out, 'even', 'even.csv'), c.EVEN_HEADER, rows)
        print(text)
    elif part == 'stretch-cost':
        print(c.stretch_cost(read(os.path.join(here, 'stretch-cost.csv'))))
    else:
        args.error(f'unknown part {part!r}')
