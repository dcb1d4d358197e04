"""Renderer.certify: the certified bound of a frame's RMSE, the same as `penumbra render --certify`
writes in run.json, and the bad inputs refused in one line."""

import json

import pytest

import penumbra
from conftest import SCENE, SIZE, cli

KEYS = ["bound", "bound_kind", "sampled_rmse", "per_frame_bound", "student_t_bound", "pixels", "unique_pixels", "delta", "proxy"]


def test_certify_records_what_the_command_line_records(scene, renderer, tmp_path):
    v, record = renderer.certify("pcss", pixels=1024)
    c = record["certify"]
    cli("render", "--scene", SCENE, "--method", "pcss", "--set", f"resolution={SIZE}", "--certify", "1024", "--out", str(tmp_path))
    theirs = json.loads((tmp_path / "run.json").read_text())["certify"]
    assert {k: c[k] for k in KEYS} == {k: theirs[k] for k in KEYS}
    assert c["pixels"] == 1024 and 0 < c["unique_pixels"] <= 1024 and c["bound_kind"] == "calibrated"
    assert c["trace"]["rays"] > 0 and c["trace"]["samples_per_pixel"] == 1024 and c["trace"]["ties"] == 0
    # The bound stands above the sampled estimate, and here above the RMSE measured on every pixel.
    measured = penumbra.metrics(v, penumbra.reference(scene))["rmse"]
    assert c["sampled_rmse"] < c["bound"] and measured <= c["bound"] < 2 * measured, (measured, c)


@pytest.mark.parametrize(
    "kwargs, says",
    [
        (dict(pixels=0), "pixels = 0"),
        (dict(pixels=SIZE * SIZE + 1), f"pixels = {SIZE * SIZE + 1}"),
        (dict(delta=1.5), "delta = 1.5 is outside (0, 1)"),
        (dict(delta=0.0), "delta = 0 is outside (0, 1)"),
    ],
)
def test_bad_options_are_refused_in_one_line(renderer, kwargs, says):
    with pytest.raises(penumbra.PenumbraError) as e:
        renderer.certify("hard", **kwargs)
    assert says in str(e.value) and "\n" not in str(e.value)
