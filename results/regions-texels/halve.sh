#!/bin/bash
# regions:target=T as decided, then every group's side halved and quartered: density D/2 with
# max_size 1024, D/4 with max_size 512 (D: the density the frame chose; a side of 2048 is
# max_size's). One compare per (scene, T) for RMSE, one render per setting for its groups.
# Usage: halve.sh OUT [RES] [MAP]  (env SCENES, TARGETS; penumbra on PATH). Prints CSV rows.
out=$1; res=${2:-128}; map=${3:-1024}
for s in ${SCENES:-canopy-market pergola-garden default}; do for t in ${TARGETS:-0.03 0.02 0.012}; do
  d=$out/$s-$t; mkdir -p $d
  penumbra render --scene $s --set resolution=$res --set shadow_map_size=$map --method regions:target=$t --out $d/r1 >/dev/null 2>&1
  D=$(python3 -c "import json;print(json.load(open('$d/r1/run.json'))['method_record']['density'])")
  M=("regions:target=$t" "regions:target=$t,density=$(python3 -c "print($D/2)"),max_size=1024" "regions:target=$t,density=$(python3 -c "print($D/4)"),max_size=512")
  penumbra compare --scene $s --set resolution=$res --set shadow_map_size=$map --methods "${M[0]}" --methods "${M[1]}" --methods "${M[2]}" --repeats 1 --out $d/cmp >/dev/null 2>&1
  for i in 1 2; do penumbra render --scene $s --set resolution=$res --set shadow_map_size=$map --method "${M[$i]}" --out $d/r$((i+1)) >/dev/null 2>&1; done
  python3 - "$d" "$s" "$t" <<'PY'
import csv, json, sys
d, s, t = sys.argv[1:]
out = csv.writer(sys.stdout, lineterminator="\n")
rows = [json.loads(l) for l in open(f"{d}/cmp/results.jsonl")]
for i, (r, name) in enumerate(zip(rows, ["as decided", "halved", "quartered"]), 1):
    m = json.load(open(f"{d}/r{i}/run.json"))["method_record"]
    groups = {}
    for c in m["classes"]:
        groups.setdefault(c["group"], (c["n"], c["map_size"], []))[2].append(c["decided_n"])
    g = " ".join(f"n{n}@{z}({','.join(map(str, k))})" for n, z, k in groups.values())
    out.writerow([s, t, name, r["shadow_maps"], round(r["metrics"]["rmse"], 5), round(m["density"], 2), g])
PY
done; done
