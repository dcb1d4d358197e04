#!/usr/bin/env python3
"""What each idea would save on one regions frame (run.json's classes): maps, texels, pairs
(triangles per map x maps) and pixel-samples shaded, for
 as-is: each class its own maps, power-of-two sides;
 half-octave: sides in steps of sqrt2 instead of 2;
 merged: a class joins the next higher class when the cost model says it is cheaper;
 one-class: every tile in the top class (the culled grid of the top n).
Cost model (texel equivalents; the method's default prices map_cost and sample_cost): per map M0 = 0.55M texels,
per texel 1, per pixel-sample shaded RHO = 40. Merged window ~ the larger extent, need ~ the finer. Usage: plan_classes.py RUN.json...
(plan-inputs/: one frame of regions:target=0.012 before groups, 128^2, lavapipe)."""
import json, math, sys
M0, RHO, DENSITY = 0.55e6, 40.0, 2.5
def side(extent, need, half):
    want = extent * DENSITY / need
    k = math.ceil((2 if half else 1) * math.log2(want)) / (2 if half else 1)
    s = 2 ** k
    return int(min(max(math.ceil(s / 16) * 16, 64), 2048))
def cost(cl, half):
    t = 0
    for c in cl:
        s = side(c['extent'], c['texel_need'], half)
        t += c['n'] ** 2 * (M0 + s * s + RHO * 64 * c['tiles'])
    return t
def stats(name, cl, half, tri):
    maps = sum(c['n'] ** 2 for c in cl)
    tex = sum(c['n'] ** 2 * side(c['extent'], c['texel_need'], half) ** 2 for c in cl)
    ps = sum(c['n'] ** 2 * 64 * c['tiles'] for c in cl)
    print(f"{name},{'/'.join(str(c['n'])+'@'+str(side(c['extent'],c['texel_need'],half)) for c in cl)},{maps},{tex/1e6:.1f},{int(maps*tri)},{ps/1e3:.0f},{cost(cl,half)/1e6:.0f}")
def merge(a, b):
    return dict(n=b['n'], tiles=a['tiles'] + b['tiles'], extent=max(a['extent'], b['extent']), texel_need=min(a['texel_need'], b['texel_need']))
print("scene,plan,classes n@side,maps,Mtexels,pairs,k_pixel_samples,model_cost_Mtexel_eq")
for f in sys.argv[1:]:
    r = json.load(open(f)); cl = r['method_record']['classes']; sc = r['scene']
    tri = sum(c['triangles_per_map_mean'] * c['maps'] for c in cl) / sum(c['maps'] for c in cl)
    pre = lambda p: sc + ',' + p
    stats(pre('as-is'), cl, False, tri)
    stats(pre('half-octave'), cl, True, tri)
    m = [dict(c) for c in cl]
    i = 0
    while i + 1 < len(m):
        joined = merge(m[i], m[i + 1])
        if cost([joined], True) < cost(m[i:i + 2], True):
            m[i:i + 2] = [joined]
        else:
            i += 1
    stats(pre('half-octave+merged'), m, True, tri)
    one = cl[0]
    for c in cl[1:]: one = merge(one, c)
    stats(pre('one-class'), [one], True, tri)
