#!/usr/bin/env python3
"""The maps' error that regions' model predicts at the sides it rendered, against the one that
halving every side adds (halved.csv). The model's own law, m² ∝ texel, makes the measured m² at
the decided sides RMSE²(halved) − RMSE²(decided). Rows with one group only (one window, one need).
Usage: map_error.py halved.csv RUN_DIR... (render folders of regions:target=T) > map-error.csv"""
import csv, json, math, sys

rmse = {}
for row in csv.DictReader(open(sys.argv[1])):
    rmse[(row["scene"], row["target"], row["sides"])] = float(row["rmse"])
out = csv.writer(sys.stdout)
out.writerow(["scene", "target", "density_asked", "density_rendered", "predicted_map", "measured_map", "predicted_over_measured_m2"])
for d in sys.argv[2:]:
    r = json.load(open(f"{d}/run.json"))
    m, t = r["method_record"], f"{r['params']['target']:.3g}"
    cs = m["classes"]
    if len({c["group"] for c in cs}) != 1:
        continue
    need = min(c["texel_need"] for c in cs)
    rendered = cs[0]["map_size"] * need / cs[0]["extent"]
    pred = m["predicted_map"] * math.sqrt(m["density"] / rendered)
    a, b = rmse[(r["scene"], t, "as decided")], rmse[(r["scene"], t, "halved")]
    meas = math.sqrt(max(b * b - a * a, 0.0))
    out.writerow([r["scene"], t, f"{m['density']:.2f}", f"{rendered:.2f}", f"{pred:.4f}", f"{meas:.4f}", f"{(pred / meas) ** 2:.1f}" if meas > 0 else "inf"])
