"""V from Python equals `penumbra render`'s, bit for bit; the pictures and the record."""

import numpy as np
import pytest

import penumbra
from conftest import SCENE, SIZE, cli

METHODS = ["hard", "pcss", "regular:n=5,layout=centred", "adaptive:preset=balanced"]


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


def test_a_kept_renderer_renders_the_same_v_again(renderer):
    first, _ = renderer.render("adaptive:preset=balanced")
    again, _ = renderer.render("adaptive", preset="balanced")
    assert np.array_equal(bits(first), bits(again))
    assert "adaptive:preset=balanced" in renderer.methods


def test_adaptive_pictures_and_the_error_bound_come_as_arrays(renderer):
    pictures = renderer.pictures("adaptive:preset=balanced", scope="local")
    assert set(pictures) == {"comparison_map", "low_quality", "light_quadtree", "samples_per_pixel"}
    for name in ("comparison_map", "low_quality", "samples_per_pixel"):
        assert pictures[name].shape == (SIZE, SIZE, 3) and pictures[name].dtype == np.uint8
    bound = renderer.pictures("regular:n=5,estimate=on")["error_bound"]
    assert bound.shape == (SIZE, SIZE) and bound.dtype == np.float32
    finite = bound[~np.isnan(bound)]
    assert finite.min() >= 0.0 and 0.0 < finite.max() <= 1.0
