"""Signatures of the extension module `penumbra._penumbra` (docs/python.md is the guide).

The docstrings here are the extension's own (`help()` shows the same text); a test keeps them equal.
"""

from collections.abc import Callable, Iterator, Mapping, Sequence
from os import PathLike
from typing import Any, Optional, Union

import numpy as np
from numpy.typing import ArrayLike, NDArray

__version__: str

Progress = Union[None, bool, Callable[[str], object]]

class PenumbraError(ValueError):
    """Bad input: a scene, setting, method, parameter or file that penumbra refuses; the message is the command line's `error:` line."""

class GpuError(RuntimeError):
    """The GPU failed: no adapter matches, the device was lost or ran out of memory, a kernel did not validate, a counter overflowed."""

class Scene:
    """A checked scene: meshes, camera, area light and render settings."""

    @staticmethod
    def load(name_or_path: str, **settings: Union[str, int, float, bool]) -> Scene:
        """A built-in scene by name or a scene TOML file, with render settings.

        Args:
            name_or_path: a built-in scene (`penumbra scenes` lists them) or the path of a scene TOML file.
            **settings: render settings by the keys of `penumbra render --set`: `resolution=128`,
                `shadow_map_size=1024`, `cull="none"`, `ambient=0.1`, ... (`True` is `true`).

        Returns:
            The scene, checked as the command line checks it.

        Raises:
            PenumbraError: no such scene, a malformed file, a missing mesh, an unknown setting or a
                value it refuses (named as its keyword: `cull='sideways'`).
        """

    @staticmethod
    def from_meshes(
        meshes: Sequence[Union[tuple[ArrayLike, ArrayLike], tuple[ArrayLike, ArrayLike, Sequence[float]]]],
        camera: Mapping[str, Any],
        light: Mapping[str, Any],
        **settings: Union[str, int, float, bool],
    ) -> Scene:
        """A scene from meshes in memory, checked as a scene file is.

        Args:
            meshes: `(positions, indices)` or `(positions, indices, albedo)` per mesh: positions
                float (N, 3), indices int (M, 3) or (3M,), counter-clockwise seen from the front,
                albedo three floats (default 0.8 grey).
            camera: `eye`, `target`, `fov_y_deg` and optionally `up` (three floats each).
            light: the scene file's `[light]` table: a rectangle `{center, edge_u, edge_v}` or any
                kind of docs/lights.md (`{"kind": "disk", "center": ..., "normal": ..., "radius": ...}`).
            **settings: render settings, as for `Scene.load`.

        Returns:
            The scene; its errors name `embedded scene`.

        Raises:
            PenumbraError: a malformed mesh, camera, light or setting.
        """

    @property
    def name(self) -> str: ...
    @property
    def origin(self) -> str:
        """The file or `builtin:NAME` every error names."""
    @property
    def width(self) -> int: ...
    @property
    def height(self) -> int: ...
    @property
    def triangles(self) -> int: ...

class Record(Mapping[str, Any]):
    """The run record of one frame: run.json's content, read as a dict is."""

    def __getitem__(self, key: str) -> Any: ...
    def __iter__(self) -> Iterator[str]: ...
    def __len__(self) -> int: ...
    def to_dict(self) -> dict[str, Any]:
        """The record as a new plain dict, its own copy down to the nested values."""

class Renderer:
    """Renders methods on one scene, each built once and kept: repeated renders reuse its pipelines and buffers.

    Args:
        scene: the scene to render.
        adapter: a GPU adapter's name or part of one, as `penumbra --adapter` takes it; `None`
            picks as the command line does (`WGPU_ADAPTER_NAME`, else the best adapter).
        reuse: each method keeps its shadow maps between `render` calls, which then rasterize
            only what changed (nothing, on one scene; V is the same bit for bit; docs/reuse.md).

    Raises:
        GpuError: no adapter matches, or none is usable.
        PenumbraError: `WGPU_BACKEND` names no backend.
    """

    def __init__(self, scene: Scene, adapter: Optional[str] = None, reuse: bool = True) -> None: ...
    def render(self, method: str, **params: Union[str, int, float, bool]) -> tuple[NDArray[np.float32], Record]:
        """Renders one frame of `method`.

        Args:
            method: a method spec as `penumbra render --method` takes it (`"pcss"`,
                `"adaptive:preset=balanced"`, `"regular:n=5,layout=centred"`).
            **params: the method's parameters, as `--param key=value` (`p_m=10`, `scope="local"`).

        Returns:
            `(V, record)`: V, the visibility, float32 of shape (height, width), top row first,
            in [0, 1] on geometry and NaN on the background; record, run.json's content.

        Raises:
            PenumbraError: an unknown method or parameter, a value it refuses, a light the method
                cannot take, sizes past the device's limits.
            GpuError: the device failed.
        """

    def certify(self, method: str, pixels: int = 2048, delta: float = 0.05, **params: Union[str, int, float, bool]) -> tuple[NDArray[np.float32], Record]:
        """Renders one frame of `method` and certifies its error (docs/certify.md).

        Args:
            method: a method spec, as for `render`.
            pixels: how many pixels are drawn and traced exactly by the reference's integrator.
            delta: the bound holds with probability at least 1 − `delta`.
            **params: the method's parameters, as for `render`.

        Returns:
            `(V, record)` as `render`; the record's `certify` holds the one-sided bound on the
            frame's RMSE (`bound`), the drawn pixels' RMSE and the tracing time.

        Raises:
            PenumbraError: as for `render`; `pixels` or `delta` out of range, or a scene the
                exact tracer cannot take.
            GpuError: the device failed.
        """

    def pictures(self, method: str, **params: Union[str, int, float, bool]) -> dict[str, NDArray[Any]]:
        """Renders one frame with the method's decision pictures on.

        Args:
            method: a method spec, as for `render`.
            **params: the method's parameters, as for `render`.

        Returns:
            The pictures by name, uint8 of shape (height, width, 3): adaptive's `comparison_map`,
            `low_quality` and `light_quadtree`, `samples_per_pixel` with `scope=local`; and
            `error_bound`, float32 (height, width), NaN on the background, where the method
            estimates its error.

        Raises:
            PenumbraError: as for `render`.
            GpuError: the device failed.
        """

    def _rust_frame_times(self, method: str, frames: int, **params: Union[str, int, float, bool]) -> list[float]: ...
    @property
    def adapter(self) -> str:
        """The adapter's name."""
    @property
    def methods(self) -> list[str]:
        """Methods built so far (their labels); each keeps its pipelines and buffers."""

class Reference:
    """The reference of one scene: V as an array (`numpy.asarray(ref)`, `ref.values`), and what `metrics` judges against."""

    @property
    def values(self) -> NDArray[np.float32]:
        """V of the reference, float32 of shape (height, width), NaN on the background."""
    def __array__(self, dtype: Any = None, copy: Optional[bool] = None) -> NDArray[Any]: ...
    @property
    def shape(self) -> tuple[int, int]: ...
    @property
    def mode(self) -> str:
        """The mode's label, as in run records (`continuous 32x32`)."""
    @property
    def cache_file(self) -> Optional[str]:
        """The cache file it was read from or written to."""
    @property
    def seconds(self) -> Optional[float]:
        """Tracing seconds; `None` when it came from the cache."""
    @property
    def geometry_pixels(self) -> int: ...

def reference(
    scene: Scene,
    samples: int = 32,
    mode: str = "continuous",
    no_cache: bool = False,
    adapter: Optional[str] = None,
    progress: Progress = None,
) -> Reference:
    """The ground truth of `scene`, traced on the CPU or read from the cache `penumbra reference` fills.

    Args:
        scene: the scene.
        samples: `continuous`: samples × samples stratified points per pixel (1..=256).
        mode: `continuous`, `lattice` (the 289 lattice points) or `point[:S,T]` (one light point).
        no_cache: trace without the cache: nothing read or stored.
        adapter: the GPU adapter for the G-buffer, as for `Renderer`.
        progress: `None`: a line on a terminal's stderr, or in a Jupyter cell; `True`: on Python's
            `sys.stderr`; `False`: nothing; a callable: called with each line.

    Returns:
        The reference: V as float32 (height, width), NaN on the background.

    Raises:
        PenumbraError: a bad mode or sample count.
        GpuError: the device failed.
    """

def metrics(v: ArrayLike, reference: Reference) -> dict[str, Any]:
    """The figures `penumbra compare` reports for V against the reference, over its geometry pixels.

    Args:
        v: V, float of shape (height, width) as `Renderer.render` returns it (background ignored).
        reference: the reference of the same scene.

    Returns:
        `rmse`, `mae`, `max_abs`, `psnr` (None when identical), `ssim`, `flip_mean`, `flip_p95`,
        `flip_p99`, `penumbra_rmse`, `bad_pixel_share`, `nan_count`, `pixels`, ... as floats and ints.

    Raises:
        PenumbraError: V's shape is not the reference's.
    """

def compare(
    scene: Scene,
    methods: Union[str, Sequence[str]],
    repeats: int = 3,
    samples: int = 32,
    reference: str = "continuous",
    no_cache: bool = False,
    adapter: Optional[str] = None,
    progress: Progress = None,
) -> list[dict[str, Any]]:
    """`penumbra compare` on `scene`; `penumbra.compare` wraps it (its rows are a `Rows`)."""

def read_exr(path: Union[str, PathLike[str]]) -> NDArray[np.float32]:
    """Channel 0 of an EXR as float32 of shape (height, width): V as `penumbra render` and `compare` write it (0 on the background).

    Args:
        path: a `visibility.exr` or `reference.exr`.

    Returns:
        V, float32 (height, width).

    Raises:
        PenumbraError: the file is missing or not an EXR.
    """
