#!/usr/bin/env python3
"""Which data measure separates the pairs whose maps' part under-reads (docs/budget.md §2). For
each scene, the factor its maps' part needs (measured_map / predicted_map, per setting); then
candidate classes, each given its own maps' factor fitted on the fitting half only (the least on
a 0.01 grid that covers 95% of the class's fitting pairs, the class's sampling factor kept), read
on the checking half and the held-out scenes; then the frame's own measures (the estimate's
terms, the setting) against the needed factor (Spearman's rho). Reads pairs.csv and estimates/;
prints the tables of README.md. The scene groups are what the scenes' files hold (which occluders,
which light), listed here by hand to read the data, never used by the engine."""
import csv, glob, json, math, os, statistics as st

here = os.path.dirname(os.path.abspath(__file__))
F = {'plane': (1.32, 1.12), 'cube': (1.22, 3.66)}  # src/methods/calibration.rs
est = {}
for path in glob.glob(os.path.join(here, 'estimates', '*.jsonl')):
    for line in open(path):
        d = json.loads(line)
        est[(d['scene'], d['spec'], d['map_size'])] = d
P = []
for r in csv.DictReader(open(os.path.join(here, 'pairs.csv'))):
    d = dict(est[(r['scene'], r['spec'], int(r['map_size']))])
    d['half'], d['class'] = r['half'], r['class']
    d['need'] = d['measured_map'] / d['predicted_map']
    P.append(d)
HALVES = ('fitting', 'checking', 'held out')


def cal(p, a, b):
    return math.hypot(a * p['predicted_sampling'], b * p['predicted_map'])


def reading(ps, f):
    r = [cal(p, *f(p)) / p['measured_rmse'] for p in ps]
    return f"{sum(x >= 1 for x in r)} of {len(r)}, median {st.median(r):.2f}" if r else '-'


print('| scene | half | light | maps\' part needs (6 settings) | median |\n|---|---|---|---:|---:|')
for s in sorted({p['scene'] for p in P}, key=lambda s: (HALVES.index(next(p['half'] for p in P if p['scene'] == s)), s)):
    ps = [p for p in P if p['scene'] == s]
    v = [p['need'] for p in ps]
    print(f"| {s} | {ps[0]['half']} | {ps[0]['class']} | {min(v):.2f}–{max(v):.2f} | {st.median(v):.2f} |")

GROUPS = {
    'ball light (LightKind::Point)': lambda p: p['class'] == 'cube',
    'closed meshes (a mesh file that shadows itself)': lambda p: p['scene'] in {'default', 'bunny', 'cows', 'teapot', 'dragon', 'bunny-seed-framing', 'ball-bunny'},
    'foliage (leaf quads)': lambda p: p['scene'] in {'grove', 'far-grove'},
}
# Before: one maps' factor for every class (the plane lights' fit, the ball lights' sampling
# factor the least that covers theirs with it).
BEFORE = {'plane': (1.32, 1.12), 'cube': (1.58, 1.12)}


def least(ps, covered):
    return next(k / 100 for k in range(50, 1001) if 100 * sum(covered(p, k / 100) for p in ps) >= 95 * len(ps))


print('\n| class with its own factors | fitted on | maps\' factor | sampling factor | class: checking | class: held out | all: checking | all: held out |\n|---|---|---:|---:|---|---|---|---|')
before = lambda p: BEFORE[p['class']]
print(f"| none (one maps' factor) | | | | | | {reading([p for p in P if p['half'] == 'checking'], before)} | {reading([p for p in P if p['half'] == 'held out'], before)} |")
for name, inc in GROUPS.items():
    # The engine's rule for the ball lights: the maps' factor covers 95% of the class's fitting
    # pairs' maps' part on its own measure, then the sampling factor 95% of their totals with it.
    fit = [p for p in P if p['half'] == 'fitting' and inc(p)]
    b = least(fit, lambda p, k: k * p['predicted_map'] >= p['measured_map'])
    # A light class refits its own sampling factor with it; a class of occluders keeps its
    # light's (refitted, it would drop to the grid's 0.50: their totals are the maps' part).
    a = least(fit, lambda p, k: cal(p, k, b) >= p['measured_rmse']) if name.startswith('ball') else None
    f = lambda p, a=a, b=b, inc=inc: ((a or BEFORE[p['class']][0]), b) if inc(p) else BEFORE[p['class']]
    cells = [reading([p for p in P if p['half'] == h and (inc(p) if k < 2 else True)], f) for k, h in enumerate(('checking', 'held out', 'checking', 'held out'))]
    print(f"| {name} | {', '.join(sorted({p['scene'] for p in fit}))} | {b:.2f} | {'%.2f' % a if a else 'as its light'} | " + ' | '.join(cells) + ' |')


def rank(v):
    o = sorted(range(len(v)), key=lambda i: v[i])
    r = [0] * len(v)
    for k, i in enumerate(o):
        r[i] = k
    return r


MEASURES = {
    'quantization share of the maps\' part': lambda p: p['predicted_quantization'] / p['predicted_map'],
    'averaging share of the maps\' part': lambda p: p['predicted_map_averaging'] / p['predicted_map'],
    'maps\' part over sampling part': lambda p: p['predicted_map'] / p['predicted_sampling'],
    'maps\' part': lambda p: p['predicted_map'],
    'map size': lambda p: p['map_size'],
    'maps': lambda p: p['maps'],
    'bound coverage': lambda p: p['bound_coverage'],
}
print('\n| frame measure (plane lights) | rho, fitting | rho, checking and held out |\n|---|---:|---:|')
for name, m in MEASURES.items():
    cells = []
    for hs in (('fitting',), ('checking', 'held out')):
        ps = [p for p in P if p['half'] in hs and p['class'] == 'plane']
        cells.append(f"{st.correlation(rank([m(p) for p in ps]), rank([p['need'] for p in ps])):+.2f}")
    print(f"| {name} | " + ' | '.join(cells) + ' |')
