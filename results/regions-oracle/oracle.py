#!/usr/bin/env python3
"""The oracle per-tile mixture of culled centred grids: an analysis script, not a user path.

Usage: oracle.py T[,T...] DIR... > rows.csv
Each DIR is one `penumbra compare` of regular:n=N,layout=centred,cull=on grids at one map size
(one scene, one resolution). From each grid's visibility.exr and the reference it knows every
pixel's squared error; it prices a frame from the grids' own stage timings (results.jsonl):

  fixed f      = median of gbuffer + readback over the grids
  per map p_Z  = median over n of (cull + shadow_raster) / n^2           (map side Z)
  per test q_Z = median over n of (shade + footprint) / (pixels * n^2)

A frame that uses the set S of settings (n, Z) and gives tile t the setting k(t) costs
  f + sum_{k in S} n_k^2 p_Zk + sum_t pixels_t n_k(t)^2 q_Zk(t),
and must keep sum_t SSE_t,k(t) <= T^2 * pixels. Tiles (8x8) whose reference is all 0 or all 1
may also take `free` (no cost, no error): a gift to the oracle, so the bound stays a bound.
For each S (branch and bound over sets by map cost) a Lagrange multiplier gives each tile
argmin cost + lambda * SSE; `oracle_ms` is the cheapest feasible such frame, `bound_ms` the
cheapest Lagrangian dual value (a lower bound on every assignment over every set).
`bound_512_ms` prices every map at the 512^2 price (as if a map fitted to its tiles gave any
density at that price); `gain_tests_only` is 1 / (1 - the single grid's share of pixel tests),
the most that choosing per tile could save with its maps shared; `best_per_tile_rmse` is the
frame's RMSE with every tile at its own most accurate setting (below it no choice reaches T).
Prices go to stderr as scene,resolution,map_size,fixed_ms,ms_per_map,ns_per_test.
"""
import json, os, sys
import numpy as np
from PIL import Image
import penumbra

TILE = 8
MAX_SET = int(os.environ.get('ORACLE_MAX_SET', 0)) or None  # a cap on |S| (then not a bound over all sets)


def load(dirs):
    where = mask = ref = None
    settings, err, per_z = [], [], {}
    fixed = []
    for d in dirs:
        r0 = penumbra.read_exr(os.path.join(d, 'reference.exr')).astype(np.float64)
        assert ref is None or (ref == r0).all(), d  # one reference for every map size
        ref = r0
        shaded = np.asarray(Image.open(os.path.join(d, 'reference_shaded.png')).convert('RGB'))
        mask = ~(shaded == shaded[0, 0]).all(-1)  # background is the corner's colour
        rows = [json.loads(l) for l in open(os.path.join(d, 'results.jsonl'))]
        for r in rows:
            n, z, px = r['params']['n'], r['shadow_map_size'], r['metrics']['pixels']
            assert px == mask.sum(), (d, px, mask.sum())
            st = r['stages_ms']
            fixed.append(st['gbuffer'] + st.get('readback', 0))
            per_z.setdefault(z, ([], []))
            per_z[z][0].append((st['cull'] + st['shadow_raster']) / n**2)
            per_z[z][1].append((st['shade'] + st['footprint']) / (px * n**2))
            img = os.path.join(d, os.path.dirname(r['images']['visibility']), 'visibility.exr')
            v = penumbra.read_exr(img)
            e = np.where(mask, (v - ref) ** 2, 0.0)
            rmse = np.sqrt(e.sum() / px)
            assert abs(rmse - r['metrics']['rmse']) < 1e-5, (d, n, rmse, r['metrics']['rmse'])
            settings.append((n, z, rmse, r['total_ms']))
            err.append(e)
        assert where in (None, (r['scene'], r['resolution'][0])), d  # one scene, one screen
        where = (r['scene'], r['resolution'][0])
    price = {z: (float(np.median(m)), float(np.median(t))) for z, (m, t) in per_z.items()}
    return where, ref, mask, settings, err, price, float(np.median(fixed))


def tiles(a):
    h, w = a.shape
    return a.reshape(h // TILE, TILE, w // TILE, TILE).sum(axis=(1, 3)).ravel()


def solve(sets_cost, c, e, budget, free):
    """Cheapest feasible Lagrangian assignment over the settings in columns c/e (tiles x k),
    and the best dual value found. Returns (primal, dual, choice) or None if infeasible."""
    c = np.concatenate([c, np.where(free, 0.0, np.inf)[:, None]], axis=1)
    e = np.concatenate([e, np.zeros((len(free), 1))], axis=1)
    if np.take_along_axis(e, np.argmin(np.where(np.isfinite(c), e, np.inf), 1)[:, None], 1).sum() > budget * (1 + 1e-12):
        return None
    best, dual = None, -np.inf
    lo, hi = -12.0, 12.0  # log10 lambda
    for _ in range(40):
        lam = 10 ** ((lo + hi) / 2)
        k = np.argmin(c + lam * e, axis=1)
        ck, ek = np.take_along_axis(c, k[:, None], 1).sum(), np.take_along_axis(e, k[:, None], 1).sum()
        dual = max(dual, ck + lam * (ek - budget))
        if ek <= budget:
            if best is None or ck < best[0]:
                best = (ck, k)
            hi = (lo + hi) / 2
        else:
            lo = (lo + hi) / 2
    if best is None:  # the most accurate choice meets the budget; lambda -> inf picks it
        k = np.argmin(np.where(np.isfinite(c), e, np.inf) + 1e-12 * np.nan_to_num(c, posinf=0), 1)
        best = (np.take_along_axis(c, k[:, None], 1).sum(), k)
    return sets_cost + best[0], sets_cost + dual, best[1]


def main():
    targets = [float(t) for t in sys.argv[1].split(',')]
    dirs = sys.argv[2:]
    d0, ref, mask, settings, err, price, f = load(dirs)
    px = tiles(mask.astype(float))
    keep = px > 0
    px = px[keep]
    refm = np.where(mask, ref, 0.5)
    lit = tiles(np.where(mask, refm >= 1.0, 0).astype(float))[keep]
    dark = tiles(np.where(mask, refm <= 0.0, 0).astype(float))[keep]
    free = (lit == px) | (dark == px)
    pen = px - lit - dark
    E = np.stack([tiles(e)[keep] for e in err], 1)
    C = np.stack([px * n**2 * price[z][1] for n, z, *_ in settings], 1)
    M = np.array([n**2 * price[z][0] for n, z, *_ in settings])
    N = mask.sum()
    name = lambda k: f"n={settings[k][0]}@{settings[k][1]}"
    for z, (pm, pt) in sorted(price.items()):
        print(f"{d0[0]},{d0[1]},{z},{f:.2f},{pm:.3f},{pt * 1e6:.1f}", file=sys.stderr)
    cheapest = M / np.array([price[z][0] for _, z, *_ in settings]) * min(p for p, _ in price.values())
    for T in targets:
        budget = T * T * N
        model = [f + M[k] + C[:, k].sum() for k in range(len(settings))]
        single = min((k for k in range(len(settings)) if settings[k][2] <= T), key=lambda k: model[k], default=None)
        reach = np.where(free, 0.0, E.min(1)).sum()  # every tile at its own best setting
        best = oracle(f, M, C, E, budget, free) if reach <= budget else [np.inf, np.inf, None, None]
        if best[2] is None:
            print(f"{d0[0]},{d0[1]},{T},none,,,,,,,,,,,{np.sqrt(reach / N):.4f}", flush=True)
            continue
        low = oracle(f, cheapest, C, E, budget, free)[1]
        use = {}  # per setting: its tiles and (the share of their pixels in penumbra, 0 < V_ref < 1)
        for j, k in enumerate(best[2]):
            t = best[3] == j
            use[name(k)] = f"{t.sum()}({pen[t].sum() / max(px[t].sum(), 1):.2f})"
        use['free'] = int((best[3] == len(best[2])).sum())
        if single is None:
            sk, gains = "none,,,", ",,"
        else:
            sk = f"{name(single)},{settings[single][2]:.4f},{model[single]:.1f},{settings[single][3]:.1f}"
            tests = C[:, single].sum() / model[single]
            gains = f"{model[single] / best[1]:.2f},{model[single] / low:.2f},{1 / (1 - tests):.2f}"
        print(f"{d0[0]},{d0[1]},{T},{sk},{best[0]:.1f},{best[1]:.1f},{low:.1f},{gains},\"{' '.join(f'{k}:{v}' for k, v in use.items())}\",{np.sqrt(reach / N):.4f}", flush=True)


def oracle(f, M, C, E, budget, free):
    """Branch and bound over sets of settings, cheapest maps first: [primal, dual, set, choice]."""
    order = np.argsort(M)
    best = [np.inf, np.inf, None, None]
    for k in order:  # the singletons first: their cost prunes the search of larger sets
        r = solve(f + M[k], C[:, [k]], E[:, [k]], budget, free)
        if r is not None and r[0] < best[0]:
            best[0], best[2], best[3] = r[0], [k], r[2]

    def dfs(start, chosen, cost):
        if len(chosen) == MAX_SET:
            return
        for i in range(start, len(order)):
            k = order[i]
            if f + cost + M[k] >= best[0]:
                break  # later settings cost more maps
            s = chosen + [k]
            r = solve(f + cost + M[k], C[:, s], E[:, s], budget, free)
            if r is not None:
                if r[0] < best[0]:
                    best[0], best[2], best[3] = r[0], s, r[2]
                best[1] = min(best[1], r[1])
            dfs(i + 1, s, cost + M[k])
    dfs(0, [], 0.0)
    return best


if __name__ == '__main__':
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    print("scene,resolution,T,single,single_rmse,single_model_ms,single_measured_ms,oracle_ms,bound_ms,bound_512_ms,gain_bound,gain_bound_512,gain_tests_only,oracle_tiles,best_per_tile_rmse")
    main()
