#!/usr/bin/env python3
"""auto's two promises against one stretch of its calibrated factors (docs/budget.md §4-5).
auto:target=T/s is the fitted factors times s. Each stretch's rows (retake.sh with STRETCH=s, in
stretch/s<s>.csv, s = 1 included) are read against the same rows, oracles and T, all from the
paired window (auto and its oracle in one `penumbra compare` under the oracle's maps).
Prints, per s: measured <= T on the rows some fixed setting reaches, time <= 1.3 x the oracle's
(side by side), the rows reported met while over T, the median time/oracle; then, per row, the
stretches at which both promises hold, and how many rows no stretch serves.
Usage (in this folder): python3 stretch.py"""
import csv, glob, os, re, statistics as st

here = os.path.dirname(os.path.abspath(__file__))


def read(path):
    return {(r['scene'], float(r['target'])): r for r in csv.DictReader(open(path))}


sweep = {}
for p in glob.glob(os.path.join(here, 'stretch', 's*.csv')):
    sweep[float(re.search(r's([0-9.]+)\.csv$', p).group(1))] = read(p)
stretches = sorted(sweep)
rows = sorted(sweep[1.0])
reached = [k for k in rows if sweep[1.0][k]['oracle'] != 'none reaches it']


def num(r, key):
    return float(r[key]) if r and r.get(key) not in (None, '') else None


def both(r):
    """Both promises on one row: measured <= T and time <= 1.3 x the oracle's."""
    m, t = num(r, 'measured_over_target'), num(r, 'time_over_oracle')
    return m is not None and t is not None and m <= 1 and t <= 1.3


print('| stretch s | rows | measured <= T (reached rows) | time <= 1.3 x oracle | both | reported met over T | median time/oracle |')
print('|---:|---:|---:|---:|---:|---:|---:|')
for s in stretches:
    got = sweep[s]
    have = [k for k in reached if k in got and got[k]['maps']]
    under = sum(1 for k in have if num(got[k], 'measured_over_target') <= 1)
    ratios = [num(got[k], 'time_over_oracle') for k in have if num(got[k], 'time_over_oracle') is not None]
    fast = sum(1 for x in ratios if x <= 1.3)
    ok = sum(1 for k in have if both(got[k]))
    over = sum(1 for k in got if got[k]['maps'] and got[k]['target_met'] == 'true' and num(got[k], 'measured_over_target') > 1)
    print(f'| {s:g} | {len(have)} of {len(reached)} | {under} ({100 * under / len(have):.0f}%) | {fast} of {len(ratios)} ({100 * fast / len(ratios):.0f}%) '
          f'| {ok} ({100 * ok / len(have):.0f}%) | {over} of {len(got)} | {st.median(ratios):.2f} |')

print()
print('| scene | T | oracle | ' + ' | '.join(f's = {s:g}: measured/T, time/oracle' for s in stretches) + ' | stretches serving both |')
print('|---|---:|---|' + '---|' * len(stretches) + '---|')
none = 0
for k in reached:
    cells, serve = [], []
    for s in stretches:
        r = sweep[s].get(k)
        m, t = num(r, 'measured_over_target'), num(r, 'time_over_oracle')
        cells.append('-' if m is None else f'{m:.2f}, {t:.2f}' if t is not None else f'{m:.2f}, unpaired')
        if both(r):
            serve.append(f'{s:g}')
    none += not serve
    print(f'| {k[0]} | {k[1]:g} | {sweep[1.0][k]["oracle"]} | ' + ' | '.join(cells) + f' | {", ".join(serve) or "none"} |')
print()
print(f'rows no stretch serves: {none} of {len(reached)}; at most {len(reached) - none} of {len(reached)} '
      f'({100 * (len(reached) - none) / len(reached):.0f}%) can keep both promises at any one stretch of these')
