#!/usr/bin/env python3
"""Why a price does or does not move auto's choice: for each auto run.json given, from each try
that missed T, the cheapest odd grid at each map size that `predicted_at` says meets T
(src/methods/auto.rs: the sampling error as n^-1.5, the maps' error with its averaging part
falling as 1/n and all of it as the texel size), its cost at the record's prices, and the price
ratio of a 2048² map to a 1024² one above which the 1024² grid would be the cheaper.
Usage: ./why.py RUN.json... > why.csv"""
import json, math, sys

def predicted_at(n, size, p, n2, size2):
    s = p["predicted_sampling"] * (n / n2) ** 1.5
    kept = 1 - (n * n) / (n2 * n2)
    texel = size / size2
    m2 = max(p["predicted_map"] ** 2 - p["predicted_map_averaging"] ** 2 * kept, 0) * texel * texel
    return math.sqrt(s * s + m2)

print("scene,target,try,n,map_size,predicted,size,cheapest_n_meeting,maps,cost,break_even_ratio_2048_over_1024,priced_ratio")
for f in sys.argv[1:]:
    r = json.load(open(f))
    rec = r["method_record"]
    t, prices = rec["target"], {int(k): v for k, v in rec["map_cost"]["per_map"].items()}
    sides = list(range(3, 18, 2))
    for k, p in enumerate(rec["tries"]):
        if p["predicted_rmse"] <= t:
            continue
        n, z = p["n"], p["map_size"]
        best = {}
        for z2 in [s for s in sorted(prices) if s >= z]:
            m = next((n2 for n2 in sides if n2 >= n and (n2, z2) != (n, z) and predicted_at(n, z, p, n2, z2) <= t), None)
            best[z2] = m
        even = ""
        if best.get(1024) and best.get(2048):
            even = "%.2f" % (best[1024] ** 2 / best[2048] ** 2)
        for z2, m in best.items():
            cost = "" if m is None else "%.0f" % (m * m * prices[z2])
            print(f'{r["scene"]},{t},{k},{n},{z},{p["predicted_rmse"]:.4f},{z2},{m or "none"},{"" if m is None else m*m},{cost},{even},{prices.get(2048, 0) / prices.get(1024, 1):.2f}')
