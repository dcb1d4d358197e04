"""Two methods on one scene: V and the error map of each against the reference, and the metrics.

    python python/examples/two_methods.py OUT_DIR [SCENE] [SIZE]

Writes OUT_DIR/two_methods.png (V of each method and the reference) and OUT_DIR/error_maps.png
(V − reference, red where too bright), background (NaN) in slate blue, with matplotlib's Agg backend, and prints compare's figures.
"""

import pathlib
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import penumbra  # noqa: E402

METHODS = ["pcss", "adaptive:preset=balanced"]
BACKGROUND = "#5b6b7f"  # NaN: pixels no mesh covers


def colormap(name):
    cmap = matplotlib.colormaps[name].copy()
    cmap.set_bad(BACKGROUND)
    return cmap


def main(out, scene_name="analytic-square", size=128):
    out = pathlib.Path(out)
    out.mkdir(parents=True, exist_ok=True)
    scene = penumbra.Scene.load(scene_name, resolution=size)
    renderer = penumbra.Renderer(scene)
    reference = penumbra.reference(scene, samples=32)
    ref = np.asarray(reference)
    results = {m: renderer.render(m)[0] for m in METHODS}

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


if __name__ == "__main__":
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    main(sys.argv[1], *sys.argv[2:3], *(int(s) for s in sys.argv[3:4]))
