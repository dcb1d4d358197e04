"""What a certified error costs against the whole reference (docs/certify.md): per screen, the
full reference traced by the CPU tracer and by ``truth_trace`` on the GPU, and one certified
frame's pixels (``render --certify K``), each from the binary's own records.

A row's ``pixels_over_reference`` is the certified frame's pixel time over the CPU tracer's whole
reference, and ``rays_over_reference`` its rays over the reference's: the share of the truth a
certificate pays for.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from . import binary as bin_
from .rows import Row

HEADER = ["scene", "width", "height", "method", "pixels", "reference_cpu_s", "reference_cpu_rays", "reference_cpu_rays_per_s",
          "reference_gpu_s", "reference_gpu_rays_per_s", "certify_pixels_ms", "certify_trace_ms", "certify_rays", "bound", "rmse_sampled",
          "pixels_over_reference", "rays_over_reference", "adapter", "version"]


def cost_row(binary: str, scene: str, size: tuple[int, int], method: str, pixels: int, out: Path, gpu_reference: bool = True) -> list[object]:
    """One screen's row: the reference by each tracer (``--no-cache``), and a certified frame.

    Args:
        binary: The binary.
        scene: A scene name or file.
        size: (width, height).
        method: The method whose frame is certified.
        pixels: K.
        out: A scratch folder for the runs.
        gpu_reference: Whether to trace the whole reference on the GPU too (a software GPU
            takes long at large screens).

    Returns:
        A row under :data:`HEADER`.

    Raises:
        RuntimeError: A run failed; its last line says why.
    """
    settings = {"width": size[0], "height": size[1]}
    label = f"{scene}-{size[0]}x{size[1]}"

    def done(r: bin_.Run) -> bin_.Run:
        if not r.ok:
            raise RuntimeError(f"{label}: {r.last_line()}")
        return r

    def reference(tracer: str) -> Row:
        r = done(bin_.run(binary, ["reference", "--scene", scene, *bin_.sets(settings), "--no-cache", "--tracer", tracer], out / f"{label}-ref-{tracer}"))
        return r.run_json("reference.json")

    cpu = reference("cpu")
    gpu = reference("gpu") if gpu_reference else None
    r = done(bin_.run(binary, ["render", "--scene", scene, *bin_.sets(settings), "--method", method, "--certify", str(pixels)], out / f"{label}-certify"))
    run = r.run_json()
    pixels_ms = run.number("certify.pixels_ms")
    rays = run.integer("certify.trace.rays")
    return [
        scene, size[0], size[1], method, pixels,
        cpu.number("trace.seconds"), cpu.integer("trace.rays"), cpu.number("trace.rays_per_s"),
        gpu.number("trace.seconds") if gpu else "", gpu.number("trace.rays_per_s") if gpu else "",
        pixels_ms, run.number("certify.trace.ms"), rays, run.number("certify.bound"), run.number("certify.sampled_rmse"),
        pixels_ms / 1e3 / cpu.number("trace.seconds"), rays / cpu.integer("trace.rays"),
        run.text("adapter.name"), run.text("version.git"),
    ]


def cost_rows(binary: str, scene: str, sizes: Sequence[tuple[int, int]], method: str, pixels: int, out: Path, gpu_up_to: int) -> list[list[object]]:
    """:func:`cost_row` per screen; the GPU traces the whole reference up to ``gpu_up_to`` pixels."""
    return [cost_row(binary, scene, s, method, pixels, out, gpu_reference=s[0] * s[1] <= gpu_up_to) for s in sizes]
