#!/usr/bin/env python3
"""auto before and after the ball lights' own maps' factor and the even sides
(penumbra.analysis.promise.before_after): each scene's auto rows here (S/frontier.jsonl,
time/oracle from each row's own side-by-side window) against the same scene's rows in
../budget-promise (time/oracle from its paired.csv). Writes rows.csv (or --out FILE) and prints
the table of README.md. Usage: python3 compare.py [--out FILE]"""
import argparse, glob, os
from penumbra.analysis import build_line, promise, read, write_csv_file
from penumbra.analysis.frontier import read_frontier

here = os.path.dirname(os.path.abspath(__file__))
before_dir = os.path.join(os.path.dirname(here), 'budget-promise')
p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
p.add_argument('--out', default=os.path.join(here, 'rows.csv'))
a = p.parse_intermixed_args()
after = [read_frontier(f) for f in sorted(glob.glob(os.path.join(here, '*', 'frontier.jsonl')))]
before = [read_frontier(os.path.join(before_dir, f.budget_rows()[0].scene, 'frontier.jsonl')) for f in after]
print(build_line(f.table for f in after))
text, rows = promise.before_after(promise.frontier_rows(before, read(os.path.join(before_dir, 'paired.csv'))),
                                  sorted(promise.frontier_rows(after), key=lambda r: (r.scene, -r.target)))
write_csv_file(a.out, promise.BEFORE_AFTER_HEADER, rows)
print(text)
