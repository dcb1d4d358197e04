#!/usr/bin/env python3
"""The counts against the promise and the rows table of README.md, from each scene's
frontier.jsonl (measured/T, what the row reported) and paired.csv (time/oracle side by side).
Usage: python3 counts.py (in this folder)."""
import csv, glob, json, os, statistics as st

here = os.path.dirname(os.path.abspath(__file__))
paired = {(r['scene'], float(r['target'])): r for r in csv.DictReader(open(os.path.join(here, 'paired.csv')))}
rows = []
for f in sorted(glob.glob(os.path.join(here, '*/frontier.jsonl'))):
    lines = [json.loads(l) for l in open(f)]
    fixed = [l for l in lines if l['kind'] != 'error budget' and not l.get('failed')]
    for b in lines:
        if b['kind'] != 'error budget' or not b['spec'].startswith('auto:'):
            continue
        t = float(b['spec'].split('target=')[1].split(',')[0])
        # The fixed setting of the run whose V is auto's (the same RMSE, bit for bit), where the run holds it.
        same = next((f'{l["spec"]} @ {l["map_config"]}' for l in fixed if l['rmse'] == b['rmse'] and l['maps'] == b['maps']), '')
        p = paired.get((b['scene'], t))
        ratio = float(p['time_over_oracle']) if p and p['time_over_oracle'] not in ('',) and not p['time_over_oracle'].startswith('failed') else None
        oracle = next((l for l in fixed if f'{l["spec"]} @ {l["map_config"]}' == b.get('oracle')), None)
        rows.append(dict(scene=b['scene'], t=t, maps=b['maps'], rmse=b['rmse'], met=b['budget']['target_met'], pred=b['budget']['predicted'],
                         search=b['budget']['search_ms'], oracle=b.get('oracle'), oracle_maps=oracle['maps'] if oracle else None, ratio=ratio, same=same))
n = len(rows)
under = sum(r['rmse'] <= r['t'] for r in rows)
reach = [r for r in rows if r['oracle']]
reach_under = sum(r['rmse'] <= r['t'] for r in reach)
false_met = [r for r in rows if r['met'] and r['rmse'] > r['t']]
unreach = [r for r in rows if not r['met']]
timed = [r for r in reach if r['ratio'] is not None]
quick = sum(r['ratio'] <= 1.3 for r in timed)
print(f"| measured RMSE ≤ T, all rows | {under} of {n} ({100 * under / n:.0f}%) | 95% |")
print(f"| measured RMSE ≤ T, rows some fixed setting of the run reaches | {reach_under} of {len(reach)} ({100 * reach_under / len(reach):.0f}%) | 95% |")
print(f"| reported met while measured over T | {len(false_met)} | 0 |")
print(f"| reported `not met`, with the best predicted error | {len(unreach)} of {n} | every unreachable row |")
print(f"| time ≤ 1.3 × the oracle's, side by side (rows with an oracle) | {quick} of {len(timed)} ({100 * quick / len(timed):.0f}%), median {st.median(r['ratio'] for r in timed):.2f} | 90% |")
print(f"\nagainst 95%: {under}/{n}; against 90%: {quick}/{len(timed)}; false met: {[(r['scene'], r['t'], round(r['rmse'] / r['t'], 2)) for r in false_met]}")
print("\n| scene | T | maps | measured/T | reported | search ms | same V as | oracle (maps) | time/oracle |\n|---|---:|---:|---:|---|---:|---|---|---:|")
for r in rows:
    rep = f"met ({r['pred']:.4f})" if r['met'] else f"not met: best predicted {r['pred']:.4f}"
    o = f"{r['oracle']} ({r['oracle_maps']})" if r['oracle'] else 'none reaches it'
    ratio = f"{r['ratio']:.2f}" if r['ratio'] is not None else '-'
    print(f"| {r['scene']} | {r['t']} | {r['maps']} | {r['rmse'] / r['t']:.2f} | {rep} | {r['search']:.0f} | {r['same'] or 'outside the run'} | {o} | {ratio} |")
