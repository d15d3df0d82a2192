#!/usr/bin/env python3
"""Writes the area-light shadow scene for judging penumbrae against Blender Cycles: a
plank (0.8 x 0.04 x 3 m, its near edge at x = 0.4) 1 m above a grey floor, under an
EXT_lights_area strip (1 x 0.1 m) or disk 3 m above the origin, shining down; a camera low
on the lit side looking under the plank at its shadow's edge (x = 0.6 on the floor).

    python3 scripts/cycles_plank_scene.py OUT.gltf --light strip-across|strip-along|disk
        [--shadows pcss|none] [--nits 2000]

`strip-across` turns the strip's long side across the plank's edge (a 0.5 m penumbra on
the floor), `strip-along` along it (5 cm). `--shadows none` writes the same scene without
shadows: Chiaro's image of it, and Cycles' with `--unshadowed`, divide the shadowed ones
into visibility (the floor is rough and grey, so radiance is irradiance times a constant).
Standard library only; geometry helpers from cycles_scenes.py.
"""

from __future__ import annotations

import argparse
import base64
import json
import math
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from cycles_scenes import FLOOR_MATERIAL, Buffer, floor_quad, looking_along, normalize  # noqa: E402

PLANK_MIN = (0.4, 0.98, -1.5)
PLANK_MAX = (1.2, 1.02, 1.5)
LIGHT_HEIGHT_M = 3.0
EDGE_ON_FLOOR_X = 0.6


def box(lo, hi):
    """Positions, normals, UVs, tangents and counter-clockwise triangles of an axis-aligned box."""
    positions, normals, uvs, tangents, indices = [], [], [], [], []
    for axis in range(3):
        for sign in (-1.0, 1.0):
            n = [0.0, 0.0, 0.0]
            n[axis] = sign
            u_axis, v_axis = [(axis + 1) % 3, (axis + 2) % 3] if sign > 0 else [(axis + 2) % 3, (axis + 1) % 3]
            base = len(positions) // 3
            for du, dv in ((0, 0), (1, 0), (1, 1), (0, 1)):
                p = [0.0, 0.0, 0.0]
                p[axis] = hi[axis] if sign > 0 else lo[axis]
                p[u_axis] = hi[u_axis] if du else lo[u_axis]
                p[v_axis] = hi[v_axis] if dv else lo[v_axis]
                positions += p
                normals += n
                uvs += [float(du), float(dv)]
                t = [0.0, 0.0, 0.0, 1.0]
                t[u_axis] = 1.0
                tangents += t
            indices += [base, base + 1, base + 2, base, base + 2, base + 3]
    return positions, normals, uvs, tangents, indices


def build(light_kind: str, shadows: str, nits: float) -> dict:
    buf = Buffer()
    floor = buf.primitive(*floor_quad(3.0), material=0)
    plank = buf.primitive(*box(PLANK_MIN, PLANK_MAX), material=0)
    if light_kind == "disk":
        light = {"name": "disk", "type": "disk", "size": 0.5}
        along = [1.0, 0.0, 0.0]
    else:
        light = {"name": light_kind, "type": "rect", "size": 0.1, "rect": {"aspect": 10.0}}
        along = [1.0, 0.0, 0.0] if light_kind == "strip-across" else [0.0, 0.0, 1.0]
    light.update({"color": [1.0, 1.0, 1.0], "intensity": nits, "extras": {"shadows": shadows}})
    # Local -Z down, local X (the strip's long side) along `along`: the rotation whose
    # columns are X = along, Y = Z x X with Z = up.
    x = along
    z = [0.0, 1.0, 0.0]
    y = [z[1] * x[2] - z[2] * x[1], z[2] * x[0] - z[0] * x[2], z[0] * x[1] - z[1] * x[0]]
    rotation = _quat(x, y, z)
    # Low and to the lit side, looking under the plank at the penumbra.
    eye = [-1.0, 1.5, 0.0]
    nodes = [
        {"name": "floor", "mesh": 0},
        {"name": "plank", "mesh": 1},
        {"name": light["name"], "translation": [0.0, LIGHT_HEIGHT_M, 0.0], "rotation": rotation,
         "extensions": {"EXT_lights_area": {"light": 0}}},
        {"name": "camera", "camera": 0, "translation": eye,
         "rotation": looking_along(normalize([EDGE_ON_FLOOR_X - eye[0], -eye[1], 0.0]))},
    ]
    return {
        "asset": {"version": "2.0", "generator": "chiaro scripts/cycles_plank_scene.py"},
        "extensionsUsed": ["EXT_lights_area"],
        "extensions": {"EXT_lights_area": {"lights": [light]}},
        "scene": 0,
        "scenes": [{"nodes": list(range(len(nodes)))}],
        "nodes": nodes,
        "meshes": [{"name": "floor", "primitives": [floor]}, {"name": "plank", "primitives": [plank]}],
        "materials": [dict(FLOOR_MATERIAL)],
        "cameras": [{"type": "perspective", "perspective": {"yfov": math.radians(70.0), "aspectRatio": 1.0,
                                                            "znear": 0.05, "zfar": 50.0}}],
        "buffers": [{"byteLength": len(buf.data),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(bytes(buf.data)).decode()}],
        "bufferViews": buf.views,
        "accessors": buf.accessors,
    }


def _quat(x, y, z):
    """The unit quaternion (x, y, z, w) of the rotation whose columns are x, y, z."""
    m00, m11, m22 = x[0], y[1], z[2]
    trace = m00 + m11 + m22
    if trace > 0:
        s = math.sqrt(trace + 1.0) * 2
        return [(y[2] - z[1]) / s, (z[0] - x[2]) / s, (x[1] - y[0]) / s, 0.25 * s]
    if m00 > m11 and m00 > m22:
        s = math.sqrt(1.0 + m00 - m11 - m22) * 2
        return [0.25 * s, (y[0] + x[1]) / s, (z[0] + x[2]) / s, (y[2] - z[1]) / s]
    if m11 > m22:
        s = math.sqrt(1.0 + m11 - m00 - m22) * 2
        return [(y[0] + x[1]) / s, 0.25 * s, (z[1] + y[2]) / s, (z[0] - x[2]) / s]
    s = math.sqrt(1.0 + m22 - m00 - m11) * 2
    return [(z[0] + x[2]) / s, (z[1] + y[2]) / s, 0.25 * s, (x[1] - y[0]) / s]


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("out")
    ap.add_argument("--light", choices=("strip-across", "strip-along", "disk"), required=True)
    ap.add_argument("--shadows", choices=("pcss", "none"), default="pcss")
    ap.add_argument("--nits", type=float, default=2000.0)
    args = ap.parse_args(argv)
    Path(args.out).write_text(json.dumps(build(args.light, args.shadows, args.nits)))
    print(f"cycles_plank_scene: wrote {args.out} ({args.light}, shadows {args.shadows})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
