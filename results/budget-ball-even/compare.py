#!/usr/bin/env python3
"""`auto` before and after the ball lights' own maps' factor and the even sides: each scene's
auto rows here (*/frontier.jsonl) against the same scene's rows in ../budget-promise (same
command, build 46e82b9). time/oracle side by side: here the frontier's `paired` field (one
window under the oracle's maps), there ../budget-promise/paired.csv. Writes rows.csv and prints
the table of README.md."""
import csv, glob, json, os, statistics as st

here = os.path.dirname(os.path.abspath(__file__))
before_dir = os.path.join(os.path.dirname(here), 'budget-promise')
paired = {(r['scene'], float(r['target'])): r for r in csv.DictReader(open(os.path.join(before_dir, 'paired.csv')))}


def rows(path):
    out = {}
    for l in open(path):
        d = json.loads(l)
        if d['kind'] != 'error budget' or not d['spec'].startswith('auto:'):
            continue
        t = float(d['spec'].split('target=')[1].split(',')[0])
        out[t] = d
    return out


table = []
for f in sorted(glob.glob(os.path.join(here, '*/frontier.jsonl'))):
    scene = os.path.basename(os.path.dirname(f))
    after = rows(f)
    before = rows(os.path.join(before_dir, scene, 'frontier.jsonl'))
    for t in sorted(after, reverse=True):
        a, b = after[t], before[t]
        p = a.get('paired')
        ra = p['ms'] / p['oracle_ms'] if p else None
        pb = paired.get((scene, t))
        rb = float(pb['time_over_oracle']) if pb and pb['time_over_oracle'] and not pb['time_over_oracle'].startswith('failed') else None
        table.append(dict(scene=scene, target=t, before_maps=b['maps'], before_over_t=b['rmse'] / t, before_met=b['budget']['target_met'], before_time_over_oracle=rb,
                          after_maps=a['maps'], after_over_t=a['rmse'] / t, after_met=a['budget']['target_met'], after_oracle=a.get('oracle') or '', after_time_over_oracle=ra))
with open(os.path.join(here, 'rows.csv'), 'w', newline='') as fh:
    w = csv.DictWriter(fh, fieldnames=list(table[0]))
    w.writeheader()
    for r in table:
        w.writerow({k: (f'{v:.4f}' if isinstance(v, float) else v) for k, v in r.items()})
fmt = lambda v: '–' if v is None else f'{v:.2f}'
print('| scene | T | before: maps | measured/T | time/oracle | after: maps | measured/T | time/oracle |\n|---|---:|---:|---:|---:|---:|---:|---:|')
for r in table:
    print(f"| {r['scene']} | {r['target']} | {r['before_maps']}{'' if r['before_met'] else ' (not met)'} | {r['before_over_t']:.2f} | {fmt(r['before_time_over_oracle'])} | "
          f"{r['after_maps']}{'' if r['after_met'] else ' (not met)'} | {r['after_over_t']:.2f} | {fmt(r['after_time_over_oracle'])} |")
for side in ('before', 'after'):
    under = sum(r[f'{side}_over_t'] <= 1 for r in table)
    ratios = [r[f'{side}_time_over_oracle'] for r in table if r[f'{side}_time_over_oracle'] is not None]
    print(f"\n{side}: measured ≤ T on {under} of {len(table)}; time ≤ 1.3 × oracle on {sum(x <= 1.3 for x in ratios)} of {len(ratios)}, median {st.median(ratios):.2f}", end='')
print()
