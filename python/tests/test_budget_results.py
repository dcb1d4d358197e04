"""Stand-ins for the budget results' analysis scripts (docs/budget.md §4-5): each runs on the
committed rows it documents, or on a small render of its own, and must print what the docs cite."""

import csv
import os
import subprocess
import sys

from conftest import ROOT, binary

RESULTS = ROOT / "results"


def script(path, *args):
    p = subprocess.run([sys.executable, str(RESULTS / path), *map(str, args)], capture_output=True, text=True)
    assert p.returncode == 0, f"{path}: {p.stderr}"
    return p.stdout


def test_spread_reads_the_window_both_promises_need_on_the_committed_pairs():
    out = script("budget-calibration/spread.py")
    assert "window W = 1.3^0.75 = 1.217" in out
    # The fitted factors (stretch 1) cover 95.8% of the fitting half, as docs/budget.md §4 says.
    assert "| 1.00 | 95.8% |" in out
    assert "checking and held out: 60 pairs" in out and "the most pairs inside [1, W] at any stretch: 21.7% (s = 1.00)" in out


def test_stretch_counts_each_stretch_of_the_committed_sweep():
    out = script("budget-promise/stretch.py")
    lines = [l for l in out.splitlines() if l.startswith("| ") and l.split("|")[1].strip().replace(".", "").isdigit()]
    stretches = [float(l.split("|")[1]) for l in lines]
    assert stretches == [0.65, 0.8, 1.0, 1.3], out
    # The counts docs/budget.md §8 cites: the engine's factors, and the stretch that covers every row.
    assert "| 1 | 32 of 32 | 29 (91%) | 17 of 32 (53%) | 16 (50%) | 3 of 45 | 1.20 |" in out, out
    assert "| 1.3 | 32 of 32 | 32 (100%) | 8 of 32 (25%) | 8 (25%) | 0 of 45 | 2.37 |" in out, out
    assert "rows no stretch serves: 7 of 32" in out, out


def test_the_reference_rule_on_a_real_render_keeps_its_bound(tmp_path):
    scene = "analytic-square"
    env = dict(os.environ, PENUMBRA=str(binary()), PENUMBRA_NO_PROGRESS="1")
    r = subprocess.run(["bash", str(RESULTS / "budget-reference/render.sh"), scene, str(tmp_path)], capture_output=True, text=True, env=env)
    assert r.returncode == 0, r.stderr
    out = script("budget-reference/reference.py", tmp_path, scene)
    rows = list(csv.DictReader(out.splitlines()))
    assert len(rows) == 9, out  # three targets, three rules
    e_ref = float(rows[0]["reference_rmse"])
    assert 0 < e_ref < 0.03, out
    chosen = [row for row in rows if row["rule"] == "triangle" and row["choice_rmse"]]
    assert chosen, out  # analytic-square's pcss is within the bound at 0.03 and 0.02
    for row in chosen:
        # With R's measured error the triangle bound cannot read low: its choice is at most T.
        assert float(row["choice_rmse"]) <= float(row["target"]), row
    # A rule that trusts R more never chooses a slower setting than the bound does.
    by = {(r["target"], r["rule"]): r for r in rows}
    for t in ("0.03", "0.02", "0.012"):
        slow = [by[(t, rule)]["time_over_oracle"] for rule in ("triangle", "quadrature", "as truth")]
        if all(slow):
            assert float(slow[0]) >= float(slow[1]) >= float(slow[2]), (t, slow)
    counts = subprocess.run([sys.executable, str(RESULTS / "budget-reference/counts.py"), "-"], input=out, capture_output=True, text=True)
    assert counts.returncode == 0 and "| triangle |" in counts.stdout, counts.stderr
