"""Penumbra from Python: soft shadows from area lights, rendered on the GPU (wgpu), with the
CPU ground truth, compare's metrics and studies as numpy arrays and dicts.

    import penumbra
    scene = penumbra.Scene.load("analytic-square", resolution=128)
    v, record = penumbra.Renderer(scene).render("adaptive:preset=balanced")
    ref = penumbra.reference(scene, samples=32)
    print(penumbra.metrics(v, ref)["rmse"])

docs/python.md is the guide.
"""

from collections.abc import Mapping

from ._penumbra import (
    GpuError,
    PenumbraError,
    Record,
    Reference,
    Renderer,
    Scene,
    __version__,
    compare,
    metrics,
    read_exr,
    reference,
)

__all__ = [
    "GpuError",
    "PenumbraError",
    "Record",
    "Reference",
    "Renderer",
    "Scene",
    "__version__",
    "compare",
    "metrics",
    "read_exr",
    "reference",
    "rows_to_frame",
]

# A run record reads as a dict does (built on first read); it is a Mapping for isinstance checks.
Mapping.register(Record)


def rows_to_frame(rows):
    """compare's rows as a pandas DataFrame, the nested ``metrics`` flattened to ``metrics.rmse``, ….

    Needs pandas (not a dependency of this package): raises ImportError naming it otherwise.
    """
    try:
        import pandas
    except ImportError as e:  # pragma: no cover - depends on the environment
        raise ImportError("penumbra.rows_to_frame needs pandas: pip install pandas") from e
    return pandas.json_normalize(rows)
