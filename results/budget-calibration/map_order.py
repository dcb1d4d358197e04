#!/usr/bin/env python3
"""How fast the maps' error falls with the map size: for each (scene, setting) measured at both
512² and 1024² in pairs.csv, the order a in measured_map(1024) = measured_map(512) · 2^-a (a = 1:
as the texel size, the law `auto`'s search extrapolates by, docs/error-estimate.md §6), and the
same for the estimate's own maps' part. Usage: python3 map_order.py > map-order.csv (the medians per half on stderr)"""
import csv, math, statistics, sys

rows = list(csv.DictReader(open("pairs.csv")))
at = {}
for r in rows:
    at.setdefault((r["half"], r["scene"], r["spec"]), {})[int(r["map_size"])] = r
out = []
for (half, scene, spec), d in sorted(at.items()):
    if 512 not in d or 1024 not in d:
        continue
    a, b = d[512], d[1024]
    order = lambda key: math.log2(float(a[key]) / float(b[key])) if min(float(a[key]), float(b[key])) > 0 else float("nan")
    out.append((half, scene, spec, order("measured_map"), order("predicted_map")))
print("half,scene,spec,measured_order,estimate_order")
for half, scene, spec, m, e in out:
    print(f'{half},{scene},"{spec}",{m:.3f},{e:.3f}')
for half in ("fitting", "checking", "held out"):
    ms = [m for h, *_, m, _ in out if h == half]
    es = [e for h, *_, _, e in out if h == half]
    if ms:
        print(f"{half}: {len(ms)} settings, median measured order {statistics.median(ms):.2f}, estimate's {statistics.median(es):.2f}", file=sys.stderr)
