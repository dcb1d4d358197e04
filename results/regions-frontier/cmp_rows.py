#!/usr/bin/env python3
"""compare's results.jsonl per (scene, target): regions beside the fixed setting the frontier
matched it with, interleaved repeats (median). Usage: cmp_rows.py cmp/*/results.jsonl > compare-rows.csv"""
import csv, json, sys
out = csv.writer(sys.stdout)
out.writerow(["scene", "target", "map_size", "regions_ms", "regions_rmse", "regions_maps", "fixed", "fixed_ms", "fixed_rmse", "fixed_maps", "time_ratio", "fixed_as_accurate"])
for p in sys.argv[1:]:
    rows = [json.loads(l) for l in open(p)]
    r = next(x for x in rows if x["method"] == "regions"); f = next(x for x in rows if x["method"] != "regions")
    out.writerow([r["scene"], f"{r['params']['target']:.3g}", r["shadow_map_size"], f"{r['total_ms']:.1f}", f"{r['metrics']['rmse']:.5f}", r["shadow_maps"],
                  f["label"], f"{f['total_ms']:.1f}", f"{f['metrics']['rmse']:.5f}", f["shadow_maps"], f"{r['total_ms'] / f['total_ms']:.2f}",
                  "yes" if f["metrics"]["rmse"] <= r["metrics"]["rmse"] else "no"])
