"""regions' certified classes against the cheapest fixed setting meeting T (issue 56, items 2-3).

  measure.py run SCENE SIDE SPEC... [--resolution R] [--repeats K] [--out DIR]
      `penumbra compare` of the SPECs (`regions:target=T` rows and fixed settings; a grid at
      another side as `regions:force=N,force_size=S`, which renders its V bit for bit), side by
      side in one run (frames interleaved round by round), the scene's maps at SIDE²; prints one
      CSV row each.
  measure.py figures rows.csv ORACLE.csv... [--variant P]
      the issue's must-show figures: per `regions:target=T` row, the cheapest fixed setting of the
      same run whose measured RMSE is at most T, and the oracle's bound for (scene, T).
      --variant P: the `regions` rows whose spec sets P besides the target (`truth_side=8`,
      `cull=off`; several sorted and joined by commas); without it, the rows of `target` alone.
  measure.py targets ROWS.csv [ORACLE.csv...]
      the target kept, over every scene of ROWS (`run` rows of `regions:target=T` alone): per
      scene and T the measured RMSE against T, `target_met` and the bound; the issue's counts.
      With the oracle's rows, the same counts split by what the oracle's family menu reaches:
      rows where one frame-wide setting of the menu meets T (its `single`), rows only a per-tile
      choice with the truth reaches, and rows nothing of the menu reaches.
"""

import csv
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

COLUMNS = ["scene", "resolution", "target", "shadow_map_size", "spec", "kind", "maps", "rmse", "ms",
           "met", "bound", "fallback", "steps", "trace_ms", "version", "adapter", "held"]


def run(args):
    scene, side, *rest = args
    opts = {"--resolution": "128", "--repeats": "3", "--out": None}
    specs = []
    while rest:
        a = rest.pop(0)
        if a in opts:
            opts[a] = rest.pop(0)
        else:
            specs.append(a)
    out = opts["--out"] or tempfile.mkdtemp(prefix="regions-measured-")
    binary = os.environ.get("PENUMBRA", "penumbra")
    cmd = [binary, "compare", "--scene", scene, "--set", f"resolution={opts['--resolution']}",
           "--set", f"shadow_map_size={side}", "--repeats", opts["--repeats"], "--out", out,
           "--methods", ",".join(specs)]
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
    w = csv.writer(sys.stdout, lineterminator="\n")
    for line in Path(out, "results.jsonl").read_text().splitlines():
        r = json.loads(line)
        record = json.loads(Path(out, Path(r["images"]["visibility"]).parent, "run.json").read_text())["method_record"]
        c = record.get("certified") or {}
        regions = r["method"] == "regions" and r["params"].get("force") is None
        w.writerow([scene, opts["--resolution"], round(record["target"], 5) if regions else "", side, r["label"],
                    "regions" if regions else "fixed", r["maps"],
                    f"{r['rmse']:.5f}", f"{r['frame_ms']:.1f}",
                    record.get("target_met", ""), f"{c['bound']:.5f}" if c else "",
                    (c.get("fallback") or {}).get("setting") or "",
                    sum(k["steps"] for k in c.get("classes", [])) if c else "",
                    f"{c['trace_ms']:.1f}" if c else "", r["version"]["git"], r["adapter"]["name"],
                    c.get("held", "") if c else ""])


def variant(spec):
    """A `regions` row's parameters besides the target, sorted and joined: '' for the default."""
    params = spec.split(":", 1)[1].split(",") if ":" in spec else []
    return ",".join(sorted(p for p in params if not p.startswith("target=")))


def split_variant(args):
    """(the arguments without `--variant P`, P or '')."""
    if "--variant" in args:
        i = args.index("--variant")
        return args[:i] + args[i + 2:], args[i + 1]
    return args, ""


def culled(spec):
    """Whether a row's maps are culled: `cull=on`, or `regions` without `cull=off` (its `auto` is
    on wherever the adapter can cull, as llvmpipe can)."""
    return "cull=on" in spec or (spec.startswith("regions") and "cull=off" not in spec)


def uncut_key(spec):
    """The spec without its culling: a culled row and its uncut twin share it (and their V)."""
    head, _, params = spec.partition(":")
    kept = [p for p in params.split(",") if p and not p.startswith("cull=")]
    return head + (":" + ",".join(sorted(kept)) if kept else "")


def culling(rows):
    """Each setting run both culled and uncut in one run: culled ms over uncut ms, the fixed
    settings' (the same V) and `regions`' per T."""
    for kind, label in (("fixed", "fixed settings, same V"), ("regions", "regions rows")):
        pairs = {}
        for r in rows:
            if r["kind"] == kind:
                key = (r["scene"], r["target"] if kind == "regions" else uncut_key(r["spec"]))
                pairs.setdefault(key, {})[culled(r["spec"])] = float(r["ms"])
        ratios = [(k, p[True] / p[False]) for k, p in pairs.items() if len(p) == 2]
        if ratios:
            print(f"culled over uncut ({len(ratios)} {label}): "
                  + ", ".join(f"{k[0]} {k[1]} {x:.2f}" for k, x in ratios))


def figures(rows_path, *oracle_paths, only=""):
    everything = list(csv.DictReader(open(rows_path)))
    rows = [r for r in everything if r["kind"] == "fixed" or variant(r["spec"]) == only]
    bounds = {}
    for o in (o for path in oracle_paths for o in csv.DictReader(open(path))):
        if o["gain_bound"]:
            bounds[(o["scene"], o["resolution"], float(o["target"]), o["menu"])] = float(o["gain_bound"])
    builds = sorted({r["version"] for r in rows})
    print(f"build: {', '.join(builds)}")
    print("| scene | T | regions RMSE | met | bound | fallback | steps | regions ms (trace) | cheapest fixed meeting T | its RMSE | its ms | gain | oracle bound (grids, family) |")
    print("|---|---:|---:|---|---:|---|---:|---:|---|---:|---:|---:|---|")
    keys = sorted({(r["scene"], r["resolution"], float(r["target"])) for r in rows if r["kind"] == "regions"}, key=lambda k: (k[0], -k[2]))
    kept = over_met = 0
    big, small, costs = [], [], []
    for key in keys:
        reg = next(r for r in rows if r["kind"] == "regions" and (r["scene"], r["resolution"], float(r["target"])) == key)
        meeting = [r for r in rows if r["kind"] == "fixed" and (r["scene"], r["resolution"]) == key[:2] and float(r["rmse"]) <= key[2]]
        fixed = min(meeting, key=lambda r: float(r["ms"])) if meeting else None
        rmse, ms = float(reg["rmse"]), float(reg["ms"])
        kept += rmse <= key[2]
        over_met += reg["met"] == "True" and rmse > key[2]
        gain = float(fixed["ms"]) / ms if fixed else None
        if fixed:
            trace = float(reg["trace_ms"])
            costs.append((trace > float(fixed["ms"]), (ms - trace) / float(fixed["ms"])))
        grids = bounds.get((key[0], key[1], key[2], "grids"))
        family = bounds.get((key[0], key[1], key[2], "family"))
        bound = family if family is not None else grids
        if bound is not None and gain is not None:
            if bound >= 1.5:
                big.append((key, gain, bound, gain - 1 >= 0.6 * (bound - 1)))
            elif bound < 1.2:
                small.append((key, gain, bound, ms <= 1.15 * float(fixed["ms"])))
        g = f"{gain:.2f}" if gain else "–"
        b = " / ".join("–" if x is None else f"{x:.2f}" for x in (grids, family))
        f = (fixed["spec"] + f" @ {fixed['shadow_map_size']}", fixed["rmse"], fixed["ms"]) if fixed else ("none of the run meets T", "–", "–")
        print(f"| {key[0]} | {key[2]} | {rmse:.4f} | {reg['met']} | {reg['bound']} | {reg['fallback'] or '–'} | {reg['steps']} | {ms:.0f} ({float(reg['trace_ms']):.0f}) | {f[0]} | {f[1]} | {f[2]} | {g} | {b} |")
    n = len(keys)
    print(f"\nmeasured RMSE ≤ T: {kept} of {n} rows ({100 * kept / n:.0f}%; 90% asked)")
    print(f"reported met while measured over T: {over_met} (0 asked)")
    ok = sum(x[3] for x in big)
    print(f"rows with bound ≥ 1.5×: {len(big)}; gain − 1 ≥ 0.6 (bound − 1) on {ok}: " + ", ".join(f"{k[0]} {k[2]} gain {g:.2f} bound {b:.2f}" for k, g, b, _ in big))
    ok = sum(x[3] for x in small)
    print(f"rows with bound < 1.2×: {len(small)}; within 1.15× of the fixed setting on {ok}: " + ", ".join(f"{k[0]} {k[2]} gain {g:.2f} bound {b:.2f}" for k, g, b, _ in small))
    regs = [r for r in rows if r["kind"] == "regions"]
    ratios = [float(r["bound"]) / float(r["rmse"]) for r in regs]
    print(f"certified bound over measured RMSE: {min(ratios):.2f}–{max(ratios):.2f}")
    print(f"frame-wide setting taken: {sum(1 for r in regs if r['fallback'])} of {len(regs)} rows")
    print(f"regions rows' maps: {sum(int(r['maps']) for r in regs)}; steps: {sum(int(r['steps']) for r in regs)}")
    culling(everything)
    traces = [float(r["trace_ms"]) for r in regs]
    print(f"the exact pixels' trace: {min(traces):.0f}–{max(traces):.0f} ms")
    print(f"the trace alone over the fixed setting's frame: {sum(c[0] for c in costs)} of {len(costs)} rows; "
          f"regions' ms less the trace over the fixed setting's: {min(c[1] for c in costs):.2f}–{max(c[1] for c in costs):.2f}")


def targets(rows_path, *oracle_paths, only=""):
    rows = [r for r in csv.DictReader(open(rows_path)) if r["kind"] == "regions" and variant(r["spec"]) == only]
    print(f"build: {', '.join(sorted({r['version'] for r in rows}))}")
    print("| scene | T | measured RMSE | RMSE / T | met | bound | maps |")
    print("|---|---:|---:|---:|---|---:|---:|")
    rows.sort(key=lambda r: (r["scene"], -float(r["target"])))
    for r in rows:
        t, rmse = float(r["target"]), float(r["rmse"])
        print(f"| {r['scene']} | {t} | {rmse:.4f} | {rmse / t:.2f} | {r['met']} | {r['bound']} | {r['maps']} |")
    kept = [r for r in rows if float(r["rmse"]) <= float(r["target"])]
    over_met = [r for r in rows if r["met"] == "True" and float(r["rmse"]) > float(r["target"])]
    unmet = [r for r in rows if r["met"] != "True"]
    print(f"\nscenes: {len({r['scene'] for r in rows})}; rows: {len(rows)}")
    print(f"measured RMSE ≤ T: {len(kept)} of {len(rows)} rows ({100 * len(kept) / len(rows):.0f}%; 90% asked)")
    print(f"reported met while measured over T: {len(over_met)} (0 asked)")
    print(f"reported not met: {len(unmet)}: " + ", ".join(f"{r['scene']} {float(r['target'])} (RMSE {float(r['rmse']):.4f}, bound {r['bound']})" for r in unmet))
    ratios = [float(r["bound"]) / float(r["rmse"]) for r in rows]
    print(f"maps over the rows: {sum(int(r['maps']) for r in rows)}; certified bound over measured RMSE: "
          f"{min(ratios):.2f}–{max(ratios):.2f} (median {sorted(ratios)[len(ratios) // 2]:.2f})")
    over = [r for r in rows if float(r["rmse"]) > float(r["target"])]
    print("over T: " + (", ".join(f"{r['scene']} {float(r['target'])} ({float(r['rmse']) / float(r['target']):.2f} T, met {r['met']})" for r in over) or "none"))
    if not oracle_paths:
        return
    # The family menu's rows: `single` names the cheapest frame-wide setting meeting T, empty
    # where none does; `best_per_tile_rmse` is the lowest a per-tile choice with the truth gives.
    family = {(o["scene"], o["resolution"], float(o["target"])): o
              for path in oracle_paths for o in csv.DictReader(open(path)) if o["menu"] == "family"}
    reach = {"one frame-wide setting": [], "only a per-tile choice": [], "nothing": [], "not in the oracle": []}
    for r in rows:
        o = family.get((r["scene"], r["resolution"], float(r["target"])))
        kind = ("not in the oracle" if o is None else "one frame-wide setting" if o["single"]
                else "only a per-tile choice" if float(o["best_per_tile_rmse"]) <= float(r["target"]) else "nothing")
        reach[kind].append(r)
    for kind, group in reach.items():
        if group:
            k = sum(float(r["rmse"]) <= float(r["target"]) for r in group)
            names = "" if kind == "one frame-wide setting" else " (" + ", ".join(f"{r['scene']} {float(r['target'])}" for r in group) + ")"
            print(f"T reached by {kind} of the menu: {len(group)} rows{names}; regions measures ≤ T on {k}")


if __name__ == "__main__":
    if len(sys.argv) > 1 and sys.argv[1] == "run":
        run(sys.argv[2:])
    elif len(sys.argv) >= 4 and sys.argv[1] == "figures":
        args, only = split_variant(sys.argv[2:])
        figures(*args, only=only)
    elif len(sys.argv) >= 3 and sys.argv[1] == "targets":
        args, only = split_variant(sys.argv[2:])
        targets(*args, only=only)
    else:
        sys.exit(__doc__)
