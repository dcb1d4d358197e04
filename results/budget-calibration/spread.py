#!/usr/bin/env python3
"""Why one calibration cannot keep both of auto's promises (docs/budget.md §4).
auto buys the cheapest grid whose calibrated prediction is at most T. A pair whose prediction
reads under its measure breaks the error promise; one that reads over it by more than W buys more
than 1.3 x the maps a truthful prediction would (a grid's sampling error falls as n^-1.5, that is
as maps^-0.75, so W = 1.3^0.75 = 1.22). Both promises on a pair need predicted/measured in [1, W].
For the fitted factors times one stretch s, prints the share of pairs covered (>= 1) and the share
inside [1, W], per half of pairs.csv; then the spread of measured/calibrated (q95/q10), which a
window of width W must hold. Usage (in this folder): python3 spread.py [pairs.csv]"""
import csv, os, sys

here = os.path.dirname(os.path.abspath(__file__))
W = 1.3 ** 0.75
rows = list(csv.DictReader(open(sys.argv[1] if len(sys.argv) > 1 else os.path.join(here, 'pairs.csv'))))
halves = {
    'fitting': [r for r in rows if r['half'] == 'fitting'],
    'checking and held out': [r for r in rows if r['half'] != 'fitting'],
}
ratio = {h: [float(r['calibrated']) / float(r['measured_rmse']) for r in rs] for h, rs in halves.items()}


def quantile(xs, p):
    xs = sorted(xs)
    k = (len(xs) - 1) * p
    i = int(k)
    return xs[i] + (xs[min(i + 1, len(xs) - 1)] - xs[i]) * (k - i)


print(f'window W = 1.3^0.75 = {W:.3f}')
print('| stretch | ' + ' | '.join(f'{h}: covered | {h}: in [1, W]' for h in halves) + ' |')
print('|---:|' + '---:|---:|' * len(halves))
best = {h: (0.0, 0.0) for h in halves}
for i in range(50, 301, 5):
    s = i / 100
    cells = []
    for h, xs in ratio.items():
        covered = sum(1 for x in xs if s * x >= 1) / len(xs)
        inside = sum(1 for x in xs if 1 <= s * x <= W) / len(xs)
        best[h] = max(best[h], (inside, s))
        cells += [f'{100 * covered:.1f}%', f'{100 * inside:.1f}%']
    if i % 25 == 0 or i in (105, 110, 115, 120, 130, 140):
        print(f'| {s:.2f} | ' + ' | '.join(cells) + ' |')
print()
for h, xs in ratio.items():
    m = [1 / x for x in xs]
    print(f'{h}: {len(xs)} pairs; measured/calibrated q10 {quantile(m, 0.10):.2f}, median {quantile(m, 0.5):.2f}, q95 {quantile(m, 0.95):.2f}, '
          f'q95/q10 {quantile(m, 0.95) / quantile(m, 0.10):.2f} (a window of W = {W:.2f} holds both promises); '
          f'the most pairs inside [1, W] at any stretch: {100 * best[h][0]:.1f}% (s = {best[h][1]:.2f})')
