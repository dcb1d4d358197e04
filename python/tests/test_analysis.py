"""penumbra.analysis on its own: the reader's typed columns and its errors, and what it reads of
the engine held against the committed rows the engine's figures were fitted on or wrote."""

import glob
import io
import math

import pytest

import penumbra
from conftest import ROOT
from penumbra.analysis import RowError, build_line, calibration, engine, read, read_json, write_csv
from penumbra.analysis.frontier import read_frontier, target_of
from penumbra.analysis.rows import Row, asked, parse
from penumbra.analysis.stats import least_covering, quantile, spearman

RESULTS = ROOT / "results"


def test_a_row_reads_its_columns_by_name_and_typed():
    t = parse('scene,target,maps,met,note\n"a,b",0.03,9,true,\nc,0.012,25,False,x\n', "rows.csv")
    assert t.columns == ["scene", "target", "maps", "met", "note"] and len(t) == 2
    r = t[0]
    assert (r.text("scene"), r.number("target"), r.integer("maps"), r.flag("met")) == ("a,b", 0.03, 9, True)
    # An empty cell is a missing value: has() says so, an optional read gives None, a read names it.
    assert not r.has("note") and r.optional_number("note") is None and r.get("note", r.text, "-") == "-"
    with pytest.raises(RowError, match=r"rows.csv:2: column 'note': missing"):
        r.text("note")
    assert t[1].flag("met") is False
    with pytest.raises(RowError, match=r"rows.csv:3: column 'note': 'x' is not a number"):
        t[1].number("note")
    with pytest.raises(RowError, match=r"rows.csv:3: column 'target': '0.012' is not a whole number"):
        t[1].integer("target")


def test_a_json_row_reads_nested_keys_with_dots():
    t = parse('{"scene": "s", "metrics": {"rmse": 0.01}, "budget": {"target_met": false}, "version": {"git": "abc"}}\n', "r.jsonl", "jsonl")
    r = t[0]
    assert r.number("metrics.rmse") == 0.01 and r.flag("budget.target_met") is False
    assert not r.has("metrics.flip") and t.builds() == ["abc"]
    with pytest.raises(RowError, match=r"r.jsonl:1: column 'scene': 's' is not a number"):
        r.number("scene")


def test_a_malformed_file_is_one_error_naming_file_and_line(tmp_path):
    with pytest.raises(RowError, match=r"r.csv:3: 1 values under a header of 2"):
        parse("a,b\n1,2\n3\n", "r.csv")
    with pytest.raises(RowError, match=r"r.jsonl:2: not a JSON object"):
        parse('{"a": 1}\n[1]\n', "r.jsonl", "jsonl")
    with pytest.raises(RowError, match=r"r.jsonl:1: not JSON"):
        parse("{nope\n", "r.jsonl", "jsonl")
    with pytest.raises(RowError, match=r"missing.csv: "):
        read(tmp_path / "missing.csv")
    with pytest.raises(RowError, match=r"rows.txt: not a rows file"):
        read(tmp_path / "rows.txt")
    (tmp_path / "x.json").write_text("[1]")
    with pytest.raises(RowError, match=r"x.json: not a JSON object"):
        read_json(tmp_path / "x.json")


def test_the_build_comes_from_the_rows_own_version():
    new = parse('scene,version\na,abc\nb,abc\n', "n.csv")
    old = parse('scene\na\n', "o.csv")
    assert build_line([new, old]) == "build: abc"
    assert build_line([old]).startswith("build: not recorded in the rows")
    out = io.StringIO()
    write_csv(out, ["a", "b"], [[1, "x,y"]])
    assert out.getvalue() == 'a,b\n1,"x,y"\n'


def test_rows_written_before_the_one_schema_read_under_the_core_keys():
    # compare's rows of old: shadow_maps, total_ms, the RMSE in metrics alone, no spec or target.
    old = parse('{"scene": "s", "method": "auto", "params": {"target": 0.012000000104308128}, "shadow_maps": 9, '
                '"shadow_map_size": 512, "total_ms": 4.5, "total_ms_runs": [4, 5], "metrics": {"rmse": 0.01}}\n', "r.jsonl", "jsonl")[0]
    assert (old.integer("maps"), old.integer("map_size"), old.number("frame_ms"), old.number("rmse")) == (9, 512, 4.5, 0.01)
    assert old.raw("frame_ms_runs") == [4, 5] and old.number("target") == 0.012
    # The same row as the lab writes it now: the core keys themselves, nothing derived.
    new = parse('{"scene": "s", "spec": "auto:target=0.012", "method": "auto", "params": {"target": 0.5}, "maps": 4, '
                '"map_size": 256, "rmse": 0.02, "frame_ms": 3.0, "target": 0.012, "metrics": {"rmse": 0.03}}\n', "r.jsonl", "jsonl")[0]
    assert (new.integer("maps"), new.number("rmse"), new.number("target")) == (4, 0.02, 0.012)
    # An old frontier line (spec only): method and params from the engine's parse of the spec.
    line = Row({"spec": "regular:n=5,layout=centred", "maps": 25})
    assert (line.text("method"), line.integer("params.n"), line.text("params.layout")) == ("regular", 5, "centred")
    assert not line.has("target")
    # A spec the engine refuses derives nothing.
    assert not Row({"spec": "regular:n=3@64"}).has("method")
    assert Row({"spec": "regions:target=0.02"}).number("target") == 0.02


def test_stats():
    assert quantile([1, 2, 3, 4], 0.5) == 2.5 and quantile([5], 0.9) == 5
    assert spearman([1, 2, 3, 4], [10, 20, 15, 40]) == pytest.approx(0.8)
    assert least_covering([1, 2, 3], list(range(20)), lambda x, k: x < 10 * k, 95) == 2


def test_the_calibration_is_the_engines_and_reproduces_the_committed_calibrated_column():
    c = engine.calibration()
    pairs = calibration.read_pairs(RESULTS / "budget-calibration" / "pairs.csv")
    assert len(pairs) == 108
    for p in pairs:
        # pairs.csv's `calibrated` is `penumbra calibrate`'s with its light class's factors, each
        # figure written to 6 decimals: the engine's factors must give it back to that rounding
        # (a factor moved by 0.01 moves it by 1e-4 or more).
        f = c.factors(p.light_class)
        assert abs(p.with_factors(f) - p.calibrated) <= 5e-7 * (1 + f.sampling + f.map), (p.scene, p.spec, p.map_size)
        # The lab's split names every shipped scene's half as the pairs do.
        assert c.half(p.scene) == p.half, p.scene
    assert c.factors("plane", 4).sampling == c.even_sampling["plane"] and c.factors("cube", 5) == c.cube
    with pytest.raises(ValueError, match="light class 'ball'"):
        c.factors("ball")


def test_a_refit_on_the_committed_pairs_gives_the_factors_the_engine_ships():
    here = RESULTS / "budget-calibration"
    pairs = calibration.read_pairs(here / "pairs.csv")
    estimates = calibration.read_estimates(sorted(glob.glob(str(here / "estimates" / "*.jsonl"))))
    c = engine.calibration()
    groups = {"ball": lambda p: p.light_class == "cube"}
    before = {"plane": c.plane, "cube": c.plane}
    _, fits = calibration.classes(pairs, estimates, groups, ["ball"], before)
    # The ball lights' maps' factor, sized on their maps' part, and their sampling factor with it.
    assert (fits[0].map, fits[0].sampling) == (c.cube.map, c.cube.sampling)
    _, _, even = calibration.even_sides(calibration.read_estimates(sorted(glob.glob(str(here / "even" / "estimates" / "*.jsonl")))), pairs)
    assert even == c.even_sampling


def test_the_promise_and_the_window_are_the_labs():
    p = engine.promise()
    assert (p.met_share, p.time_ratio, p.time_share) == (0.95, 1.3, 0.9)
    assert engine.window() == pytest.approx(1.3 ** 0.75) and engine.sampling_order() == 1.5


def test_a_spec_is_read_by_the_engines_parser():
    assert engine.method_params("auto:target=0.03")["target"] == pytest.approx(0.03, rel=1e-6)
    assert asked(engine.method_params("auto:target=0.03")["target"]) == 0.03
    p = engine.method_params("regular:n=5,layout=centred")
    assert (p["method"], p["n"], p["layout"]) == ("regular", 5, "centred")
    with pytest.raises(penumbra.PenumbraError):
        engine.method_params("auto:target=nope")
    # A row's target: its column, else compare's params, else the engine's parse of its spec.
    assert target_of(Row({"target": 0.02, "spec": "auto:target=0.5"})) == 0.02
    assert target_of(Row({"params": {"target": 0.012000000104308128}})) == 0.012
    assert target_of(Row({"spec": "regions:target=0.012"})) == 0.012
    assert target_of(Row({"spec": "pcss"})) is None


def test_autos_law_gives_back_each_try_of_a_committed_run():
    runs = sorted(glob.glob(str(RESULTS / "budget-prices" / "runs" / "*.json")))
    assert runs
    for path in runs:
        for t in read_json(path).raw("method_record.tries"):
            light = engine.light_class_of_try(t["maps"], t["n"])
            # At its own grid the law is the try's own calibrated prediction.
            assert engine.predicted_at(light, t["n"], t["map_size"], t, t["n"], t["map_size"]) == pytest.approx(t["predicted_rmse"], rel=1e-12), path
            # More samples never raise it; larger maps never raise it.
            assert engine.predicted_at(light, t["n"], t["map_size"], t, t["n"] + 2, t["map_size"]) <= t["predicted_rmse"]
            assert engine.predicted_at(light, t["n"], t["map_size"], t, t["n"], 2 * t["map_size"]) <= t["predicted_rmse"]
    with pytest.raises(ValueError, match="neither n² nor 6n²"):
        engine.light_class_of_try(10, 3)


def test_regions_laws():
    assert [engine.half_octave(w) for w in (0.5, 1, 100, 1000, 1e9)] == [1, 16, 128, 1024, 8192]
    assert engine.density_floor({"constant": 0.5, "slope": 0.5, "normal_offset": 0.5}) == 2.5


def test_the_frontier_reads_the_labs_oracle_on_every_committed_frontier():
    files = sorted(glob.glob(str(RESULTS / "**" / "frontier.jsonl"), recursive=True))
    assert len(files) >= 20
    for path in files:
        f = read_frontier(path)
        for b in f.budget_rows():
            assert b.target is not None and b.target == float(f"{b.target:g}"), (path, b.spec)
            o, m = f.oracle(b), f.matched(b)
            # The lab's oracle is the cheapest fixed setting at most T, its match the cheapest at
            # most the row's own RMSE: no fixed setting both reaches and is faster.
            for level, named in ((b.target, o), (b.rmse, m)):
                reach = [s for s in f.fixed if s.rmse <= level]
                assert (named is None) == (not reach), (path, b.spec, level)
                if named:
                    assert named.rmse <= level and all(s.frame_ms >= named.frame_ms for s in reach), (path, b.spec, level)
    with pytest.raises(RowError, match="no auto row at target 0.5"):
        read_frontier(files[0]).budget_row("auto", 0.5)
    assert not math.isnan(read_frontier(files[0]).fixed[0].rmse)


def test_the_guides_example_runs(capsys, monkeypatch):
    # docs/python.md's "Analysis of results" example, as written, from the repository's root.
    text = (ROOT / "docs" / "python.md").read_text()
    section = text[text.index("## Analysis of results"):]
    code = section[section.index("```python\n") + len("```python\n"):section.index("```\n", section.index("```python\n") + 1)]
    monkeypatch.chdir(ROOT)
    exec(compile(code, "docs/python.md", "exec"), {})
    out = capsys.readouterr().out
    assert "| measured RMSE ≤ T, all rows | 3 of 3 (100%) | 95% |" in out, out
    assert out.rstrip().endswith("build: not recorded in the rows (they predate the version column; the README names it)"), out


def test_autos_record_reads_through_one_type_on_every_committed_run():
    from penumbra.analysis.auto_record import AutoRecord
    runs = sorted(glob.glob(str(RESULTS / "budget-prices" / "runs" / "*.json")))
    assert runs
    for path in runs:
        raw = read_json(path).raw("method_record")
        rec = AutoRecord.read(raw, path)
        assert len(rec.tries) == len(raw["tries"]) >= 1, path
        assert rec.target_met == raw["target_met"] and rec.chosen_map_size == raw["chosen"]["map_size"], path
        assert rec.search_ms() == pytest.approx(sum(t["ms"] for t in raw["tries"]) + (raw.get("certified") or {}).get("decision_ms", 0.0)), path
    # Out of reach: the warning is a field; a filter renders by its name; the certified bound is what it reports.
    rec = AutoRecord.read({"method": "auto", "chosen": {"n": 3, "layout": "centred", "map_size": 256, "spec": "regular:n=3,layout=centred"},
                           "target": 0.001, "target_met": False, "tries": [{"n": 3, "map_size": 256, "maps": 9, "ms": 2.0, "predicted_rmse": 0.02}],
                           "predicted_rmse": 0.02, "renders": "pcss", "certified": {"bound": 0.03, "decision_ms": 5.0},
                           "warning": "auto: target RMSE 0.001 is out of reach"})
    assert (rec.choice(), rec.reported(), rec.search_ms(), rec.warning) == ("pcss", 0.03, 7.0, "auto: target RMSE 0.001 is out of reach")
    with pytest.raises(ValueError, match="not an auto record"):
        AutoRecord.read({"method": "regions", "classes": []}, "r.json")
    with pytest.raises(ValueError, match=r"r.json: method_record.chosen is missing"):
        AutoRecord.read({"target": 0.01}, "r.json")
