#!/usr/bin/env python3
"""What a map of each size adds to a frame, and auto's price of it (penumbra.analysis.budget):
  python3 prices.py frame-split [--rounds 3 --scenes cows,default --sides 3,5 --sizes 512,1024,2048] > frame-split.csv   (PENUMBRA=bin)
  python3 prices.py frame-split-table [frame-split.csv]   the medians of README.md
  python3 prices.py paired BEFORE AFTER FRONTIER.jsonl... [--rounds 2 --repeats 5] > paired.csv   auto beside its oracle, each build in turn
  python3 prices.py prices BEFORE AFTER [--rounds 2 --rows cows:0.03,…] > prices.csv   (the after build's run.json in runs/)
  python3 prices.py counts [paired.csv]                  time/oracle per row and build
  python3 prices.py why RUN.json... > why.csv            why a price does or does not move the choice"""
import argparse, os, sys
from penumbra.analysis import binary, budget, build_line, read, read_json, retake, write_csv
from penumbra.analysis.frontier import read_frontier

here = os.path.dirname(os.path.abspath(__file__))
p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
p.add_argument('command', choices=['frame-split', 'frame-split-table', 'paired', 'prices', 'counts', 'why'])
p.add_argument('files', nargs='*')
p.add_argument('--rounds', type=int, default=2)
p.add_argument('--scenes', default='cows,default')
p.add_argument('--sides', default='3,5')
p.add_argument('--sizes', default='512,1024,2048')
p.add_argument('--rows', default='cows:0.03,cows:0.02,default:0.03,default:0.012,analytic-square:0.012')
p.add_argument('--resolution', type=int, default=128)
p.add_argument('--runs', default='runs')
p.add_argument('--repeats', type=int, default=retake.REPEATS)
a = p.parse_intermixed_args()
ints = lambda s: [int(x) for x in s.split(',')]
table = lambda name: read(a.files[0] if a.files else os.path.join(here, name))
builds = lambda: {'before': binary.find(a.files[0]), 'after': binary.find(a.files[1])}
if a.command == 'frame-split':
    write_csv(sys.stdout, budget.FRAME_SPLIT_HEADER, budget.frame_split(binary.find(), a.scenes.split(','), ints(a.sides), ints(a.sizes), a.rounds, a.resolution))
elif a.command == 'frame-split-table':
    print(build_line([table('frame-split.csv')]) + '\n' + budget.frame_split_table(table('frame-split.csv')))
elif a.command == 'paired':
    frontiers = [read_frontier(f) for f in a.files[2:]]
    write_csv(sys.stdout, ['round', 'build', *retake.HEADER], [[r, b, *row] for r in range(1, a.rounds + 1) for b, path in builds().items() for row in retake.retake(path, frontiers, repeats=a.repeats)])
elif a.command == 'prices':
    rows = [(s, float(t)) for s, t in (x.split(':') for x in a.rows.split(','))]
    write_csv(sys.stdout, budget.PRICES_HEADER, budget.prices(builds(), rows, a.rounds, a.resolution, a.runs))
elif a.command == 'counts':
    print(build_line([table('paired.csv')]) + '\n' + budget.paired_counts(table('paired.csv')))
else:
    write_csv(sys.stdout, budget.WHY_HEADER, [row for f in a.files for row in budget.why(read_json(f))])
