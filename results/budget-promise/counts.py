#!/usr/bin/env python3
"""The counts against the promise and the rows table of README.md.
Usage (in this folder): python3 counts.py [BUILD]
- BUILD with a retake (rows-BUILD.csv and alone-BUILD.csv, from retake.sh; the default is the
  newest, RETAKE): its rows, each row's figures from its render at 512² maps (alone-BUILD.csv
  where the oracle's maps are not 512², as the frontier renders its budget rows), time/oracle from
  the paired window where auto rendered the same maps there;
- BUILD 46e82b9, the build that took the frontiers: each scene's frontier.jsonl (measured/T, what
  the row reported) and paired.csv (time/oracle side by side)."""
import csv, glob, json, os, statistics as st, sys

here = os.path.dirname(os.path.abspath(__file__))
RETAKE = '9f4717b'
FIRST = '46e82b9'


def frontier(scene):
    lines = [json.loads(l) for l in open(os.path.join(here, scene, 'frontier.jsonl'))]
    return [l for l in lines if l['kind'] != 'error budget' and not l.get('failed')], lines


def same_v(fixed, maps, rmse):
    """The fixed setting of the run whose V is the row's (the same RMSE, bit for bit), where the run holds it."""
    return next((f'{l["spec"]} @ {l["map_config"]}' for l in fixed if l['rmse'] == rmse and l['maps'] == maps), '')


def first_rows():
    paired = {(r['scene'], float(r['target'])): r for r in csv.DictReader(open(os.path.join(here, 'paired.csv')))}
    rows = []
    for f in sorted(glob.glob(os.path.join(here, '*/frontier.jsonl'))):
        fixed, lines = frontier(os.path.basename(os.path.dirname(f)))
        for b in lines:
            if b['kind'] != 'error budget' or not b['spec'].startswith('auto:'):
                continue
            t = float(b['spec'].split('target=')[1].split(',')[0])
            p = paired.get((b['scene'], t))
            ratio = float(p['time_over_oracle']) if p and p['time_over_oracle'] and not p['time_over_oracle'].startswith('failed') else None
            oracle = next((l for l in fixed if f'{l["spec"]} @ {l["map_config"]}' == b.get('oracle')), None)
            rows.append(dict(scene=b['scene'], t=t, choice='', maps=b['maps'], rmse=b['rmse'], met=b['budget']['target_met'], pred=b['budget']['predicted'],
                             search=b['budget']['search_ms'], oracle=b.get('oracle'), oracle_maps=oracle['maps'] if oracle else None, ratio=ratio,
                             same=same_v(fixed, b['maps'], b['rmse']), names_best=not b['budget']['target_met']))
    return rows


def retake_rows(build):
    read = lambda name: {(r['scene'], r['target']): r for r in csv.DictReader(open(os.path.join(here, f'{name}-{build}.csv')))}
    paired, alone = read('rows'), read('alone')
    rows = []
    for key, p in paired.items():
        r = alone.get(key, p)
        if not r['maps'] or not p['maps']:
            sys.exit(f"{build}: {key[0]} at {key[1]} failed: {r['out_of_reach']} {p['out_of_reach']}")
        fixed, _ = frontier(r['scene'])
        reached = p['oracle'] != 'none reaches it'
        same_maps = p['maps'] == r['maps']
        rows.append(dict(scene=r['scene'], t=float(r['target']), choice=r['choice'], maps=int(r['maps']), rmse=float(r['rmse']), met=r['target_met'] == 'true',
                         pred=float(r['predicted_rmse']), search=float(r['search_ms']), oracle=p['oracle'] if reached else None,
                         oracle_maps=int(p['oracle_maps']) if reached else None, ratio=float(p['time_over_oracle']) if reached and same_maps else None,
                         same=same_v(fixed, int(r['maps']), float(r['rmse'])), names_best='the best predicted is' in r['out_of_reach'],
                         oracle_same=reached and float(p['oracle_rmse']) == float(p['frontier_oracle_rmse']),
                         paired=None if p is r else (p['choice'], int(p['maps']), float(p['rmse']) / float(p['target']), p['target_met'] == 'true')))
    return sorted(rows, key=lambda r: (r['scene'], -r['t']))


build = sys.argv[1] if len(sys.argv) > 1 else RETAKE
rows = first_rows() if build == FIRST else retake_rows(build)
n = len(rows)
under = sum(r['rmse'] <= r['t'] for r in rows)
reach = [r for r in rows if r['oracle']]
reach_under = sum(r['rmse'] <= r['t'] for r in reach)
false_met = [r for r in rows if r['met'] and r['rmse'] > r['t']]
unreach = [r for r in rows if not r['met']]
timed = [r for r in reach if r['ratio'] is not None]
untimed = len(reach) - len(timed)
quick = sum(r['ratio'] <= 1.3 for r in timed)
print(f"| measured RMSE ≤ T, all rows | {under} of {n} ({100 * under / n:.0f}%) | 95% |")
print(f"| measured RMSE ≤ T, rows some fixed setting of the run reaches | {reach_under} of {len(reach)} ({100 * reach_under / len(reach):.0f}%) | 95% |")
print(f"| reported met while measured over T | {len(false_met)} | 0 |")
print(f"| reported `not met`, naming the best predicted error | {sum(r['names_best'] for r in unreach)} of {len(unreach)} (of {n} rows) | every unreachable row |")
print(f"| time ≤ 1.3 × the oracle's, side by side (rows with an oracle) | {quick} of {len(timed)} ({100 * quick / len(timed):.0f}%), median {st.median(r['ratio'] for r in timed):.2f}{f' ({untimed} unpaired)' if untimed else ''} | 90% |")
print(f"\nfalse met: {[(r['scene'], r['t'], round(r['rmse'] / r['t'], 2)) for r in false_met]}")
print(f"over 1.3 × the oracle: {[(r['scene'], r['t'], round(r['ratio'], 2)) for r in timed if r['ratio'] > 1.3]}")
if 'oracle_same' in rows[0]:
    print(f"oracle rendered again at the frontier's RMSE, bit for bit: {sum(r['oracle_same'] for r in reach)} of {len(reach)}")
    for r in rows:
        if r['paired'] and (r['paired'][0], r['paired'][1]) != (r['choice'], r['maps']):
            c, m, over, met = r['paired']
            print(f"{r['scene']} at {r['t']}: under the oracle's maps auto took {c} ({m} maps, {over:.2f} T, {'met' if met else 'not met'}), at 512² {r['choice']} ({r['maps']} maps)"
                  + ('' if r['ratio'] is not None else ': time/oracle left out'))
print("\n| scene | T | choice | maps | measured/T | reported | search ms | same V as | oracle (maps) | time/oracle |\n|---|---:|---|---:|---:|---|---:|---|---|---:|")
for r in rows:
    rep = f"met ({r['pred']:.4f})" if r['met'] else f"not met: best predicted {r['pred']:.4f}"
    o = f"{r['oracle']} ({r['oracle_maps']})" if r['oracle'] else 'none reaches it'
    ratio = f"{r['ratio']:.2f}" if r['ratio'] is not None else '-'
    print(f"| {r['scene']} | {r['t']} | {r['choice'].replace(',layout=centred', '')} | {r['maps']} | {r['rmse'] / r['t']:.2f} | {rep} | {r['search']:.0f} | {r['same'] or 'outside the run'} | {o} | {ratio} |")
