#!/usr/bin/env python3
"""The table of README.md from paired.csv: per row and build, the rounds' time/oracle and their median."""
import csv, statistics as st
rows = list(csv.DictReader(open("paired.csv")))
g = {}
for r in rows:
    g.setdefault((r["scene"], float(r["target"])), {}).setdefault(r["build"], []).append(r)
print("| scene | T | auto maps | measured/T | oracle (maps) | before | after |")
print("|---|---:|---:|---:|---|---:|---:|")
for (scene, t), b in g.items():
    a = b["after"][0]
    cell = lambda k: " / ".join("%.2f" % float(x["time_over_oracle"]) for x in b[k]) + " (median %.2f)" % st.median(float(x["time_over_oracle"]) for x in b[k])
    print(f"| {scene} | {t:g} | {a['auto_maps']} | {float(a['auto_rmse'])/t:.2f} | {a['oracle']} ({a['oracle_maps']}) | {cell('before')} | {cell('after')} |")
