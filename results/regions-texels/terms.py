#!/usr/bin/env python3
"""Which term sets each group's map side in `regions` (docs/regions.md, "Texels"): the side is
half_octave(extent * D / need), within min_size..=max_size, where extent is the group's window
(tangent units), need its finest texel (the finest of its classes' needs, each the finest over
its tiles of max(footprint, narrowest width / n)) and D the frame's density (the maps' share of
the target, never below the floor 1 + bias constant + slope + normal offset).
Usage: terms.py RUN_DIR... (render folders of regions:target=T) > texel-terms.csv"""
import csv, json, math, sys

def half_octave(want):
    if not (want >= 1 and math.isfinite(want)):
        return 1
    side = round(2 ** (math.ceil(2 * math.log2(min(want, 8192))) / 2))
    return -(-side // 16) * 16

out = csv.writer(sys.stdout)
out.writerow(["scene", "target", "group", "n", "classes_n", "tiles", "extent", "need", "density", "floor",
              "side_asked", "side_at_floor", "max_size", "side", "set_by"])
for d in sys.argv[1:]:
    r = json.load(open(f"{d}/run.json"))
    m, p, b = r["method_record"], r["params"], r["render"]["bias"]
    floor = 1 + b["constant"] + b["slope"] + b["normal_offset"]
    groups = {}
    for c in m["classes"]:
        groups.setdefault(c["group"], []).append(c)
    for g, cs in sorted(groups.items()):
        need = min(c["texel_need"] for c in cs)
        ext, side = cs[0]["extent"], cs[0]["map_size"]
        asked, at_floor = half_octave(ext * m["density"] / need), half_octave(ext * floor / need)
        set_by = "max_size" if asked > p["max_size"] else ("min_size" if asked < p["min_size"] else ("maps' share" if m["density"] > floor else "floor"))
        out.writerow([r["scene"], f"{p['target']:.3g}", g, cs[0]["n"],
                      "/".join(str(c["decided_n"]) for c in cs), sum(c["tiles"] for c in cs), f"{ext:.3f}", f"{need:.5f}",
                      f"{m['density']:.2f}", f"{floor:.2f}", asked, at_floor, p["max_size"], side, set_by])
