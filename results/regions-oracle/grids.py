#!/usr/bin/env python3
"""The measured grids as rows (an analysis script): grids.py DIR... > grids.csv"""
import os, sys

from penumbra.analysis.rows import read

print("scene,resolution,n,map_size,maps,rmse,total_ms,gbuffer_ms,cull_ms,shadow_raster_ms,footprint_ms,shade_ms")
for d in sys.argv[1:]:
    for r in read(os.path.join(d, 'results.jsonl')):
        st = lambda s: f"{r.number(f'stages_ms.{s}'):.1f}"
        print(f"{r.text('scene')},{r.raw('resolution')[0]},{r.integer('params.n')},{r.integer('map_size')},{r.integer('maps')},"
              f"{r.number('rmse'):.4f},{r.number('frame_ms'):.1f},{st('gbuffer')},{st('cull')},"
              f"{st('shadow_raster')},{st('footprint')},{st('shade')}")
