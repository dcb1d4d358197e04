"""V from Python equals `penumbra render`'s, bit for bit; the pictures and the record."""

import json
from collections.abc import Mapping

import numpy as np
import pytest

import penumbra
from conftest import SCENE, SIZE, cli

METHODS = ["hard", "pcss", "regular:n=5,layout=centred", "adaptive:preset=balanced"]
# run.json's keys that depend on how the frame was timed: `penumbra render` times its stages,
# `render` times the frame (as compare's timed frames are), and only the command line warms up.
TIMED = {"timing", "timing_waits", "total_ms", "stages_ms", "gpu_stages_ms", "frame_split_ms", "decision_stages_ms", "decision_share", "warm_up_frames"}
# The renderer keeps its maps between renders (docs/reuse.md): it rasterizes fewer than a new one.
TIMED |= {"reuse"}


def bits(a):
    return np.ascontiguousarray(a, dtype=np.float32).view(np.uint32)


@pytest.mark.parametrize("method", METHODS)
def test_v_equals_the_command_lines_bit_for_bit(method, renderer, tmp_path):
    v, record = renderer.render(method)
    cli("render", "--scene", SCENE, "--method", method, "--set", f"resolution={SIZE}", "--out", str(tmp_path))
    theirs = penumbra.read_exr(tmp_path / "visibility.exr")
    assert v.dtype == np.float32 and v.shape == (SIZE, SIZE) == theirs.shape
    background = np.isnan(v)
    # The analytic square's ground fills the lower part of the picture; the sky above is background.
    assert 0 < background.sum() < SIZE * SIZE // 2
    assert np.all(theirs[background] == 0.0), "the command line writes 0 on the background"
    assert np.array_equal(bits(v[~background]), bits(theirs[~background])), method
    assert record["label"] == method and record["resolution"] == [SIZE, SIZE]
    assert record["geometry_pixels"] == int((~background).sum())
    # Built on first read, the record is run.json's, figure for figure, but for the timing.
    run = json.loads((tmp_path / "run.json").read_text())
    assert set(run) - set(record) == {"warm_up_frames"} and set(record) <= set(run)
    assert {k: v for k, v in run.items() if k not in TIMED} == {k: v for k, v in record.items() if k not in TIMED}
    assert record["timing"] == "frame" and record["total_ms"] > 0


def test_the_record_reads_as_a_dict(renderer):
    _, record = renderer.render("adaptive:preset=balanced")
    assert isinstance(record, penumbra.Record) and isinstance(record, Mapping)
    plain = record.to_dict()
    assert type(plain) is dict and plain == record and record == plain and dict(record) == plain
    assert list(record) == list(record.keys()) == list(plain) and len(record) == len(plain) > 20
    assert "method_record" in record and "no_such_key" not in record and record.get("no_such_key", 7) == 7
    assert record["method_record"] == plain["method_record"] != {}
    with pytest.raises(KeyError, match="no_such_key"):
        record["no_such_key"]
    # to_dict gives its own copy: changing it leaves the record as it was.
    plain["method_record"]["added"] = 1
    assert "added" not in record["method_record"]
    assert json.loads(json.dumps(record.to_dict())) == record
    assert repr(record).startswith("Record({") and "'label': 'adaptive:preset=balanced'" in repr(record)


def test_a_kept_renderer_renders_the_same_v_again(renderer):
    first, _ = renderer.render("adaptive:preset=balanced")
    again, _ = renderer.render("adaptive", preset="balanced")
    assert np.array_equal(bits(first), bits(again))
    assert "adaptive:preset=balanced" in renderer.methods


def test_a_renderer_keeps_its_maps_between_renders(scene, renderer):
    method = "regular:n=5,layout=centred"
    renderer.render(method)
    again, record = renderer.render(method)
    assert record["shadow_maps"] == 25 and record["reuse"]["kept"] == 25 and record["reuse"]["rendered"] == 0
    # A renderer that keeps nothing rasterizes every map, and V is the same bit for bit.
    fresh, record = penumbra.Renderer(scene, reuse=False).render(method)
    assert record["reuse"]["rendered"] == 25 and record["reuse"]["kept"] == 0
    assert np.array_equal(bits(again), bits(fresh))


def test_adaptive_pictures_and_the_error_bound_come_as_arrays(renderer):
    pictures = renderer.pictures("adaptive:preset=balanced", scope="local")
    assert set(pictures) == {"comparison_map", "low_quality", "light_quadtree", "samples_per_pixel"}
    for name in ("comparison_map", "low_quality", "samples_per_pixel"):
        assert pictures[name].shape == (SIZE, SIZE, 3) and pictures[name].dtype == np.uint8
    bound = renderer.pictures("regular:n=5,estimate=on")["error_bound"]
    assert bound.shape == (SIZE, SIZE) and bound.dtype == np.float32
    finite = bound[~np.isnan(bound)]
    assert finite.min() >= 0.0 and 0.0 < finite.max() <= 1.0
