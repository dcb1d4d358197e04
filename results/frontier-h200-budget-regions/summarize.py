#!/usr/bin/env python3
"""Rows of `penumbra frontier --budget` (frontier.jsonl, one file per scene): each error-budget row
(auto:target=T, regions:target=T) with its RMSE over T, whether a fixed setting is both faster and at
least as accurate, the cheapest fixed setting at most its RMSE (time ratio), and the oracle (the
cheapest fixed setting at most T; time/oracle). Usage: summarize.py S.jsonl ... > summary.csv"""
import csv, json, sys

w = csv.writer(sys.stdout, lineterminator="\n")
w.writerow(["scene", "spec", "target", "maps", "rmse", "rmse_over_target", "frame_ms", "dominated", "matched_fixed", "matched_ms", "time_over_matched", "oracle", "oracle_ms", "time_over_oracle", "paired", "reported_met"])
for path in sys.argv[1:]:
    rows = [json.loads(l) for l in open(path)]
    fixed = [r for r in rows if r["kind"] != "error budget" and r.get("rmse") is not None and r.get("frame_ms")]
    for r in rows:
        if r["kind"] != "error budget" or not r.get("frame_ms"):
            continue
        t = float(r["spec"].split("target=")[1].split(",")[0])
        dominated = any(f["frame_ms"] <= r["frame_ms"] and f["rmse"] <= r["rmse"] for f in fixed)
        cheapest = lambda bound: min((f for f in fixed if f["rmse"] <= bound), key=lambda f: f["frame_ms"], default=None)
        m, o = cheapest(r["rmse"]), cheapest(t)
        met = r.get("budget", {}).get("target_met")
        p = r.get("paired")
        over_oracle = p["ms"] / p["oracle_ms"] if p else (o and r["frame_ms"] / o["frame_ms"])
        w.writerow([r["scene"], r["spec"], t, r["maps"], f"{r['rmse']:.5f}", f"{r['rmse']/t:.2f}", f"{r['frame_ms']:.2f}", dominated,
                    m and f"{m['spec']} @ {m['map_config']}", m and f"{m['frame_ms']:.2f}", m and f"{r['frame_ms']/m['frame_ms']:.2f}",
                    o and f"{o['spec']} @ {o['map_config']}", o and f"{o['frame_ms']:.2f}", o and f"{over_oracle:.2f}", bool(p), "" if met is None else met])
