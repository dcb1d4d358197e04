#!/usr/bin/env python3
"""A finer grid as a truth-free reference for auto's choice: how well could it serve the promise?

Usage: reference.py OUT SCENE... > rows.csv   (OUT from render.sh; oracles from
results/budget-promise/SCENE/frontier.jsonl)

Instead of predicting each grid's error, `auto` could render the finest grid it may choose (R:
17×17 centred at 2048²) and measure each candidate c's difference from it, d_c = RMSE(V_c − V_R).
Since V_c − V_true = (V_c − V_R) + (V_R − V_true), the triangle inequality gives
    RMSE(c) <= d_c + e_R,
a bound that cannot read low where e_R (R's own error) is known. This script gives that bound
every advantage: e_R is R's *measured* error, which no truth-free method has. For each row
(scene, T) it chooses the cheapest of auto's ladder (centred n = 2-6, 8, pcss, msm at 512² and
1024²) under three rules:
  triangle:   d_c + e_R <= T   (the bound);
  quadrature: sqrt(d_c² + e_R²) <= T   (R's error taken as independent of c's; not a bound);
  as truth:   d_c <= T   (R taken for the truth);
and reads the choice's measured RMSE over T and its frame time over the oracle's (the cheapest
fixed setting of the frontier whose RMSE is at most T; both times from that frontier's run).
RMSE is over the geometry pixels, as `penumbra compare` measures it."""
import json, os, re, sys
import numpy as np
import penumbra

here = os.path.dirname(os.path.abspath(__file__))
TARGETS = [0.03, 0.02, 0.012]
LADDER = [f'regular:n={n},layout=centred' for n in (2, 3, 4, 5, 6, 8)] + ['pcss', 'msm']
RULES = {
    'triangle': lambda d, e: d + e,
    'quadrature': lambda d, e: (d * d + e * e) ** 0.5,
    'as truth': lambda d, e: d,
}


def folder(spec):
    return re.sub(r'[^A-Za-z0-9]+', '_', spec).strip('_')


def read(path):
    return penumbra.read_exr(path).astype(np.float64)


def rms(a, b, pixels):
    return float(np.sqrt(((a - b) ** 2).sum() / pixels))


out, scenes = sys.argv[1], sys.argv[2:]
print('scene,target,reference_rmse,oracle,oracle_rmse,rule,choice,choice_rmse,measured_over_target,time_over_oracle')
for scene in scenes:
    pixels = json.load(open(os.path.join(out, scene, '512', 'reference.json')))['geometry_pixels']
    truth = read(os.path.join(out, scene, '512', 'reference.exr'))
    ref = read(os.path.join(out, scene, 'ref', 'images', folder('regular:n=17,layout=centred'), 'visibility.exr'))
    e_ref = rms(ref, truth, pixels)
    fixed = [json.loads(l) for l in open(os.path.join(here, '..', 'budget-promise', scene, 'frontier.jsonl'))]
    fixed = [f for f in fixed if f['kind'] != 'error budget' and not f.get('failed')]
    ladder = []
    for f in fixed:
        if f['spec'] not in LADDER or f['map_size'] not in (512, 1024):
            continue
        run = str(f['map_size']) + ('-msm' if f['spec'] == 'msm' else '')
        v = read(os.path.join(out, scene, run, 'images', folder(f['spec']), 'visibility.exr'))
        mine = rms(v, truth, pixels)
        # The EXR is V as rendered (f32): it must be the frontier's setting, to f32 rounding.
        assert abs(mine - f['rmse']) < 1e-5 * max(1.0, f['rmse']) + 1e-6, (scene, f['spec'], f['map_size'], mine, f['rmse'])
        ladder.append(dict(label=f"{f['spec']} @ {f['map_size']}", rmse=f['rmse'], ms=f['frame_ms'], d=rms(v, ref, pixels)))
    for t in TARGETS:
        reach = [f for f in fixed if f['rmse'] <= t]
        oracle = min(reach, key=lambda f: f['frame_ms']) if reach else None
        for rule, bound in RULES.items():
            ok = [c for c in ladder if bound(c['d'], e_ref) <= t]
            c = min(ok, key=lambda c: c['ms']) if ok else None
            print(','.join(str(x) for x in [
                scene, t, f'{e_ref:.6f}',
                f'"{oracle["spec"]} @ {oracle["map_size"]}"' if oracle else 'none reaches it', f'{oracle["rmse"]:.6f}' if oracle else '', rule,
                f'"{c["label"]}"' if c else 'none meets it', f'{c["rmse"]:.6f}' if c else '',
                f'{c["rmse"] / t:.3f}' if c else '', f'{c["ms"] / oracle["frame_ms"]:.3f}' if c and oracle else '']))
