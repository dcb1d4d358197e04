#!/usr/bin/env python3
"""The measured grids as rows (an analysis script): grids.py DIR... > grids.csv"""
import json, os, sys
print("scene,resolution,n,map_size,maps,rmse,total_ms,gbuffer_ms,cull_ms,shadow_raster_ms,footprint_ms,shade_ms")
for d in sys.argv[1:]:
    for r in map(json.loads, open(os.path.join(d, 'results.jsonl'))):
        st = r['stages_ms']
        print(f"{r['scene']},{r['resolution'][0]},{r['params']['n']},{r['shadow_map_size']},{r['shadow_maps']},"
              f"{r['metrics']['rmse']:.4f},{r['total_ms']:.1f},{st['gbuffer']:.1f},{st['cull']:.1f},"
              f"{st['shadow_raster']:.1f},{st['footprint']:.1f},{st['shade']:.1f}")
