#!/usr/bin/env python3
"""Visibility in an area light's penumbra, Chiaro against Cycles: from two
compare_cycles.py output folders of the same scene, one shadowed and one unshadowed
(scripts/cycles_plank_scene.py writes both scenes), each renderer's visibility is its
shadowed luminance over its unshadowed luminance, pixel by pixel. Over the pixels whose
Cycles visibility lies strictly between 0.02 and 0.98 (the penumbra) it prints the mean
|Chiaro - Cycles| visibility and the share off by more than 0.1.

    target/bpy-venv/bin/python scripts/cycles_penumbra.py SHADOWED_DIR UNSHADOWED_DIR

Needs numpy and OpenEXR (the bpy environment has both).
"""

from __future__ import annotations

import sys

import numpy as np
import OpenEXR

PENUMBRA = (0.02, 0.98)
FAR_OFF = 0.1


def luminance(path: str) -> np.ndarray:
    with OpenEXR.File(path) as f:
        rgb = np.asarray(f.channels()["RGB"].pixels, dtype=np.float64)
    return 0.2126 * rgb[..., 0] + 0.7152 * rgb[..., 1] + 0.0722 * rgb[..., 2]


def main() -> int:
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    shadowed, unshadowed = sys.argv[1], sys.argv[2]
    visibility = {}
    for who in ("chiaro", "cycles"):
        lit = luminance(f"{unshadowed}/{who}.exr")
        visibility[who] = np.where(lit > 1e-6, luminance(f"{shadowed}/{who}.exr") / np.maximum(lit, 1e-6), np.nan)
    reference, rendered = visibility["cycles"], visibility["chiaro"]
    penumbra = np.isfinite(reference) & np.isfinite(rendered) & (reference > PENUMBRA[0]) & (reference < PENUMBRA[1])
    error = np.abs(rendered[penumbra] - reference[penumbra])
    print(f"{int(penumbra.sum())} penumbra pixels: mean |dv| {error.mean():.4f}, "
          f"|dv| > {FAR_OFF} on {100.0 * np.mean(error > FAR_OFF):.2f}%, "
          f"mean signed {np.mean(rendered[penumbra] - reference[penumbra]):+.4f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
