#!/usr/bin/env python3
"""The cost model's prices from culled centred grids (prices.csv: one `penumbra render` frame each
of regular:n=N,layout=centred,cull=on, N = 2, 4, 8, sides 256, 512, 1024, 128^2, --warm-up 1):
a least-squares line of raster ms per map against texels per map (intercept: c_m), and the
median shade ms per map and geometry pixel (c_s), both in texels. Usage: prices.py prices.csv"""
import csv, statistics, sys
rows = list(csv.DictReader(open(sys.argv[1])))
for scene in sorted({r['scene'] for r in rows}) + ['both']:
    sel = [r for r in rows if scene in ('both', r['scene'])]
    xs = [int(r['map_size']) ** 2 for r in sel]; ys = [float(r['raster_ms']) / int(r['maps']) for r in sel]
    mx, my = statistics.mean(xs), statistics.mean(ys)
    b = sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sum((x - mx) ** 2 for x in xs); a = my - b * mx
    s = statistics.median(float(r['shade_ms']) / int(r['maps']) / int(r['geometry_pixels']) for r in sel)
    print(f"{scene}: per map {a:.2f} ms + {b * 1e6:.2f} ms per M texels; c_m = {a / b / 1e3:.0f} k texels; shade {s * 1e6:.0f} ns per test, c_s = {s / b:.0f} texels")
