"""Every driver of results/ runs here: on its folder's committed rows, where the rows are all it
reads, giving the figures its README quotes; on a small render of its own (analytic-square,
64² or 128², one repeat), where it renders through the binary."""

import csv
import io
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from conftest import ROOT, binary

RESULTS = ROOT / "results"
# regions-oracle's analysis becomes a lab study of its own (issue 56): its scripts are not drivers.
NOT_DRIVERS = {"regions-oracle"}


def run(folder, *args, cwd=None, stdin=None):
    """Runs a folder's driver with this Python and the tree's binary; returns its standard output."""
    env = dict(os.environ, PENUMBRA=str(binary()), PENUMBRA_NO_PROGRESS="1")
    p = subprocess.run([sys.executable, str(RESULTS / folder), *map(str, args)], capture_output=True, text=True, env=env, cwd=cwd or RESULTS / Path(folder).parent, input=stdin)
    assert p.returncode == 0, f"{folder} {' '.join(map(str, args))}:\n{p.stderr}"
    return p.stdout


def csv_rows(text):
    return list(csv.reader(io.StringIO(text)))


def committed(path):
    return csv_rows((RESULTS / path).read_text())


# The drivers the tests below run, each at least once.
DRIVERS = {"budget-calibration/analyze.py", "budget-promise/promise.py", "budget-prices/prices.py", "budget-reference/reference.py",
           "budget-ball-even/compare.py", "regions-frontier/regions.py", "regions-texels/texels.py", "regions-target/targets.py",
           "certify-cost/cost.py", "regions-measured/measure.py"}


# --- drivers that read committed rows --------------------------------------------------------

def test_budget_calibration_prints_its_readme_and_writes_its_rows_again(tmp_path):
    out = run("budget-calibration/analyze.py", "--out", tmp_path)
    assert out.startswith("build: not recorded in the rows")
    # spread: the window and the stretch table of README.md.
    assert "window W = 1.3^0.75 = 1.217" in out
    assert "| 1.00 | 95.8% | 62.5% | 78.3% | 21.7% |" in out and "| 1.40 | 97.9% | 0.0% | 96.7% | 11.7% |" in out
    assert "checking and held out: 60 pairs; measured/calibrated q10 0.43, median 0.77, q95 1.36, q95/q10 3.15" in out
    # classes: the ball light's own factors (the engine's), the meshes' and the foliage's.
    assert "| ball light (LightKind::Point) | point-edge | 3.66 | 1.22 | 6 of 6, median 2.12 | 6 of 6, median 2.20 | 34 of 42, median 1.28 | 13 of 18, median 1.52 |" in out
    assert "| none (one maps' factor) | | | | | | 31 of 42, median 1.17 | 8 of 18, median 0.88 |" in out
    assert "| closed meshes (a mesh file that shadows itself) | bunny, cows, default | 1.11 | as its light | 13 of 18, median 1.32 |" in out
    assert "| teapot | checking | plane | 0.47–0.82 | 0.68 |" in out and "| map size | -0.11 | -0.30 |" in out
    # misses: which part stops coverage, the stretches, the leave-one-out margin.
    assert "checking and held out: 60 pairs, 13 under (78.3% covered)" in out
    assert "| checking and held out (60) | × 4.81 (median 3.05) | × 1.40 (median 1.76) | × 1.37 (median 1.78) |" in out
    assert "sampling × 1.04, maps × 1.38, median 1.73" in out and "37 of 42 covered; 95% from a stretch of 1.04" in out
    # map order and the even sides.
    assert "held out: 3 settings, median measured order 0.46, estimate's 0.30" in out
    assert "plane 2.28, ball 2.44" in out and "| checking half, even, own sampling factor | 42 | 37 (88.1%) | 1.74 |" in out
    assert "even side predicted above the odd side below it: 35 of 45" in out
    for name in ("misses.csv", "map-order.csv", "even/even.csv"):
        assert (tmp_path / name).read_text() == (RESULTS / "budget-calibration" / name).read_text(), name


def test_budget_promise_counts_its_retake_its_frontiers_and_its_stretches():
    here = "budget-promise/promise.py"
    out = run(here, "counts", "rows-9f4717b.csv", "alone-9f4717b.csv")
    for line in ("| measured RMSE ≤ T, all rows | 33 of 45 (73%) | 95% |",
                 "| measured RMSE ≤ T, rows some fixed setting of the run reaches | 31 of 32 (97%) | 95% |",
                 "| reported met while measured over T | 1 | 0 |",
                 "| reported `not met`, naming the best predicted error | 12 of 12 (of 45 rows) | every unreachable row |",
                 "| time ≤ 1.3 × the oracle's, side by side (rows with an oracle) | 13 of 30 (43%), median 1.43 (2 unpaired) | 90% |",
                 "oracle rendered again at the frontier's RMSE, bit for bit: 32 of 32",
                 "| point-room | 0.012 | regular:n=9 @ 1024 | 486 | 0.33 | met (0.0093) | 5197 | outside the run | regular:n=4,layout=centred @ plain 512 (96) | 12.62 |"):
        assert line in out, line
    first = run(here, "counts", "--frontiers")
    assert "| time ≤ 1.3 × the oracle's, side by side (rows with an oracle) | 18 of 32 (56%), median 1.16 | 90% |" in first
    assert "| measured RMSE ≤ T, all rows | 33 of 45 (73%) | 95% |" in first
    stretch = run(here, "stretch")
    assert "| 1 | 32 of 32 | 29 (91%) | 17 of 32 (53%) | 16 (50%) | 3 of 45 | 1.20 |" in stretch
    assert "| 1.3 | 32 of 32 | 32 (100%) | 8 of 32 (25%) | 8 (25%) | 0 of 45 | 2.37 |" in stretch
    assert "rows no stretch serves: 7 of 32" in stretch
    # The frontiers' rows as one table: rows.csv's figures.
    assert csv_rows(run(here, "rows")) == committed("budget-promise/rows.csv")


def test_budget_prices_tables_and_why():
    here = "budget-prices/prices.py"
    assert "| cows | 0.03 | 9 | 0.68 | regular:n=3,layout=centred @ plain 1024 (9) | 1.52 / 1.40 (median 1.46) | 1.25 / 1.19 (median 1.22) |" in run(here, "counts")
    split = run(here, "frame-split-table")
    assert "| cows | 5 | 2048² | 1354 | 1289 | 51.6 | 32.3 | 37.9 |" in split and "| default | 3 | 1024² | 106 | 57 | 6.3 | 18.0 | 13.8 |" in split
    folder = RESULTS / "budget-prices"
    runs = sorted(str(p) for p in (folder / "runs").glob("*-1.json"))
    assert csv_rows(run(here, "why", *runs)) == committed("budget-prices/why.csv")
    assert csv_rows(run(here, "why", *sorted(str(p) for p in (folder / "runs-other").glob("*.json")))) == committed("budget-prices/why-other.csv")


def test_budget_reference_counts():
    out = run("budget-reference/reference.py", "counts")
    assert "| triangle | 32 | 21 (66%) | 13 (41%) | 13 (41%) | 11 |" in out and "| as truth | 32 | 20 (62%) | 25 (78%) | 17 (53%) | 4 |" in out


def test_budget_ball_even_compares_the_two_builds(tmp_path):
    out = run("budget-ball-even/compare.py", "--out", tmp_path / "rows.csv")
    assert "| point-room | 0.03 | 54 | 0.46 | 5.04 | 150 | 0.28 | 15.02 |" in out
    assert "before: measured ≤ T on 15 of 15; time ≤ 1.3 × oracle on 9 of 15, median 1.02" in out
    assert "after: measured ≤ T on 15 of 15; time ≤ 1.3 × oracle on 5 of 15, median 1.59" in out
    assert (tmp_path / "rows.csv").read_text() == (RESULTS / "budget-ball-even/rows.csv").read_text()


def test_regions_frontier_summaries_and_plans():
    here = "regions-frontier/regions.py"
    scenes = ["pergola-garden", "canopy-market", "default", "cows", "bunny-seed-framing"]
    assert csv_rows(run(here, "summarize", *(f"{s}.jsonl" for s in scenes))) == committed("regions-frontier/budget-rows.csv")
    h200 = RESULTS / "frontier-h200-budget-regions"
    assert csv_rows(run(here, "summary", *(h200 / f"{s}.jsonl" for s in scenes))) == committed("frontier-h200-budget-regions/summary.csv")
    assert csv_rows(run(here, "plan-classes", "plan-inputs/canopy-market.run.json", "plan-inputs/pergola-garden.run.json")) == committed("regions-frontier/plan-classes.csv")
    assert csv_rows(run(here, "plan-windows", "plan-inputs/canopy-market", "plan-inputs/pergola-garden")) == committed("regions-frontier/plan-windows.csv")
    prices = run(here, "prices", "prices.csv")
    assert prices.count("c_m = ") == 3 and prices.splitlines()[-1].startswith("both: per map")


# --- drivers that render: a small stand-in ---------------------------------------------------

@pytest.fixture(scope="module")
def frontier(tmp_path_factory):
    """A real frontier of analytic-square at 64² with one target: its auto and regions rows."""
    d = tmp_path_factory.mktemp("frontier")
    p = subprocess.run([str(binary()), "frontier", "--scene", "analytic-square", "--set", "resolution=64", "--n", "2", "--sizes", "512", "--hybrid", "none",
                        "--repeats", "1", "--budget", "0.03", "--out", str(d / "analytic-square")], capture_output=True, text=True, env=dict(os.environ, PENUMBRA_NO_PROGRESS="1"))
    assert p.returncode == 0, p.stderr
    return d


def test_budget_promise_retakes_each_auto_row_beside_its_standing_oracle(frontier):
    from penumbra.analysis import read
    from penumbra.analysis.frontier import read_frontier

    f = read_frontier(frontier / "analytic-square" / "frontier.jsonl")
    auto = f.budget_row("auto", 0.03)
    oracle = f.oracle(auto)
    assert auto.target == 0.03 and auto.row.has("version.git") and oracle is not None
    here = "budget-promise/promise.py"
    (frontier / "rows.csv").write_text(run(here, "retake", "analytic-square", "--repeats", "2", cwd=frontier))
    [row] = read(frontier / "rows.csv")
    assert (row.text("scene"), row.number("target"), row.text("oracle")) == ("analytic-square", 0.03, oracle.name)
    # The rows name their build, and the oracle rendered again reads the frontier's RMSE, bit for bit.
    assert row.text("version") == auto.row.text("version.git")
    assert row.number("oracle_rmse") == row.number("frontier_oracle_rmse") == oracle.rmse
    assert row.number("rmse") > 0 and row.number("measured_over_target") == pytest.approx(row.number("rmse") / 0.03, rel=1e-12)
    assert row.number("time_over_oracle") == pytest.approx(row.number("ms") / row.number("oracle_ms"), rel=1e-12)
    assert row.number("tries") >= 1 and row.number("search_ms") > 0
    # The stretched row: T/2 asked, measured against the row's own T, met meaning at most T/2.
    [half] = read(_write(frontier / "s2.csv", run(here, "retake", "analytic-square", "--stretch", "2", "--repeats", "1", cwd=frontier)))
    assert (half.number("target"), half.text("oracle")) == (0.03, oracle.name)
    assert half.flag("target_met") == (half.number("predicted_rmse") <= 0.015)
    # Counted against the promise: the retake's one row, its build from its own version.
    counts = run(here, "counts", frontier / "rows.csv", "--dir", frontier)
    assert counts.startswith(f"build: {row.text('version')}") and "| reported met while measured over T |" in counts


def _write(path, text):
    path.write_text(text)
    return path


def test_budget_prices_renders_its_stand_ins(frontier, tmp_path):
    here = "budget-prices/prices.py"
    split = run(here, "frame-split", "--rounds", "1", "--scenes", "analytic-square", "--sides", "3", "--sizes", "512", "--resolution", "64")
    [header, row] = csv_rows(split)
    assert header[:4] == ["round", "scene", "n", "map_size"] and row[:4] == ["1", "analytic-square", "3", "512"] and float(row[5]) > 0
    b = binary()
    prices = csv_rows(run(here, "prices", b, b, "--rounds", "1", "--rows", "analytic-square:0.03", "--resolution", "64", "--runs", tmp_path / "runs", cwd=tmp_path))
    assert [r[1] for r in prices[1:]] == ["before", "after"] and (tmp_path / "runs" / "analytic-square-0.03-1.json").is_file()
    paired = _write(tmp_path / "paired.csv", run(here, "paired", b, b, frontier / "analytic-square" / "frontier.jsonl", "--rounds", "1", "--repeats", "1"))
    assert "| analytic-square | 0.03 |" in run(here, "counts", paired)


def test_budget_reference_renders_and_keeps_its_bound(tmp_path):
    here = "budget-reference/reference.py"
    run(here, "render", "analytic-square", tmp_path)
    rows = csv_rows(run(here, "rows", tmp_path, "analytic-square"))
    header, rows = rows[0], [dict(zip(rows[0], r)) for r in rows[1:]]
    assert len(rows) == 9, rows  # three targets, three rules
    e_ref = float(rows[0]["reference_rmse"])
    assert 0 < e_ref < 0.03, rows
    chosen = [r for r in rows if r["rule"] == "triangle" and r["choice_rmse"]]
    assert chosen, rows  # analytic-square's pcss is within the bound at 0.03 and 0.02
    for r in chosen:
        # With R's measured error the triangle bound cannot read low: its choice is at most T.
        assert float(r["choice_rmse"]) <= float(r["target"]), r
    # A rule that trusts R more never chooses a slower setting than the bound does.
    by = {(r["target"], r["rule"]): r for r in rows}
    for t in ("0.03", "0.02", "0.012"):
        slow = [by[(t, rule)]["time_over_oracle"] for rule in ("triangle", "quadrature", "as truth")]
        if all(slow):
            assert float(slow[0]) >= float(slow[1]) >= float(slow[2]), (t, slow)
    text = "\n".join(",".join(f'"{v}"' if "," in v else v for v in r.values()) for r in rows)
    assert "| triangle | 3 |" in run(here, "counts", "-", stdin=",".join(header) + "\n" + text + "\n")


def test_regions_frontier_renders_where_and_compares(frontier, tmp_path):
    here = "regions-frontier/regions.py"
    p = subprocess.run([str(binary()), "render", "--scene", "analytic-square", "--set", "resolution=64", "--method", "regions:target=0.03,certify=off", "--out", str(tmp_path / "r")],
                       capture_output=True, text=True, env=dict(os.environ, PENUMBRA_NO_PROGRESS="1"))
    assert p.returncode == 0, p.stderr
    [header, row] = csv_rows(run(here, "where", tmp_path / "r"))
    assert row[0] == "analytic-square" and int(row[2]) > 0 and float(row[7]) > 0
    # The stand-in's regions row is matched with pcss (as accurate, by the frontier's RMSE).
    out = run(here, "compare", frontier / "analytic-square" / "frontier.jsonl", "--out", tmp_path / "cmp")
    assert "analytic-square-0.03: done" in out, out
    [_, cmp] = csv_rows(run(here, "compare-rows", tmp_path / "cmp" / "analytic-square-0.03" / "results.jsonl"))
    assert cmp[:3] == ["analytic-square", "0.03", "512"] and cmp[6] == "pcss" and cmp[-1] == "yes", cmp


def test_regions_texels_halves_the_sides_and_reads_the_terms(tmp_path):
    here = "regions-texels/texels.py"
    halved = _write(tmp_path / "halved.csv", run(here, "halve", tmp_path, "--scenes", "analytic-square", "--targets", "0.03", "--resolution", "64", "--map", "512"))
    rows = csv_rows(halved.read_text())
    assert [r[2] for r in rows[1:]] == ["as decided", "halved", "quartered"] and float(rows[2][5]) == pytest.approx(float(rows[1][5]) / 2, abs=0.01)
    decided = tmp_path / "analytic-square-0.03" / "r1"
    terms = csv_rows(run(here, "terms", decided))
    assert terms[1][:2] == ["analytic-square", "0.03"] and terms[1][-1] in ("max_size", "min_size", "maps' share", "floor")
    assert csv_rows(run(here, "map-error", halved, decided))[0][0] == "scene"


def test_regions_target_renders_before_and_after_and_joins_them(tmp_path):
    here = "regions-target/targets.py"
    for tag in ("before", "after"):
        run(here, "render", tmp_path, tag, "--scenes", "analytic-square", "--targets", "0.03", "--resolution", "64")
    [header, row] = csv_rows(run(here, "table", tmp_path, "--scenes", "analytic-square"))
    assert header[:2] == ["scene", "target"] and row[:2] == ["analytic-square", "0.03"]
    # The same build twice: the same V, so the same RMSE and maps.
    assert row[2:5] == row[6:9]
    table = subprocess.run([sys.executable, "-m", "penumbra.analysis.table", str(tmp_path / "after-analytic-square" / "results.jsonl"),
                            "--columns", "scene,setting,maps,rmse,ms,target_asked=target"], capture_output=True, text=True)
    assert table.returncode == 0, table.stderr
    assert csv_rows(table.stdout)[1][:2] == ["analytic-square", "regions:target=0.03"] and csv_rows(table.stdout)[1][-1] == "0.03"
    bad = subprocess.run([sys.executable, "-m", "penumbra.analysis.table", str(tmp_path / "after-analytic-square" / "results.jsonl"), "--columns", "nope"],
                         capture_output=True, text=True)
    assert bad.returncode == 1 and bad.stderr.startswith("error: ") and "column 'nope': missing" in bad.stderr


def test_certify_cost_sets_the_pixels_against_the_whole_reference():
    from penumbra.analysis import certify

    rows = csv_rows(run("certify-cost/cost.py", "--scene", "analytic-square", "--sizes", "32x32,48x32", "--pixels", "256", "--gpu-up-to", "1024"))
    assert rows[0] == certify.HEADER and [r[:5] for r in rows[1:]] == [["analytic-square", "32", "32", "pcss", "256"], ["analytic-square", "48", "32", "pcss", "256"]]
    for r in map(lambda r: dict(zip(rows[0], r)), rows[1:]):
        # At most 256 distinct pixels of 32 × 32 samples each; the reference traces every pixel.
        assert 0 < int(r["certify_rays"]) <= 256 * 1024 < int(r["reference_cpu_rays"]) * 4
        assert float(r["rays_over_reference"]) == int(r["certify_rays"]) / int(r["reference_cpu_rays"])
        assert float(r["pixels_over_reference"]) == float(r["certify_pixels_ms"]) / 1e3 / float(r["reference_cpu_s"])
        assert float(r["bound"]) >= float(r["rmse_sampled"]) > 0
    # The GPU traced the whole reference of the first screen only (1,024 pixels).
    assert rows[1][rows[0].index("reference_gpu_s")] != "" and rows[2][rows[0].index("reference_gpu_s")] == ""


FIGURES_REGIONS_MEASURED = (
    "build: ee1fe26b305f",
    "| yard | 0.02 | 0.0169 | True | 0.01996 | – | 0 | 898 (292) | adaptive:preset=seed @ 512 | 0.01855 | 143.8 | 0.16 | 2.16 / 4.36 |",
    "| pergola-garden | 0.012 | 0.0154 | False | 0.01854 | – | 0 | 2768 (355) | none of the run meets T | – | – | – | – / – |",
    "measured RMSE ≤ T: 11 of 12 rows (92%; 90% asked)",
    "reported met while measured over T: 0 (0 asked)",
    "rows with bound ≥ 1.5×: 8; gain − 1 ≥ 0.6 (bound − 1) on 0:",
    "rows with bound < 1.2×: 2; within 1.15× of the fixed setting on 0: default 0.03 gain 0.08 bound 1.04, default 0.012 gain 0.23 bound 1.04",
    "certified bound over measured RMSE: 1.17–1.86",
    "regions rows' maps: 2376; steps: 0",
    "the trace alone over the fixed setting's frame: 8 of 11 rows; regions' ms less the trace over the fixed setting's: 0.30–11.25",
)
# The same commands with each setting at δ/C (rows-54e48a9.csv): the README's middle column.
FIGURES_EACH_AT_DELTA_OVER_C = (
    "build: 54e48a94c71a",
    "certified bound over measured RMSE: 0.99–1.57",
    "regions rows' maps: 1952; steps: 0",
    "rows with bound < 1.2×: 2; within 1.15× of the fixed setting on 0: default 0.03 gain 0.12 bound 1.04, default 0.012 gain 0.19 bound 1.04",
)
# The same commands before the hold (rows-18e3d57.csv): the README's "before" column.
FIGURES_BEFORE_THE_HOLD = (
    "rows with bound ≥ 1.5×: 8; gain − 1 ≥ 0.6 (bound − 1) on 0:",
    "frame-wide setting taken: 7 of 12 rows",
    "regions rows' maps: 2813; steps: 21",
)

# Two 8 × 8 estimates per exact pixel beside the reference's truth (rows-truth-side-8.csv).
FIGURES_TRUTH_SIDE_8 = (
    "| yard | 0.012 | 0.0091 | False | 0.01314 | – | 0 | 3001 (101) | regions:force=16,force_size=2048 @ 512 | 0.00966 | 2095.2 | 0.70 | 2.87 / 3.21 |",
    "measured RMSE ≤ T: 11 of 12 rows (92%; 90% asked)",
    "rows with bound < 1.2×: 2; within 1.15× of the fixed setting on 0: default 0.03 gain 0.16 bound 1.04, default 0.012 gain 0.39 bound 1.04",
    "certified bound over measured RMSE: 1.21–1.90",
    "the exact pixels' trace: 77–196 ms",
    "the trace alone over the fixed setting's frame: 4 of 11 rows; regions' ms less the trace over the fixed setting's: 1.38–6.89",
)
FIGURES_TRUTH_SIDE_8_REFERENCE = (
    "certified bound over measured RMSE: 1.17–1.86",
    "the exact pixels' trace: 317–1158 ms",
    "the trace alone over the fixed setting's frame: 8 of 11 rows; regions' ms less the trace over the fixed setting's: 1.85–5.81",
)

# Every fixed setting culled and uncut, regions with and without culling (rows-cull.csv).
FIGURES_CULL = (
    "culled over uncut (11 fixed settings, same V): yard regular:layout=centred,n=6 2.45,",
    "canopy-market regular:layout=centred,n=4 1.64, canopy-market regular:layout=centred,n=6 1.78,",
    "default regions:force=2,force_size=512 0.89, default regions:force=2,force_size=2048 0.97, default regions:force=3,force_size=2048 0.96, pergola-garden regular:layout=centred,n=8 2.15, pergola-garden regular:layout=centred,n=16 2.03",
    "yard regions:force=6,force_size=2048 1.31, yard regions:force=16,force_size=2048 1.38",
    "canopy-market regions:force=11,force_size=2048 1.40",
    "| yard | 0.03 | 0.0197 | True | 0.02621 | – | 0 | 639 (334) | regular:n=6,layout=centred @ 512 | 0.02662 | 47.4 | 0.07 | 1.87 / 5.95 |",
    "rows with bound ≥ 1.5×: 8; gain − 1 ≥ 0.6 (bound − 1) on 0:",
    "rows with bound < 1.2×: 2; within 1.15× of the fixed setting on 0: default 0.03 gain 0.06 bound 1.04, default 0.012 gain 0.11 bound 1.04",
    "regions' ms less the trace over the fixed setting's: 2.08–11.56",
    "culled over uncut (12 regions rows): yard 0.03 1.31, yard 0.02 1.41, yard 0.012 1.33, canopy-market 0.03 1.07, canopy-market 0.02 0.90, canopy-market 0.012 0.89, default 0.03 0.91, default 0.02 0.99, default 0.012 1.01, pergola-garden 0.03 0.97, pergola-garden 0.02 1.00, pergola-garden 0.012 1.16",
)
FIGURES_CULL_LISTED = (
    "culled over uncut (12 regions rows): yard 0.03 1.09, yard 0.02 1.19, yard 0.012 1.12, canopy-market 0.03 1.04, canopy-market 0.02 1.02, canopy-market 0.012 1.14, default 0.03 0.94, default 0.02 0.99, default 0.012 1.00, pergola-garden 0.03 1.09, pergola-garden 0.02 1.38, pergola-garden 0.012 1.06",
    "rows with bound ≥ 1.5×: 8; gain − 1 ≥ 0.6 (bound − 1) on 0:",
    "yard 0.012 gain 0.30 bound 3.21",
    "rows with bound < 1.2×: 2; within 1.15× of the fixed setting on 0: default 0.03 gain 0.05 bound 1.04, default 0.012 gain 0.13 bound 1.04",
)
FIGURES_CULL_OFF = (
    "| yard | 0.012 | 0.0089 | True | 0.01184 | – | 0 | 3811 (344) | regions:cull=off,force=16,force_size=2048 @ 512 | 0.00966 | 1329.1 | 0.35 | 2.87 / 3.21 |",
    "rows with bound < 1.2×: 2; within 1.15× of the fixed setting on 0: default 0.03 gain 0.06 bound 1.04, default 0.012 gain 0.12 bound 1.04",
)


# The target over every shipped scene regions takes (rows-targets.csv): the README's counts.
TARGETS_REGIONS_MEASURED = (
    "build: ee1fe26b305f",
    "| grazing-ground | 0.03 | 0.1766 | 5.89 | False | 0.20476 | 258 |",
    "| spot-edge | 0.012 | 0.0069 | 0.57 | True | 0.01003 | 54 |",
    "scenes: 11; rows: 33",
    "measured RMSE ≤ T: 26 of 33 rows (79%; 90% asked)",
    "reported met while measured over T: 0 (0 asked)",
    "reported not met: 9:",
    "maps over the rows: 7463; certified bound over measured RMSE: 1.16–1.86 (median 1.24)",
    "T reached by one frame-wide setting of the menu: 26 rows; regions measures ≤ T on 26",
    "T reached by only a per-tile choice of the menu: 2 rows (grazing-ground 0.03, grazing-ground 0.02); regions measures ≤ T on 0",
    "T reached by nothing of the menu: 5 rows (grazing-ground 0.012, pergola-garden 0.012, pole-between-corners 0.012, slat-roof 0.02, slat-roof 0.012); regions measures ≤ T on 0",
)
# The four scenes at 256² (rows-targets-256.csv).
TARGETS_256 = (
    "scenes: 4; rows: 12",
    "measured RMSE ≤ T: 11 of 12 rows (92%; 90% asked)",
    "reported met while measured over T: 0 (0 asked)",
    "reported not met: 2: pergola-garden 0.02 (RMSE 0.0155, bound 0.02038), pergola-garden 0.012 (RMSE 0.0156, bound 0.01937)",
    "certified bound over measured RMSE: 1.20–1.70 (median 1.32)",
    "over T: pergola-garden 0.012 (1.30 T, met False)",
)
# The same before each setting's δ was shared over the settings reachable (rows-targets-54e48a9.csv).
TARGETS_BEFORE_THE_UNION = (
    "measured RMSE ≤ T: 26 of 33 rows (79%; 90% asked)",
    "maps over the rows: 6810; certified bound over measured RMSE: 0.99–1.57 (median 1.16)",
)


def test_regions_measured_counts_its_figures_and_renders_a_row_of_each_kind():
    here = "regions-measured/measure.py"
    out = run(here, "figures", "rows.csv", "../oracle/oracle.csv", "oracle-more.csv")
    for line in FIGURES_REGIONS_MEASURED:
        assert line in out, line
    at_c = run(here, "figures", "rows-54e48a9.csv", "../oracle/oracle.csv", "oracle-more.csv")
    for line in FIGURES_EACH_AT_DELTA_OVER_C:
        assert line in at_c, line
    before = run(here, "figures", "rows-18e3d57.csv", "../oracle/oracle.csv", "oracle-more.csv")
    for line in FIGURES_BEFORE_THE_HOLD:
        assert line in before, line
    paired = run(here, "figures", "rows-truth-side-8.csv", "../oracle/oracle.csv", "oracle-more.csv", "--variant", "truth_side=8")
    for line in FIGURES_TRUTH_SIDE_8:
        assert line in paired, line
    reference = run(here, "figures", "rows-truth-side-8.csv", "../oracle/oracle.csv", "oracle-more.csv")
    for line in FIGURES_TRUTH_SIDE_8_REFERENCE:
        assert line in reference, line
    assert "truth_side=8" not in reference and "0.01314" not in reference
    cull = run(here, "figures", "rows-cull.csv", "../oracle/oracle.csv", "oracle-more.csv")
    for line in FIGURES_CULL:
        assert line in cull, line
    listed = run(here, "figures", "rows-cull-listed.csv", "../oracle/oracle.csv", "oracle-more.csv")
    for line in FIGURES_CULL_LISTED:
        assert line in listed, line
    cull_off = run(here, "figures", "rows-cull.csv", "../oracle/oracle.csv", "oracle-more.csv", "--variant", "cull=off")
    for line in FIGURES_CULL_OFF:
        assert line in cull_off, line
    targets = run(here, "targets", "rows-targets.csv", "../oracle/oracle.csv", "oracle-more.csv")
    for line in TARGETS_REGIONS_MEASURED:
        assert line in targets, line
    at_256 = run(here, "targets", "rows-targets-256.csv")
    for line in TARGETS_256:
        assert line in at_256, line
    before = run(here, "targets", "rows-targets-54e48a9.csv")
    for line in TARGETS_BEFORE_THE_UNION:
        assert line in before, line
    rows = csv_rows(run(here, "run", "analytic-square", "256", "regions:target=0.05,pixels=64", "regular:n=2,layout=centred,cull=on", "--resolution", "64", "--repeats", "1"))
    assert [r[:2] + r[4:6] for r in rows] == [["analytic-square", "64", "regions:target=0.05,pixels=64", "regions"],
                                              ["analytic-square", "64", "regular:n=2,layout=centred,cull=on", "fixed"]]
    # The regions row carries its certified bound and says met only where the bound is at most T.
    met, bound = rows[0][9], float(rows[0][10])
    assert rows[0][2] == "0.05" and (met == "True") == (bound <= 0.05), rows[0]


def test_oracle_runs_each_listed_scene_and_joins_their_rows(tmp_path):
    # The driver writes beside itself: a copy in a scratch folder, on one tiny scene.
    shutil.copy(RESULTS / "oracle" / "run.sh", tmp_path)
    env = dict(os.environ, PENUMBRA=str(binary()), PENUMBRA_NO_PROGRESS="1")
    runs = "# scene resolution flags\nanalytic-square 32 --targets 0.5,0.02 --n 1,4 --sizes 64,256 --singles pcss --hybrid none --adaptive none --repeats 1 --samples 16\n"
    p = subprocess.run(["bash", str(tmp_path / "run.sh")], input=runs, capture_output=True, text=True, env=env)
    assert p.returncode == 0 and "FAIL" not in p.stdout, p.stdout + p.stderr
    joined, own = csv_rows((tmp_path / "oracle.csv").read_text()), csv_rows((tmp_path / "analytic-square-32" / "oracle.csv").read_text())
    # Two menus (grids, family) × two targets, under the committed rows' header.
    assert joined == own and len(own) == 5 and own[0] == committed("oracle/oracle.csv")[0]
    # A folder that holds its rows is kept: a second run renders nothing.
    again = subprocess.run(["bash", str(tmp_path / "run.sh")], input=runs, capture_output=True, text=True, env=env)
    assert again.returncode == 0 and "analytic-square-32" not in again.stdout, again.stdout


# Drivers a lab test runs (it needs the census's scene helpers and the lab's CSV checks).
RUN_BY_LAB = {"bad-input-census/measure.sh": "lab/tests/bad_input_census_script.rs"}


def test_every_driver_in_results_runs_here():
    found = {str(p.relative_to(RESULTS)) for p in RESULTS.rglob("*") if p.suffix in (".py", ".sh") and p.relative_to(RESULTS).parts[0] not in NOT_DRIVERS}
    tested = DRIVERS | {"oracle/run.sh"} | set(RUN_BY_LAB)
    assert found == tested, f"drivers no test runs: {sorted(found - tested)}; tested but gone: {sorted(tested - found)}"
    for driver, test in RUN_BY_LAB.items():
        assert f"results/{driver}" in (ROOT / test).read_text(), f"{test} does not run {driver}"
