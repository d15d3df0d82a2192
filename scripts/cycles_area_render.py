#!/usr/bin/env python3
"""Renders a glTF scene with Blender Cycles as ../shared/peers/cycles/cycles_render.py
does, with the scene's EXT_lights_area lights added as Blender area lights (Blender's
glTF importer does not read the extension). Same arguments as cycles_render.py:

    BPY_PYTHON scripts/cycles_area_render.py SCENE.gltf OUT.exr --width W --height H ...

compare_cycles.py runs it with `--cycles-script scripts/cycles_area_render.py`. The
script it wraps is $CHIARO_CYCLES_RENDER, else ../shared/peers/cycles/cycles_render.py
beside the repository.

Each light becomes a Blender area light at its node's world transform (glTF's Y up made
Blender's Z up), shaped as a rectangle (`size` x `rect.aspect` along local X, `size` along
local Y) or a disk (`size` across), times the node's largest scale, emitting towards its
local -Z with a spread of 180 degrees: Lambertian, as the extension says. Its power is
pi x area x nits / 683 W (cycles_render.py multiplies the render by 683 lm/W), which
reproduces Lambert's polygon formula to 0.1% (the peers' README). The light itself is
hidden from the camera (Chiaro draws no surface for it) but seen in reflections, as
Chiaro's LTC shading sees it. `extras.shadows = "none"` turns its shadows off.
"""

from __future__ import annotations

import importlib.util
import json
import math
import os
import struct
import sys
from pathlib import Path

import numpy as np

WATTS_TO_LUMENS = 683.0
EXTENSION = "EXT_lights_area"


def wrapped_script() -> Path:
    explicit = os.environ.get("CHIARO_CYCLES_RENDER")
    if explicit:
        return Path(explicit)
    return Path(__file__).resolve().parents[2] / "shared" / "peers" / "cycles" / "cycles_render.py"


def read_gltf(path: str) -> dict:
    data = Path(path).read_bytes()
    if data[:4] == b"glTF":
        length, kind = struct.unpack_from("<II", data, 12)
        if kind != 0x4E4F534A:
            raise SystemExit(f"cycles_area_render: {path}: the first GLB chunk is not JSON")
        return json.loads(data[20:20 + length])
    return json.loads(data)


def local_matrix(node: dict) -> np.ndarray:
    if "matrix" in node:
        return np.array(node["matrix"], dtype=np.float64).reshape(4, 4).T
    x, y, z, w = node.get("rotation", [0.0, 0.0, 0.0, 1.0])
    rotation = np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
    ])
    m = np.eye(4)
    m[:3, :3] = rotation * np.array(node.get("scale", [1.0, 1.0, 1.0]))
    m[:3, 3] = node.get("translation", [0.0, 0.0, 0.0])
    return m


def world_matrices(doc: dict) -> dict[int, np.ndarray]:
    """World transforms of the default scene's nodes, by node index."""
    nodes = doc.get("nodes", [])
    scenes = doc.get("scenes", [])
    roots = scenes[doc.get("scene", 0)]["nodes"] if scenes else range(len(nodes))
    out: dict[int, np.ndarray] = {}
    stack = [(int(i), np.eye(4)) for i in roots]
    while stack:
        index, parent = stack.pop()
        world = parent @ local_matrix(nodes[index])
        out[index] = world
        stack.extend((int(c), world) for c in nodes[index].get("children", []))
    return out


def area_lights(doc: dict) -> list[tuple[dict, np.ndarray]]:
    """(light, world matrix) for each node of the scene carrying an EXT_lights_area light."""
    lights = doc.get("extensions", {}).get(EXTENSION, {}).get("lights", [])
    placed = []
    for index, world in world_matrices(doc).items():
        reference = doc["nodes"][index].get("extensions", {}).get(EXTENSION)
        if reference is not None:
            placed.append((lights[reference["light"]], world))
    return placed


def add_area_lights(scene_path: str) -> None:
    import bpy
    import mathutils

    # glTF (x, y, z) is Blender (x, -z, y).
    to_blender = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]])
    for k, (light, world) in enumerate(area_lights(read_gltf(scene_path))):
        axes = world[:3, :3]
        lengths = np.linalg.norm(axes, axis=0)
        scale = float(lengths.max())
        rotation = to_blender @ (axes / lengths)
        matrix = np.eye(4)
        matrix[:3, :3] = rotation
        matrix[:3, 3] = to_blender @ world[:3, 3]
        size = float(light.get("size", 1.0)) * scale
        data = bpy.data.lights.new(name=light.get("name", f"area {k}"), type="AREA")
        if light.get("type") == "disk":
            data.shape = "DISK"
            data.size = size
            area = math.pi * size * size / 4.0
        else:
            width = size * float(light.get("rect", {}).get("aspect", 1.0))
            data.shape = "RECTANGLE"
            data.size, data.size_y = width, size
            area = width * size
        nits = float(light.get("intensity", 1000.0))
        data.color = light.get("color", [1.0, 1.0, 1.0])
        data.energy = math.pi * area * nits / WATTS_TO_LUMENS
        data.spread = math.pi
        data.use_shadow = light.get("extras", {}).get("shadows", "pcss") != "none"
        obj = bpy.data.objects.new(data.name, data)
        bpy.context.scene.collection.objects.link(obj)
        obj.matrix_world = mathutils.Matrix(matrix.tolist())
        obj.visible_camera = False
        print(f"cycles_area_render: {data.shape.lower()} light '{data.name}' {area:.4g} m^2, {nits:g} nits, "
              f"{data.energy:.4g} W")


def main() -> None:
    path = wrapped_script()
    if not path.is_file():
        raise SystemExit(f"cycles_area_render: {path}: no cycles_render.py there (set CHIARO_CYCLES_RENDER)")
    spec = importlib.util.spec_from_file_location("cycles_render", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    scale_emission = module.scale_emission

    # cycles_render.main scales emission once the scene is imported and before it renders:
    # the lights are added there.
    def scale_emission_and_add_area_lights(factor):
        scale_emission(factor)
        add_area_lights(sys.argv[1])

    module.scale_emission = scale_emission_and_add_area_lights
    module.main()


if __name__ == "__main__":
    main()
