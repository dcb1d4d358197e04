"""What the Python package adds to a warm render: the same 64² frames through `penumbra.Renderer.render`
(as a loop that wants V, and as one that also reads the run record), through the same kept renderer
with no Python in the loop (`Renderer._rust_frame_times`: the frame
call `ShadowRenderer::render` makes), and through the Rust API in its own process on its own device
(examples/frame_times.rs), in interleaved rounds.

    cargo build --release --example frame_times
    python scripts/python-overhead.py OUT_DIR [ROUNDS] [FRAMES]

Each round runs FRAMES timed frames per side (each side warmed up first; the Python renderer is
kept across rounds, as a notebook keeps it), alternating which side goes first. Writes
OUT_DIR/rows.csv (one row per frame) and prints the per-method medians, and the median and the
range over rounds of each round's ratio of medians.
"""

import csv
import pathlib
import statistics
import subprocess
import sys
import time

import penumbra

ROOT = pathlib.Path(__file__).resolve().parents[1]
SIZE = 64
METHODS = ["hard", "adaptive:preset=balanced"]


def rust_frames(method, frames):
    exe = ROOT / "target" / "release" / "examples" / "frame_times"
    out = subprocess.run([str(exe), method, str(SIZE), str(frames)], capture_output=True, text=True, check=True)
    return [float(line) for line in out.stdout.split()]


def python_frames(renderer, method, frames, read_record=False):
    times = []
    for _ in range(frames):
        start = time.perf_counter()
        _, record = renderer.render(method)
        if read_record:
            record["total_ms"]  # the first read builds the record's dict
        times.append((time.perf_counter() - start) * 1e3)
    return times


def main(out, rounds=7, frames=20):
    out = pathlib.Path(out)
    out.mkdir(parents=True, exist_ok=True)
    renderer = penumbra.Renderer(penumbra.Scene.load("analytic-square", resolution=SIZE))
    for m in METHODS:
        renderer.render(m)  # built, warmed up and kept
    rows = []
    for r in range(rounds):
        for m in METHODS:
            sides = [
                ("rust-process", lambda: rust_frames(m, frames)),
                ("rust-same-renderer", lambda: renderer._rust_frame_times(m, frames)),
                ("python", lambda: python_frames(renderer, m, frames)),
                ("python-record", lambda: python_frames(renderer, m, frames, read_record=True)),
            ]
            for side, run in sides if r % 2 == 0 else sides[::-1]:
                rows += [{"round": r, "method": m, "side": side, "frame": i, "ms": t} for i, t in enumerate(run())]
    with open(out / "rows.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=["round", "method", "side", "frame", "ms"])
        w.writeheader()
        w.writerows(rows)
    sides = ["rust-process", "rust-same-renderer", "python", "python-record"]
    print(f"{rounds}x{frames} frames at {SIZE}x{SIZE}: median ms of all frames; a python side over a Rust")
    print("side: the median [min, max] over rounds of each round's ratio of medians (its sides ran back to back)")
    for m in METHODS:
        def med(side, r=None):
            return statistics.median(x["ms"] for x in rows if x["method"] == m and x["side"] == side and r in (None, x["round"]))
        print(m + ": " + ", ".join(f"{s} {med(s):.3f}" for s in sides))
        for p in sides[2:]:
            for s in sides[:2]:
                ratios = [med(p, r) / med(s, r) for r in range(rounds)]
                print(f"  {p} / {s}: {statistics.median(ratios):.3f} [{min(ratios):.3f}, {max(ratios):.3f}]")


if __name__ == "__main__":
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    main(sys.argv[1], *(int(s) for s in sys.argv[2:4]))
