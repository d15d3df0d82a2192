#!/usr/bin/env python3
"""Judges a shadow's colour and depth in one compare_cycles.py output folder: over the
pixels of one object (the floor) that Cycles shadows, Chiaro's radiance against Cycles'
per channel, and each renderer's shadow relative to the same object lit.

    python3 scripts/cycles_shadow_colour.py DIR [--object NAME] [--shadow-below F]

DIR holds chiaro.exr, chiaro.instance.exr, cycles.exr and compare.json, as
scripts/compare_cycles.py leaves them. The object is named as compare.json names it
(default "floor"). Its lit level, per renderer and channel, is the median over its pixels
where Cycles' luminance is at least 0.9 of its median; its shadow is its pixels where
Cycles' luminance is below F (default 0.8) of that median, less those within two pixels
of another object (silhouettes) or of the lit level's edge (penumbrae, which the two
renderers blur differently). Each connected shadow region of at least --min-pixels
(default 10), left to right, is reported: its pixels; per channel its mean over the lit
level in each renderer (what the shadow lets through) and Chiaro / Cycles over it; the
median of Chiaro / Cycles luminance there and the share within 10%.
Runs under the bpy python (numpy, OpenEXR) like compare_cycles.py.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
from pathlib import Path
from typing import Any


def reexec_under_bpy() -> None:
    try:
        import numpy  # noqa: F401
        import OpenEXR  # type: ignore[import-not-found,import-untyped,unused-ignore]  # noqa: F401
    except ImportError:
        python = os.environ.get("CHIARO_BPY_PYTHON", "target/bpy-venv/bin/python")
        if Path(python).exists() and "CHIARO_SHADOW_COLOUR_REEXEC" not in os.environ:
            os.environ["CHIARO_SHADOW_COLOUR_REEXEC"] = "1"
            os.execv(python, [python, *sys.argv])
        sys.exit(f"error: needs numpy and OpenEXR (the bpy environment {python} has them)")


reexec_under_bpy()

import numpy as np  # noqa: E402
import OpenEXR  # type: ignore[import-not-found,import-untyped,unused-ignore]  # noqa: E402


def read_rgb(path: Path) -> Any:
    with OpenEXR.File(str(path)) as f:
        channels = f.channels()
        if "RGB" in channels:
            return np.asarray(channels["RGB"].pixels, dtype=np.float64)
        if "RGBA" in channels:
            return np.asarray(channels["RGBA"].pixels, dtype=np.float64)[..., :3]
        return np.stack([np.asarray(channels[c].pixels, dtype=np.float64) for c in "RGB"], -1)


def read_ids(path: Path) -> Any:
    """The instance AOV: one uint32 channel Y, the glTF node per pixel."""
    with OpenEXR.File(str(path)) as f:
        return np.asarray(f.channels()["Y"].pixels, dtype=np.uint32)


def grown(mask: Any, steps: int) -> Any:
    """`mask` grown by `steps` 4-neighbourhood steps."""
    out = mask.copy()
    for _ in range(steps):
        g = out.copy()
        g[1:, :] |= out[:-1, :]
        g[:-1, :] |= out[1:, :]
        g[:, 1:] |= out[:, :-1]
        g[:, :-1] |= out[:, 1:]
        out = g
    return out


def luminance(rgb: Any) -> Any:
    return rgb[..., 0] * 0.2126 + rgb[..., 1] * 0.7152 + rgb[..., 2] * 0.0722


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0] if __doc__ else None)
    ap.add_argument("dir", type=Path)
    ap.add_argument("--object", default="floor")
    ap.add_argument("--shadow-below", type=float, default=0.8)
    ap.add_argument("--min-pixels", type=int, default=10, help="smaller shadow regions are not reported")
    args = ap.parse_args()
    report = json.loads((args.dir / "compare.json").read_text())
    ids = [o["id"] for o in report["objects"] if o["name"] == args.object]
    if not ids:
        sys.exit(f"error: {args.dir / 'compare.json'} names no object {args.object!r}")
    chiaro = read_rgb(args.dir / "chiaro.exr")
    cycles = read_rgb(args.dir / "cycles.exr")
    instance = read_ids(args.dir / "chiaro.instance.exr")
    obj = instance == ids[0]
    y_cycles = luminance(cycles)
    median = np.median(y_cycles[obj])
    lit = obj & (y_cycles >= 0.9 * median)
    shadow = obj & (y_cycles < args.shadow_below * median)
    shadow &= ~grown(~obj, 2) & ~grown(lit, 2)
    if not shadow.any():
        sys.exit(f"error: no pixel of {args.object!r} is in Cycles' shadow")
    lit_chiaro = np.median(chiaro[lit], axis=0)
    lit_cycles = np.median(cycles[lit], axis=0)
    fmt = lambda v: "(" + ", ".join(f"{x:.3f}" for x in v) + ")"  # noqa: E731
    print(f"{args.dir}: {args.object!r} lit at Chiaro {fmt(lit_chiaro)}, Cycles {fmt(lit_cycles)} nits")
    for k, region in enumerate(shadows_left_to_right(shadow, args.min_pixels)):
        through_chiaro = chiaro[region].mean(axis=0) / lit_chiaro
        through_cycles = cycles[region].mean(axis=0) / lit_cycles
        # A full shadow (0 in Cycles) has no ratio: nan, as printed.
        cycles_mean = cycles[region].mean(axis=0)
        ratio = chiaro[region].mean(axis=0) / np.where(cycles_mean > 0, cycles_mean, np.nan)
        per_pixel = luminance(chiaro[region]) / np.maximum(luminance(cycles[region]), 1e-9)
        within = float(np.mean(np.abs(per_pixel - 1.0) <= 0.1))
        print(f"  shadow {k} ({int(region.sum())} pixels): let through, Chiaro {fmt(through_chiaro)}, "
              f"Cycles {fmt(through_cycles)}; Chiaro / Cycles {fmt(ratio)}, median luminance ratio "
              f"{np.median(per_pixel):.3f}, {100 * within:.0f}% within 10%")
    return 0


def shadows_left_to_right(shadow: Any, min_pixels: int) -> list[Any]:
    """The 4-connected regions of `shadow` of at least `min_pixels`, by their mean column."""
    height, width = shadow.shape
    label = np.full(shadow.shape, -1)
    regions: list[Any] = []
    for start in zip(*np.nonzero(shadow)):
        if label[start] >= 0:
            continue
        stack, pixels = [start], []
        label[start] = len(regions)
        while stack:
            y, x = stack.pop()
            pixels.append((y, x))
            for ny, nx in ((y - 1, x), (y + 1, x), (y, x - 1), (y, x + 1)):
                if 0 <= ny < height and 0 <= nx < width and shadow[ny, nx] and label[ny, nx] < 0:
                    label[ny, nx] = len(regions)
                    stack.append((ny, nx))
        mask = np.zeros(shadow.shape, dtype=bool)
        mask[tuple(np.array(pixels).T)] = True
        regions.append(mask)
    kept = [r for r in regions if r.sum() >= min_pixels]
    return sorted(kept, key=lambda r: float(np.nonzero(r)[1].mean()))


if __name__ == "__main__":
    sys.exit(main())
