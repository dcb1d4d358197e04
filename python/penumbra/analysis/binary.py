"""Runs the ``penumbra`` binary for the results' drivers: every render a driver needs goes
through the command line, as the README's commands do, so a driver measures what a user would.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import tempfile
from collections.abc import Iterator, Mapping, Sequence
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Optional, Union

from .rows import PathLike, Row, Table, read, read_json


def find(binary: Optional[PathLike] = None) -> str:
    """The binary to run: the argument, else ``$PENUMBRA``, else ``penumbra`` on the PATH.

    Args:
        binary: A path, or None.

    Returns:
        The path or command name.

    Raises:
        FileNotFoundError: Nothing found.
    """
    name = str(binary) if binary else os.environ.get("PENUMBRA", "penumbra")
    path = shutil.which(name) or (name if Path(name).is_file() else None)
    if path is None:
        raise FileNotFoundError(f"{name}: no penumbra binary (set PENUMBRA=path/to/penumbra)")
    return path


@dataclass(frozen=True)
class Run:
    """One finished command.

    Attributes:
        ok: Whether it exited 0.
        log: Its standard output and error together.
        out: Its output folder.
    """

    ok: bool
    log: str
    out: Path

    def last_line(self) -> str:
        """The log's last line (the one-line error of a refused command)."""
        lines = self.log.strip().splitlines()
        return lines[-1] if lines else ""

    def results(self) -> Table:
        """``results.jsonl`` of a compare."""
        return read(self.out / "results.jsonl")

    def run_json(self, pattern: str = "run.json") -> Row:
        """The one ``run.json`` under the output folder matching ``pattern`` (``images/auto*/run.json``).

        Raises:
            FileNotFoundError: None, or more than one, matches.
        """
        found = sorted(self.out.glob(pattern))
        if len(found) != 1:
            raise FileNotFoundError(f"{self.out}: {len(found)} files match {pattern}")
        return read_json(found[0])


def sets(settings: Mapping[str, Union[str, int, float]]) -> list[str]:
    """``--set k=v`` arguments."""
    out: list[str] = []
    for k, v in settings.items():
        out += ["--set", f"{k}={v}"]
    return out


def run(binary: str, args: Sequence[str], out: PathLike) -> Run:
    """Runs ``binary args… --out OUT`` without progress bars.

    Args:
        binary: The binary.
        args: The command and its arguments, ``--out`` left out.
        out: The output folder.

    Returns:
        The finished run.
    """
    env = dict(os.environ, PENUMBRA_NO_PROGRESS="1")
    p = subprocess.run([binary, *args, "--out", str(out)], capture_output=True, text=True, env=env)
    return Run(p.returncode == 0, p.stdout + p.stderr, Path(out))


def compare(binary: str, scene: str, methods: Sequence[str], out: PathLike, settings: Mapping[str, Union[str, int, float]], repeats: int) -> Run:
    """``penumbra compare`` of methods on one scene.

    Args:
        binary: The binary.
        scene: A scene name or file.
        methods: Method specs, rendered in one window, frames interleaved.
        out: The output folder.
        settings: ``--set`` pairs.
        repeats: Timed frames per method.

    Returns:
        The finished run.
    """
    args = ["compare", "--scene", scene, *sets(settings), "--repeats", str(repeats)]
    for m in methods:
        args += ["--methods", m]
    return run(binary, args, out)


def render(binary: str, scene: str, method: str, out: PathLike, settings: Mapping[str, Union[str, int, float]]) -> Run:
    """``penumbra render`` of one method on one scene.

    Args:
        binary: The binary.
        scene: A scene name or file.
        method: The method spec.
        out: The output folder.
        settings: ``--set`` pairs.

    Returns:
        The finished run.
    """
    return run(binary, ["render", "--scene", scene, *sets(settings), "--method", method], out)


@contextmanager
def scratch() -> Iterator[Path]:
    """A temporary folder, removed afterwards."""
    with tempfile.TemporaryDirectory(prefix="penumbra-analysis-") as d:
        yield Path(d)
