"""Two methods on one scene: V and the error map of each against the reference, and the metrics.

    python python/examples/two_methods.py OUT_DIR [SCENE] [SIZE]

Writes OUT_DIR/two_methods.png (V of each method and the reference) and OUT_DIR/error_maps.png
(V − reference, red where too bright), background (NaN) in slate blue, with matplotlib's Agg backend,
prints the metrics of each, and compare's rows as a pandas DataFrame where pandas is installed. It is
typed: `mypy --strict python/examples/two_methods.py` checks it against the package's stubs.
"""

import importlib.util
import pathlib
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.colors import Colormap  # noqa: E402
from numpy.typing import NDArray  # noqa: E402

import penumbra  # noqa: E402

METHODS = ["pcss", "adaptive:preset=balanced"]
BACKGROUND = "#5b6b7f"  # NaN: pixels no mesh covers


def colormap(name: str) -> Colormap:
    cmap = matplotlib.colormaps[name].copy()
    cmap.set_bad(BACKGROUND)
    return cmap


def main(out_dir: str, scene_name: str = "analytic-square", size: int = 128) -> None:
    out = pathlib.Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    scene = penumbra.Scene.load(scene_name, resolution=size)
    renderer = penumbra.Renderer(scene)
    reference = penumbra.reference(scene, samples=32)
    ref: NDArray[np.float32] = reference.values
    results: dict[str, NDArray[np.float32]] = {m: renderer.render(m)[0] for m in METHODS}

    fig, axes = plt.subplots(1, len(METHODS) + 1, figsize=(4 * (len(METHODS) + 1), 4))
    for ax, (title, v) in zip(axes, [*results.items(), (f"reference ({reference.mode})", ref)]):
        ax.imshow(v, cmap=colormap("gray"), vmin=0, vmax=1)
        ax.set_title(title, fontsize=9)
        ax.axis("off")
    fig.tight_layout()
    fig.savefig(out / "two_methods.png", dpi=100)

    fig, axes = plt.subplots(1, len(METHODS), figsize=(4.6 * len(METHODS), 4))
    for ax, (method, v) in zip(axes, results.items()):
        shown = ax.imshow(v - ref, cmap=colormap("RdBu_r"), vmin=-0.25, vmax=0.25)
        ax.set_title(f"{method}: V − reference", fontsize=9)
        ax.axis("off")
        fig.colorbar(shown, ax=ax, fraction=0.046)
    fig.tight_layout()
    fig.savefig(out / "error_maps.png", dpi=100)

    print(f"{scene.name} at {size}x{size} on {renderer.adapter}, reference {reference.mode}")
    print(f"{'method':<28} {'RMSE':>8} {'MAE':>8} {'max':>8} {'SSIM':>7} {'FLIP':>7}")
    for method, v in results.items():
        m = penumbra.metrics(v, reference)
        print(f"{method:<28} {m['rmse']:8.4f} {m['mae']:8.4f} {m['max_abs']:8.4f} {m['ssim']:7.4f} {m['flip_mean']:7.4f}")
    print(f"wrote {out / 'two_methods.png'} and {out / 'error_maps.png'}")

    # compare times each method after a warm-up frame and judges it: its rows go straight into pandas.
    rows = penumbra.compare(scene, METHODS, repeats=1, progress=False)
    if importlib.util.find_spec("pandas") is None:
        print("compare:", [(r["label"], r["metrics"]["rmse"]) for r in rows], "(pip install pandas for a DataFrame)")
        return
    frame = rows.to_frame()
    print(frame[["label", "maps", "frame_ms", "rmse", "metrics.flip_mean"]].to_string(index=False))


if __name__ == "__main__":
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    scene_name = sys.argv[2] if len(sys.argv) > 2 else "analytic-square"
    main(sys.argv[1], scene_name, int(sys.argv[3]) if len(sys.argv) > 3 else 128)
