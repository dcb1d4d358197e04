#!/usr/bin/env python3
"""Where the time goes: one run.json per setting (penumbra render with stage timing), as CSV:
maps, map sizes, texels written, (triangle, map) pairs rasterized, the decision's share of the
frame, the raster's (with its shadow_raster and cull stages) and shade's milliseconds. Usage: where.py RUN_DIR... > where.csv"""
import csv, json, sys

out = csv.writer(sys.stdout)
out.writerow(["scene", "setting", "maps", "map_sizes", "texels_written", "triangle_map_pairs", "syncs", "total_ms", "decision_ms", "decision_share", "raster_ms", "shadow_raster_ms", "cull_ms", "shade_ms"])
for d in sys.argv[1:]:
    r = json.load(open(f"{d}/run.json"))
    m = r.get("method_record", {})
    split = r["frame_split_ms"]
    if r["method"] == "regions":
        sizes = "/".join(str(c["map_size"]) for c in m["classes"])
        texels, pairs = m["texels_written"], m["triangle_map_pairs"]
    else:
        size = r["shadow_map_size"]
        sizes = str(size)
        texels = r["shadow_maps"] * size * size
        pairs = m["triangles_per_map_mean"] * r["shadow_maps"]
    out.writerow([r["scene"], r["label"] + ("" if r["method"] == "regions" else f" @ {r['shadow_map_size']}"), r["shadow_maps"], sizes, int(texels), int(pairs), r["syncs"],
                  f"{r['total_ms']:.1f}", f"{split['decision']:.1f}", f"{r['decision_share']:.3f}", f"{split['raster']:.1f}", f"{r['stages_ms'].get('shadow_raster', 0):.1f}", f"{r['stages_ms'].get('cull', 0):.1f}", f"{split['shade']:.1f}"])
