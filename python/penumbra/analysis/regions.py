"""The per-region method's rows (docs/regions.md): its budget rows against the frontier, where
its frame's time goes, which term sets each group's map side, and the what-if plans read off
one frame (results/regions-frontier/, regions-texels/, frontier-h200-budget-regions/).
"""

from __future__ import annotations

import math
import statistics
import struct
import zlib
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import Any, Optional

from . import engine
from .frontier import Frontier, Summary, summarize, target_of
from .rows import PathLike, Row, Table

# --- summaries of a frontier's budget rows ----------------------------------------------------

BUDGET_ROWS_HEADER = ["scene", "setting", "maps", "rmse", "rmse_over_target", "median_ms", "cheapest_fixed_at_this_rmse", "its_rmse", "its_ms", "time_ratio",
                      "dominated"]


def budget_rows(frontier: Frontier) -> list[list[object]]:
    """Each budget row against the cheapest fixed setting at most as wrong, and whether a fixed
    setting is both strictly faster and at most as wrong (budget-rows.csv).

    Args:
        frontier: The frontier.

    Returns:
        Rows under :data:`BUDGET_ROWS_HEADER`.
    """
    out: list[list[object]] = []
    for s in summarize(frontier, strict=True):
        r, m = s.row, s.matched
        t = r.target
        assert t is not None
        out.append([r.scene, r.spec, r.maps, f"{r.rmse:.5f}", f"{r.rmse / t:.2f}", f"{r.frame_ms:.1f}", m.name if m else "none reaches it",
                    f"{m.rmse:.5f}" if m else "", f"{m.frame_ms:.1f}" if m else "", f"{r.frame_ms / m.frame_ms:.2f}" if m else "", "yes" if s.dominated else "no"])
    return out


SUMMARY_HEADER = ["scene", "spec", "target", "maps", "rmse", "rmse_over_target", "frame_ms", "dominated", "matched_fixed", "matched_ms", "time_over_matched",
                  "oracle", "oracle_ms", "time_over_oracle", "paired", "reported_met"]


def summary_rows(frontier: Frontier) -> list[list[object]]:
    """Each budget row with its matched setting and its oracle (time/oracle side by side where
    the frontier paired it), and whether a fixed setting is as fast and at most as wrong
    (summary.csv).

    Args:
        frontier: The frontier.

    Returns:
        Rows under :data:`SUMMARY_HEADER`.
    """
    out: list[list[object]] = []
    for s in summarize(frontier, strict=False):
        r, m, o = s.row, s.matched, s.oracle
        t = r.target
        assert t is not None
        met = r.budget.target_met if r.budget else ""
        out.append([r.scene, r.spec, t, r.maps, f"{r.rmse:.5f}", f"{r.rmse / t:.2f}", f"{r.frame_ms:.2f}", s.dominated,
                    m.name if m else "", f"{m.frame_ms:.2f}" if m else "", f"{r.frame_ms / m.frame_ms:.2f}" if m else "",
                    o.name if o else "", f"{o.frame_ms:.2f}" if o else "", f"{s.time_over_oracle:.2f}" if o and s.time_over_oracle is not None else "",
                    r.paired is not None, met])
    return out


def matched_windows(frontier: Frontier) -> list[tuple[Summary, int]]:
    """The ``regions`` rows with a fixed setting at most as wrong, and the map side to compare
    them at (the setting's), for a compare of each beside its match.

    Args:
        frontier: The frontier.

    Returns:
        (summary, map side) per row.
    """
    return [(s, s.matched.map_size) for s in summarize(frontier) if s.row.method == "regions" and s.matched is not None]


COMPARE_ROWS_HEADER = ["scene", "target", "map_size", "regions_ms", "regions_rmse", "regions_maps", "fixed", "fixed_ms", "fixed_rmse", "fixed_maps",
                       "time_ratio", "fixed_as_accurate"]


def compare_row(results: Table) -> list[object]:
    """One compare of ``regions`` beside the fixed setting it was matched with (compare-rows.csv).

    Args:
        results: The compare's results.jsonl.

    Returns:
        The row under :data:`COMPARE_ROWS_HEADER`.
    """
    r = next(x for x in results if x.text("method") == "regions")
    f = next(x for x in results if x.text("method") != "regions")
    t = target_of(r)
    assert t is not None
    return [r.text("scene"), f"{t:.3g}", r.integer("map_size"), f"{r.number('frame_ms'):.1f}", f"{r.number('rmse'):.5f}", r.integer("maps"),
            f.text("label"), f"{f.number('frame_ms'):.1f}", f"{f.number('rmse'):.5f}", f.integer("maps"),
            f"{r.number('frame_ms') / f.number('frame_ms'):.2f}", "yes" if f.number("rmse") <= r.number("rmse") else "no"]


# --- where the time goes ----------------------------------------------------------------------

WHERE_HEADER = ["scene", "setting", "maps", "map_sizes", "texels_written", "triangle_map_pairs", "syncs", "total_ms", "decision_ms", "decision_share", "raster_ms",
                "shadow_raster_ms", "cull_ms", "shade_ms"]


def where_row(run: Row) -> list[object]:
    """Where one frame's time goes (a render with stage timing): maps and their sides, texels
    written, (triangle, map) pairs rasterized, the decision's share, the raster's and shade's ms.

    Args:
        run: The render's run.json.

    Returns:
        The row under :data:`WHERE_HEADER`.
    """
    regions = run.text("method") == "regions"
    if regions:
        sizes = "/".join(str(c["map_size"]) for c in run.raw("method_record.classes"))
        texels, pairs = run.number("method_record.texels_written"), run.number("method_record.triangle_map_pairs")
    else:
        size = run.integer("shadow_map_size")
        sizes = str(size)
        texels = run.integer("shadow_maps") * size * size
        pairs = run.number("method_record.triangles_per_map_mean") * run.integer("shadow_maps")
    stage = run.raw("stages_ms") or {}
    return [run.text("scene"), run.text("label") + ("" if regions else f" @ {run.integer('shadow_map_size')}"), run.integer("shadow_maps"), sizes, int(texels),
            int(pairs), run.integer("syncs"), f"{run.number('total_ms'):.1f}", f"{run.number('frame_split_ms.decision'):.1f}", f"{run.number('decision_share'):.3f}",
            f"{run.number('frame_split_ms.raster'):.1f}", f"{stage.get('shadow_raster', 0):.1f}", f"{stage.get('cull', 0):.1f}", f"{run.number('frame_split_ms.shade'):.1f}"]


def prices_fit(rows: Table) -> list[str]:
    """The cost model's prices from culled centred grids (one frame each): a least-squares line of
    raster ms per map against texels per map (its intercept over its slope: c_m, in texels), and
    the median shade ms per map and geometry pixel over the slope (c_s), per scene and both.

    Args:
        rows: ``scene``, ``map_size``, ``maps``, ``raster_ms``, ``shade_ms``, ``geometry_pixels``.

    Returns:
        One line per scene, then ``both``.
    """
    out = []
    for scene in sorted({r.text("scene") for r in rows}) + ["both"]:
        sel = [r for r in rows if scene in ("both", r.text("scene"))]
        xs = [r.integer("map_size") ** 2 for r in sel]
        ys = [r.number("raster_ms") / r.integer("maps") for r in sel]
        mx, my = statistics.mean(xs), statistics.mean(ys)
        b = sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sum((x - mx) ** 2 for x in xs)
        a = my - b * mx
        s = statistics.median(r.number("shade_ms") / r.integer("maps") / r.integer("geometry_pixels") for r in sel)
        out.append(f"{scene}: per map {a:.2f} ms + {b * 1e6:.2f} ms per M texels; c_m = {a / b / 1e3:.0f} k texels; shade {s * 1e6:.0f} ns per test, c_s = {s / b:.0f} texels")
    return out


# --- what-if plans on one frame ---------------------------------------------------------------

PLAN_CLASSES_HEADER = ["scene", "plan", "classes n@side", "maps", "Mtexels", "pairs", "k_pixel_samples", "model_cost_Mtexel_eq"]
PLAN_DENSITY = 2.5
"""The texels per pixel footprint the what-if plans assume for every class."""


def plan_classes(run: Row) -> list[list[object]]:
    """What each idea would save on one ``regions`` frame (run.json's classes): maps, texels,
    (triangle, map) pairs and pixel-samples shaded, for the classes as they are, sides in steps of
    √2 (half-octave), classes merged where the cost model says the joined maps are cheaper, and one
    class for every tile. The cost model is the method's own (its default ``map_cost`` and
    ``sample_cost``, in texels); sides clamp to the frame's ``min_size`` and ``max_size``.

    Args:
        run: A ``regions`` render's run.json.

    Returns:
        Rows under :data:`PLAN_CLASSES_HEADER`.
    """
    prices = engine.method_params("regions")
    m0, rho = float(prices["map_cost"]), float(prices["sample_cost"])
    lo, hi = run.integer("params.min_size"), run.integer("params.max_size")
    classes: list[dict[str, Any]] = run.raw("method_record.classes")

    def side(extent: float, need: float, half: bool) -> int:
        want = extent * PLAN_DENSITY / need
        k = math.ceil((2 if half else 1) * math.log2(want)) / (2 if half else 1)
        return int(min(max(math.ceil(2 ** k / 16) * 16, lo), hi))

    def cost(cl: Sequence[Mapping[str, Any]], half: bool) -> float:
        return float(sum(c["n"] ** 2 * (m0 + side(c["extent"], c["texel_need"], half) ** 2 + rho * 64 * c["tiles"]) for c in cl))

    def merge(a: Mapping[str, Any], b: Mapping[str, Any]) -> dict[str, Any]:
        return dict(n=b["n"], tiles=a["tiles"] + b["tiles"], extent=max(a["extent"], b["extent"]), texel_need=min(a["texel_need"], b["texel_need"]))

    tri = sum(c["triangles_per_map_mean"] * c["maps"] for c in classes) / sum(c["maps"] for c in classes)
    scene = run.text("scene")

    def stats(name: str, cl: Sequence[Mapping[str, Any]], half: bool) -> list[object]:
        maps = sum(c["n"] ** 2 for c in cl)
        tex = sum(c["n"] ** 2 * side(c["extent"], c["texel_need"], half) ** 2 for c in cl)
        ps = sum(c["n"] ** 2 * 64 * c["tiles"] for c in cl)
        return [scene, name, "/".join(f"{c['n']}@{side(c['extent'], c['texel_need'], half)}" for c in cl), maps, f"{tex / 1e6:.1f}", int(maps * tri),
                f"{ps / 1e3:.0f}", f"{cost(cl, half) / 1e6:.0f}"]

    out = [stats("as-is", classes, False), stats("half-octave", classes, True)]
    m = [dict(c) for c in classes]
    i = 0
    while i + 1 < len(m):
        joined = merge(m[i], m[i + 1])
        if cost([joined], True) < cost(m[i:i + 2], True):
            m[i:i + 2] = [joined]
        else:
            i += 1
    out.append(stats("half-octave+merged", m, True))
    one: Mapping[str, Any] = classes[0]
    for c in classes[1:]:
        one = merge(one, c)
    out.append(stats("one-class", [one], True))
    return out


def read_png_rgb(path: PathLike) -> tuple[int, int, Callable[[int, int], tuple[int, int, int]]]:
    """An 8-bit RGB or RGBA PNG, decoded with the standard library alone.

    Args:
        path: The file.

    Returns:
        (width, height, pixel(x, y) -> (r, g, b)).

    Raises:
        ValueError: Not an 8-bit RGB or RGBA PNG.
    """
    data = Path(path).read_bytes()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        raise ValueError(f"{path}: not a PNG")
    pos, idat, w, h, ctype, depth = 8, b"", 0, 0, 0, 0
    while pos < len(data):
        n, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + n]
        pos += 12 + n
        if kind == b"IHDR":
            w, h, depth, ctype = struct.unpack(">IIBB", body[:10])
        elif kind == b"IDAT":
            idat += body
    if depth != 8 or ctype not in (2, 6):
        raise ValueError(f"{path}: colour type {ctype} at depth {depth}: not 8-bit RGB or RGBA")
    bpp = 3 if ctype == 2 else 4
    raw = zlib.decompress(idat)
    stride = w * bpp
    rows: list[bytearray] = []
    prev = bytearray(stride)
    for y in range(h):
        f = raw[y * (stride + 1)]
        line = bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - bpp] if i >= bpp else 0
            b = prev[i]
            c = prev[i - bpp] if i >= bpp else 0
            if f == 1:
                line[i] = (line[i] + a) & 255
            elif f == 2:
                line[i] = (line[i] + b) & 255
            elif f == 3:
                line[i] = (line[i] + (a + b) // 2) & 255
            elif f == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(line)
        prev = line
    return w, h, lambda x, y: (rows[y][x * bpp], rows[y][x * bpp + 1], rows[y][x * bpp + 2])


PLAN_WINDOWS_HEADER = ["scene", "n", "tiles", "groups", "union_box_tiles", "groups_box_tiles", "area_fraction", "side", "cost_one", "cost_split"]


def plan_windows(run: Row, samples_png: PathLike) -> list[list[object]]:
    """Tight windows: per class (one colour of region_samples.png, 8×8-pixel tiles), the screen
    box of all its tiles against its 4-connected groups' boxes, screen area standing in for the
    light-space window's. With the method's ``map_cost`` M0 a map and side S per class, splitting
    pays when k·M0 + f·S² < M0 + S² (k groups, f = the boxes' area over the union's).

    The picture draws tiles outside every class darker than any class and the classes from dark
    (fewest samples) to bright (most), so its colours, darkest first, are the background and then
    the classes in order of n.

    Args:
        run: The frame's run.json.
        samples_png: Its region_samples.png.

    Returns:
        Rows under :data:`PLAN_WINDOWS_HEADER`.

    Raises:
        ValueError: A picture whose colours are not one per class and the background.
    """
    m0 = float(engine.method_params("regions")["map_cost"])
    w, h, pixel = read_png_rgb(samples_png)
    classes = run.raw("method_record.classes")
    tiles: dict[tuple[int, int, int], set[tuple[int, int]]] = {}
    for ty in range(h // 8):
        for tx in range(w // 8):
            tiles.setdefault(pixel(tx * 8 + 4, ty * 8 + 4), set()).add((tx, ty))
    colours = sorted(tiles, key=lambda c: sum(c))
    if len(colours) != len(classes) + 1:
        raise ValueError(f"{samples_png}: {len(colours)} colours for {len(classes)} classes and the background")
    out: list[list[object]] = []
    for c, rec in zip(colours[1:], sorted(classes, key=lambda c: c["n"])):
        t = tiles[c]
        seen: set[tuple[int, int]] = set()
        boxes = []
        for s in t:
            if s in seen:
                continue
            stack, comp = [s], []
            seen.add(s)
            while stack:
                x, y = stack.pop()
                comp.append((x, y))
                for q in ((x + 1, y), (x - 1, y), (x, y + 1), (x, y - 1)):
                    if q in t and q not in seen:
                        seen.add(q)
                        stack.append(q)
            xs, ys = [p[0] for p in comp], [p[1] for p in comp]
            boxes.append((max(xs) - min(xs) + 1) * (max(ys) - min(ys) + 1))
        xs, ys = [p[0] for p in t], [p[1] for p in t]
        union = (max(xs) - min(xs) + 1) * (max(ys) - min(ys) + 1)
        f = min(sum(boxes) / union, 1.0)
        side = rec["map_size"]
        out.append([run.text("scene"), rec["n"], len(t), len(boxes), union, sum(boxes), f"{f:.2f}", side, f"{(m0 + side * side) / 1e6:.2f}",
                    f"{(len(boxes) * m0 + f * side * side) / 1e6:.2f}"])
    return out


# --- which term sets a group's side -----------------------------------------------------------

TEXEL_TERMS_HEADER = ["scene", "target", "group", "n", "classes_n", "tiles", "extent", "need", "density", "floor", "side_asked", "side_at_floor", "max_size", "side",
                      "set_by"]


def texel_terms(run: Row) -> list[list[object]]:
    """Which term sets each group's map side: the side is ``half_octave(extent · D / need)``
    within ``min_size..=max_size`` (``regions``' own law, :func:`penumbra.analysis.engine.half_octave`),
    where D is the frame's density (the maps' share of the target, never below the floor,
    :func:`penumbra.analysis.engine.density_floor`).

    Args:
        run: A ``regions:target=T`` render's run.json.

    Returns:
        One row per group under :data:`TEXEL_TERMS_HEADER`.
    """
    m = run.raw("method_record")
    floor = engine.density_floor(run.raw("render.bias"))
    t = target_of(run)
    assert t is not None
    lo, hi = run.integer("params.min_size"), run.integer("params.max_size")
    groups: dict[int, list[Mapping[str, Any]]] = {}
    for c in m["classes"]:
        groups.setdefault(c["group"], []).append(c)
    out: list[list[object]] = []
    for g, cs in sorted(groups.items()):
        need = min(c["texel_need"] for c in cs)
        ext, side = cs[0]["extent"], cs[0]["map_size"]
        asked, at_floor = engine.half_octave(ext * m["density"] / need), engine.half_octave(ext * floor / need)
        set_by = "max_size" if asked > hi else ("min_size" if asked < lo else ("maps' share" if m["density"] > floor else "floor"))
        out.append([run.text("scene"), f"{t:.3g}", g, cs[0]["n"], "/".join(str(c["decided_n"]) for c in cs), sum(c["tiles"] for c in cs), f"{ext:.3f}",
                    f"{need:.5f}", f"{m['density']:.2f}", f"{floor:.2f}", asked, at_floor, hi, side, set_by])
    return out


HALVED_HEADER = ["scene", "target", "sides", "maps", "rmse", "density", "groups"]


def groups_label(record: Mapping[str, Any]) -> str:
    """A frame's groups as ``n4@2048(2,3,4)``: each group's n, side and its classes' decided n."""
    groups: dict[int, tuple[int, int, list[int]]] = {}
    for c in record["classes"]:
        groups.setdefault(c["group"], (c["n"], c["map_size"], []))[2].append(c["decided_n"])
    return " ".join(f"n{n}@{z}({','.join(map(str, k))})" for n, z, k in groups.values())


MAP_ERROR_HEADER = ["scene", "target", "density_asked", "density_rendered", "predicted_map", "measured_map", "predicted_over_measured_m2"]


def map_error(halved: Table, run: Row) -> Optional[list[object]]:
    """The maps' error ``regions``' model predicts at the sides it rendered, against the one that
    halving every side adds: by the model's own law (m² ∝ texel) the measured m² at the decided
    sides is RMSE²(halved) − RMSE²(as decided). Frames with one group only.

    Args:
        halved: The halved rows (:data:`HALVED_HEADER`).
        run: The frame's run.json (``regions:target=T`` as decided).

    Returns:
        The row under :data:`MAP_ERROR_HEADER`, or None for a frame of several groups.
    """
    rmse = {(r.text("scene"), r.text("target"), r.text("sides")): r.number("rmse") for r in halved}
    m = run.raw("method_record")
    t = target_of(run)
    assert t is not None
    cs = m["classes"]
    if len({c["group"] for c in cs}) != 1:
        return None
    need = min(c["texel_need"] for c in cs)
    rendered = cs[0]["map_size"] * need / cs[0]["extent"]
    pred = m["predicted_map"] * math.sqrt(m["density"] / rendered)
    key = f"{t:.3g}"
    a, b = rmse[(run.text("scene"), key, "as decided")], rmse[(run.text("scene"), key, "halved")]
    meas = math.sqrt(max(b * b - a * a, 0.0))
    return [run.text("scene"), key, f"{m['density']:.2f}", f"{rendered:.2f}", f"{pred:.4f}", f"{meas:.4f}", f"{(pred / meas) ** 2:.1f}" if meas > 0 else "inf"]
