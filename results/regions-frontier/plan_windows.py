#!/usr/bin/env python3
"""Tight windows: per class (one colour of region_samples.png, 8x8-pixel tiles), the screen box of
all its tiles against its 4-connected groups' boxes. Screen area stands in for the light-space
window's area (receivers on the ground). Usage: plan_windows.py plan-inputs/SCENE... With M0 = 0.55M texels per map and side S per class
(run.json), splitting pays when k*M0 + f*S^2 < M0 + S^2 (k groups, f = boxes' area / union area)."""
import json, sys
import struct, zlib

def png_rgb(path):
    """An 8-bit RGB or RGBA PNG as (width, height, pixel(x, y) -> (r, g, b))."""
    data = open(path, 'rb').read(); pos = 8; idat = b''
    while pos < len(data):
        n, kind = struct.unpack('>I4s', data[pos:pos + 8]); body = data[pos + 8:pos + 8 + n]; pos += 12 + n
        if kind == b'IHDR': w, h, depth, ctype = struct.unpack('>IIBB', body[:10])
        elif kind == b'IDAT': idat += body
    bpp = {2: 3, 6: 4}[ctype]; raw = zlib.decompress(idat); stride = w * bpp; rows = []; prev = bytearray(stride)
    for y in range(h):
        f = raw[y * (stride + 1)]; line = bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - bpp] if i >= bpp else 0; b = prev[i]; c = prev[i - bpp] if i >= bpp else 0
            if f == 1: line[i] = (line[i] + a) & 255
            elif f == 2: line[i] = (line[i] + b) & 255
            elif f == 3: line[i] = (line[i] + (a + b) // 2) & 255
            elif f == 4:
                p = a + b - c; pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(line); prev = line
    return w, h, lambda x, y: tuple(rows[y][x * bpp:x * bpp + 3])
M0 = 0.55e6
print("scene,n,tiles,groups,union_box_tiles,groups_box_tiles,area_fraction,side,cost_one,cost_split")
for d in sys.argv[1:]:
    w, h, pixel = png_rgb(f"{d}.region_samples.png")
    r = json.load(open(f"{d}.run.json")); cl = r['method_record']['classes']
    tiles = {}
    for ty in range(h // 8):
        for tx in range(w // 8):
            c = pixel(tx * 8 + 4, ty * 8 + 4)
            if c != (40, 44, 52): tiles.setdefault(c, set()).add((tx, ty))
    # colours sorted by brightness = by n (the ramp is monotone); classes sorted by n
    cols = sorted(tiles, key=lambda c: sum(c))
    for c, rec in zip(cols, sorted(cl, key=lambda c: c['n'])):
        t = tiles[c]; seen = set(); boxes = []
        for s in t:
            if s in seen: continue
            stack = [s]; seen.add(s); comp = []
            while stack:
                x, y = stack.pop(); comp.append((x, y))
                for q in ((x+1, y), (x-1, y), (x, y+1), (x, y-1)):
                    if q in t and q not in seen: seen.add(q); stack.append(q)
            xs = [p[0] for p in comp]; ys = [p[1] for p in comp]
            boxes.append((max(xs)-min(xs)+1) * (max(ys)-min(ys)+1))
        xs = [p[0] for p in t]; ys = [p[1] for p in t]
        union = (max(xs)-min(xs)+1) * (max(ys)-min(ys)+1)
        f = min(sum(boxes) / union, 1.0); S = rec['map_size']
        print(f"{r['scene']},{rec['n']},{len(t)},{len(boxes)},{union},{sum(boxes)},{f:.2f},{S},{(M0+S*S)/1e6:.2f},{(len(boxes)*M0+f*S*S)/1e6:.2f}")
