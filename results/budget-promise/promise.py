#!/usr/bin/env python3
"""auto's rows against the oracle (penumbra.analysis.promise, .retake). In this folder:
  python3 promise.py retake [--alone] [--stretch S] SCENE... > FILE.csv   renders each row again (PENUMBRA=bin)
  python3 promise.py counts ROWS.csv [ALONE.csv]   the counts and rows table of a retake
  python3 promise.py counts --frontiers            the same of the frontiers' own rows (paired.csv's time/oracle)
  python3 promise.py stretch                       the stretch sweep (stretch/s<S>.csv)
  python3 promise.py rows > rows.csv               the frontiers' auto rows as one table"""
import argparse, glob, os, re, sys
from penumbra.analysis import binary, build_line, promise, read, retake, write_csv
from penumbra.analysis.frontier import read_frontier

here = os.path.dirname(os.path.abspath(__file__))
p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
p.add_argument('command', choices=['retake', 'counts', 'stretch', 'rows'])
p.add_argument('files', nargs='*', help='retake: scene folders (S/frontier.jsonl); counts: ROWS.csv [ALONE.csv]')
p.add_argument('--alone', action='store_true')
p.add_argument('--stretch', type=float, default=1.0)
p.add_argument('--repeats', type=int, default=retake.REPEATS)
p.add_argument('--frontiers', action='store_true')
p.add_argument('--dir', default=here, help='the folder holding S/frontier.jsonl (this one by default)')
a = p.parse_intermixed_args()
frontiers = {os.path.basename(os.path.dirname(f)): read_frontier(f) for f in sorted(glob.glob(os.path.join(a.dir, '*', 'frontier.jsonl')))}
if a.command == 'retake':
    rows = retake.retake(binary.find(), [read_frontier(os.path.join(s, 'frontier.jsonl')) for s in a.files], stretch=a.stretch, alone=a.alone, repeats=a.repeats)
    write_csv(sys.stdout, retake.HEADER, rows)
elif a.command == 'counts' and a.frontiers:
    print(build_line(f.table for f in frontiers.values()))
    print(promise.report(promise.frontier_rows(frontiers.values(), read(os.path.join(a.dir, 'paired.csv')))))
elif a.command == 'counts':
    tables = [read(f) for f in a.files]
    print(build_line(tables))
    print(promise.report(promise.retake_rows(tables[0], tables[1] if len(tables) > 1 else None, frontiers)))
elif a.command == 'stretch':
    sweep = {float(re.search(r's([0-9.]+)\.csv$', f).group(1)): read(f) for f in glob.glob(os.path.join(a.dir, 'stretch', 's*.csv'))}
    print(build_line(sweep.values()))
    print(promise.stretch_report(sweep))
else:
    write_csv(sys.stdout, promise.FRONTIER_TABLE_HEADER, promise.frontier_table(frontiers.values()))
