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
        assert r["repeats"] == 1 and r["maps"] == theirs[r["label"]]["maps"]
    assert 0.0 < rows[0]["metrics"]["rmse"] < 0.5


# Long work: a reference traced afresh, then compare with repeats.
LONG_WORK = (
    "import penumbra; s = penumbra.Scene.load('analytic-square', resolution=64); "
    "ref = penumbra.reference(s, samples=8, no_cache=True); "
    "rows = penumbra.compare(s, 'hard,pcss', repeats=2, samples=8); print(len(rows), ref.seconds is not None)"
)


def run_long_work(stderr):
    """Runs LONG_WORK in a fresh interpreter with stderr to `stderr`; returns the process."""
    env = {k: v for k, v in os.environ.items() if k != "PENUMBRA_NO_PROGRESS"}
    p = subprocess.run([sys.executable, "-c", LONG_WORK], stdout=subprocess.PIPE, stderr=stderr, text=True, env=env)
    assert p.returncode == 0, p.stderr
    assert p.stdout == "2 True\n"
    return p


def test_long_work_is_quiet_without_a_terminal():
    """Progress and compare's per-method lines go to a terminal only: a pipe gets none of them."""
    p = run_long_work(subprocess.PIPE)
    # Mesa may say why it has no display (XDG_RUNTIME_DIR); nothing from penumbra.
    ours = [line for line in p.stderr.splitlines() if "XDG_RUNTIME_DIR" not in line]
    assert ours == [], ours


def test_long_work_shows_progress_on_a_terminal():
    """The same work with stderr on a terminal draws the reference's and the frames' bars and
    prints compare's line per method."""
    import pty
    import re

    master, terminal = pty.openpty()
    try:
        run_long_work(terminal)
        os.close(terminal)
        seen = b""
        while True:
            try:
                chunk = os.read(master, 1 << 16)
            except OSError:  # the terminal's other end is closed: all was read
                break
            if not chunk:
                break
            seen += chunk
    finally:
        os.close(master)
    text = re.sub(r"\x1b\[[0-9]*[A-Za-z]", "", seen.decode()).replace("\r", "\n")
    # Each bar draws when it starts; later draws are rate-limited, so only the starts are sure.
    assert re.search(r"reference continuous 8x8 \[ +\] 0/4096", text), text[:2000]
    assert re.search(r"frames +\[ +\] 0/8", text), text[:2000]
    for method in ("hard", "pcss"):
        assert re.search(rf"^{method}: 1 shadow maps, median [0-9.]+ ms \(min [0-9.]+, max [0-9.]+\), RMSE 0\.[0-9]+$", text, re.M), text[:2000]
