#!/usr/bin/env python3
"""The certified frame's pixels against the whole reference (penumbra.analysis.certify). In this folder:
  python3 cost.py [--scene S] [--sizes 128x128,512x512,1920x1080] [--pixels K] > rows.csv   (PENUMBRA=bin)"""
import argparse, sys
from penumbra.analysis import binary, certify, write_csv

p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
p.add_argument('--scene', default='canopy-market')
p.add_argument('--sizes', default='128x128,512x512,1920x1080')
p.add_argument('--method', default='pcss')
p.add_argument('--pixels', type=int, default=2048)
p.add_argument('--gpu-up-to', type=int, default=512 * 512, help='trace the whole reference on the GPU up to this many pixels')
a = p.parse_args()
sizes = [tuple(int(x) for x in s.split('x')) for s in a.sizes.split(',')]
with binary.scratch() as out:
    rows = certify.cost_rows(binary.find(), a.scene, sizes, a.method, a.pixels, out, a.gpu_up_to)
write_csv(sys.stdout, certify.HEADER, rows)
