#!/usr/bin/env python3
"""For each regions row of the frontiers: compare (interleaved repeats) regions:target=T beside the
cheapest fixed setting at least as accurate, at that setting's map size. Prints shell commands."""
import json, sys, shlex
for scene in sys.argv[1:]:
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
        print(f"penumbra compare --scene {scene} --set resolution=128 --set shadow_map_size={size} --repeats 5 "
              f"--methods {shlex.quote(l['spec'] + ',' + best['spec'])} --out cmp/{scene}-{t} > cmp/{scene}-{t}.txt 2>&1")
