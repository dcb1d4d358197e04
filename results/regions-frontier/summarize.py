#!/usr/bin/env python3
"""Rows of `regions:target=T` (and `auto:target=T`) from frontier.jsonl files, set against the
fixed settings of the same frontier: the cheapest fixed setting whose RMSE is at most the row's,
its time and the ratio, and whether any fixed setting is both faster and at least as accurate.
Usage: summarize.py SCENE.jsonl... > budget-rows.csv"""
import csv, json, sys

out = csv.writer(sys.stdout)
out.writerow(["scene", "setting", "maps", "rmse", "rmse_over_target", "median_ms", "cheapest_fixed_at_this_rmse", "its_rmse", "its_ms", "time_ratio", "dominated"])
for path in sys.argv[1:]:
    lines = [json.loads(l) for l in open(path)]
    fixed = [l for l in lines if l["kind"] != "error budget" and not l.get("failed")]
    for l in lines:
        if l["kind"] != "error budget" or l.get("failed"):
            continue
        target = float(l["spec"].split("target=")[1].split(",")[0])
        reach = [f for f in fixed if f["rmse"] <= l["rmse"]]
        best = min(reach, key=lambda f: f["frame_ms"]) if reach else None
        dominated = any(f["frame_ms"] < l["frame_ms"] for f in reach)
        out.writerow([
            l["scene"], l["spec"], l["maps"], f"{l['rmse']:.5f}", f"{l['rmse'] / target:.2f}", f"{l['frame_ms']:.1f}",
            f"{best['spec']} @ {best['map_config']}" if best else "none reaches it",
            f"{best['rmse']:.5f}" if best else "", f"{best['frame_ms']:.1f}" if best else "",
            f"{l['frame_ms'] / best['frame_ms']:.2f}" if best else "", "yes" if dominated else "no",
        ])
