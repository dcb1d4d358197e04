#!/usr/bin/env python3
"""Counts of reference.py's rows per rule: rows some fixed setting reaches, the rule's choice at
most T, within 1.3 x the oracle's time, both, and rows where it finds nothing.
Usage (in this folder): python3 counts.py [rows.csv, or - for standard input]"""
import csv, os, sys

here = os.path.dirname(os.path.abspath(__file__))
path = sys.argv[1] if len(sys.argv) > 1 else os.path.join(here, 'rows.csv')
rows = list(csv.DictReader(sys.stdin if path == '-' else open(path)))
refs = {r['scene']: float(r['reference_rmse']) for r in rows}
print('reference (17x17 centred at 2048²) RMSE per scene: ' + ', '.join(f'{s} {e:.4f}' for s, e in sorted(refs.items())))
print('| rule | rows reached | choice <= T | time <= 1.3 x oracle | both | nothing meets T |')
print('|---|---:|---:|---:|---:|---:|')
for rule in dict.fromkeys(r['rule'] for r in rows):
    got = [r for r in rows if r['rule'] == rule and r['oracle'] != 'none reaches it']
    under = sum(1 for r in got if r['measured_over_target'] and float(r['measured_over_target']) <= 1)
    fast = sum(1 for r in got if r['time_over_oracle'] and float(r['time_over_oracle']) <= 1.3)
    both = sum(1 for r in got if r['measured_over_target'] and float(r['measured_over_target']) <= 1 and float(r['time_over_oracle']) <= 1.3)
    none = sum(1 for r in got if r['choice'] == 'none meets it')
    n = len(got)
    print(f'| {rule} | {n} | {under} ({100 * under / n:.0f}%) | {fast} ({100 * fast / n:.0f}%) | {both} ({100 * both / n:.0f}%) | {none} |')
