"""The reference through the CLI's cache; metrics and compare equal `penumbra compare`'s."""

import json
import os
import subprocess
import sys

import numpy as np

import penumbra
from conftest import SCENE, SIZE, cli

SAMPLES = 8
METHODS = ["hard", "pcss"]


def cli_compare(tmp_path):
    out = tmp_path / "compare"
    cli("compare", "--scene", SCENE, "--set", f"resolution={SIZE}", "--methods", ",".join(METHODS),
        "--repeats", "1", "--samples", str(SAMPLES), "--out", str(out))
    rows = [json.loads(line) for line in (out / "results.jsonl").read_text().splitlines()]
    return out, {r["label"]: r for r in rows}


def test_reference_metrics_and_compare_equal_the_command_lines(scene, renderer, tmp_path):
    out, theirs = cli_compare(tmp_path)
    ref = penumbra.reference(scene, samples=SAMPLES)
    assert ref.mode == "continuous 8x8" and ref.shape == (SIZE, SIZE)
    # The command line filled the cache; Python read the same file.
    assert ref.seconds is None and ref.cache_file.endswith(".vis")
    values = np.asarray(ref)
    cli_ref = penumbra.read_exr(out / "reference.exr")
    assert np.array_equal(np.nan_to_num(values, nan=0.0), cli_ref)
    for method in METHODS:
        v, _ = renderer.render(method)
        assert penumbra.metrics(v, ref) == theirs[method]["metrics"], method
    rows = penumbra.compare(scene, METHODS, repeats=1, samples=SAMPLES)
    assert [r["label"] for r in rows] == METHODS
    for r in rows:
        assert r["metrics"] == theirs[r["label"]]["metrics"]
        assert r["repeats"] == 1 and r["shadow_maps"] == theirs[r["label"]]["shadow_maps"]
    assert 0.0 < rows[0]["metrics"]["rmse"] < 0.5


def test_compare_is_quiet_without_a_terminal():
    """Progress and compare's per-method lines go to a terminal only: a pipe gets none of them."""
    code = (
        "import penumbra; s = penumbra.Scene.load('analytic-square', resolution=64); "
        "rows = penumbra.compare(s, 'hard,pcss', repeats=1, samples=8); print(len(rows))"
    )
    env = {k: v for k, v in os.environ.items() if k != "PENUMBRA_NO_PROGRESS"}
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env)
    assert p.returncode == 0, p.stderr
    assert p.stdout == "2\n"
    # Mesa may say why it has no display (XDG_RUNTIME_DIR); nothing from penumbra.
    ours = [line for line in p.stderr.splitlines() if "XDG_RUNTIME_DIR" not in line]
    assert ours == [], ours
