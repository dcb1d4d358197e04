"""Shared fixtures: the lab binary built from the same tree, a scratch folder, the tiny scene."""

import os
import pathlib
import subprocess

import pytest

import penumbra

ROOT = pathlib.Path(__file__).resolve().parents[2]
SIZE = 64
SCENE = "analytic-square"


def binary():
    """The `penumbra` binary of this tree (PENUMBRA_BIN overrides): the tests compare against it."""
    path = pathlib.Path(os.environ.get("PENUMBRA_BIN", ROOT / "target" / "release" / "penumbra"))
    assert path.is_file(), f"{path}: build it first (cargo build --release -p penumbra-lab)"
    return path


def cli(*args, check=True):
    """Runs the binary; returns the finished process (stdout and stderr as text)."""
    env = dict(os.environ, PENUMBRA_NO_PROGRESS="1")
    p = subprocess.run([str(binary()), *args], capture_output=True, text=True, env=env)
    if check:
        assert p.returncode == 0, f"penumbra {' '.join(args)}: {p.stderr}"
    return p


def cli_error(*args):
    """The one `error:` line of a refused command, without its prefix."""
    p = cli(*args, check=False)
    assert p.returncode == 1, p.stderr
    lines = [line for line in p.stderr.splitlines() if line.startswith("error: ")]
    assert len(lines) == 1, p.stderr
    return lines[0][len("error: "):]


@pytest.fixture(scope="session")
def scene():
    return penumbra.Scene.load(SCENE, resolution=SIZE)


@pytest.fixture(scope="session")
def renderer(scene):
    return penumbra.Renderer(scene)
