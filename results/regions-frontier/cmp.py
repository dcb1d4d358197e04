#!/usr/bin/env python3
"""For each regions row of the frontiers: compare (interleaved repeats) regions:target=T beside the
cheapest fixed setting at least as accurate, at that setting's map size. Prints shell commands.
Usage: cmp.py [--resolution R] SCENE...  (SCENE/frontier.jsonl; R: the frontier's screen side, 128)"""
import json, sys, shlex
args = sys.argv[1:]
res = 128
if args[:1] == ["--resolution"]:
    res, args = int(args[1]), args[2:]
for scene in args:
    lines = [json.loads(l) for l in open(f"{scene}/frontier.jsonl")]
    fixed = [l for l in lines if l["kind"] != "error budget" and not l.get("failed")]
    for l in lines:
        if not l["spec"].startswith("regions:"):
            continue
        reach = [f for f in fixed if f["rmse"] <= l["rmse"]]
        if not reach:
            continue
        best = min(reach, key=lambda f: f["frame_ms"])
        size = best["map_config"].split()[-1]
        t = l["spec"].split("target=")[1]
        print(f"penumbra compare --scene {scene} --set resolution={res} --set shadow_map_size={size} --repeats 5 "
              f"--methods {shlex.quote(l['spec'] + ',' + best['spec'])} --out cmp/{scene}-{t} > cmp/{scene}-{t}.txt 2>&1")
