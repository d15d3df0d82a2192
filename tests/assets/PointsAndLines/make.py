"""Writes the PointsAndLines test scene, points-and-lines.gltf (one file, its buffer
embedded): a grey floor under a sun with a camera, and on it every point and line mode of
glTF 2.0: a box's twelve edges as LINES (red, no normals), a zigzag LINE_STRIP whose
vertex colours run green to blue (no normals), a circle as a LINE_LOOP on the glTF default
material (no normals), a grid of POINTS coloured by their vertices (no normals), and a
row of LINES with normals, lit by the sun. Run with python3; no dependencies."""

import base64
import json
import math
import struct

buffer = bytearray()
views, accessors = [], []


def add(values, fmt, kind, bounds=False):
    offset = len(buffer)
    for v in values:
        buffer.extend(struct.pack("<" + fmt * len(v), *v))
    views.append({"buffer": 0, "byteOffset": offset, "byteLength": len(buffer) - offset})
    accessor = {"bufferView": len(views) - 1, "componentType": 5126 if fmt == "f" else 5125,
                "count": len(values), "type": kind}
    if bounds:
        accessor["min"] = [min(v[k] for v in values) for k in range(3)]
        accessor["max"] = [max(v[k] for v in values) for k in range(3)]
    accessors.append(accessor)
    return len(accessors) - 1


h = 4.0
floor = {"attributes": {"POSITION": add([[-h, 0, -h], [h, 0, -h], [h, 0, h], [-h, 0, h]], "f", "VEC3", True),
                        "NORMAL": add([[0, 1, 0]] * 4, "f", "VEC3")},
         "indices": add([[0], [2], [1], [0], [3], [2]], "I", "SCALAR"), "material": 0}

corners = [[x, y, z] for x in (-0.6, 0.6) for y in (0.1, 1.3) for z in (-0.6, 0.6)]
edges = [(a, b) for a in range(8) for b in range(a + 1, 8)
         if sum(corners[a][k] != corners[b][k] for k in range(3)) == 1]
box_edges = {"attributes": {"POSITION": add(corners, "f", "VEC3", True)},
             "indices": add([[i] for e in edges for i in e], "I", "SCALAR"), "mode": 1, "material": 1}

zigzag = [[-3.0 + 0.5 * k, 0.4 + 0.3 * (k % 2), 2.5] for k in range(13)]
strip = {"attributes": {"POSITION": add(zigzag, "f", "VEC3", True),
                        "COLOR_0": add([[0.1, 1.0 - k / 12, k / 12] for k in range(13)], "f", "VEC3")},
         "mode": 3, "material": 2}

circle = [[2.5 * math.cos(a), 0.05, 2.5 * math.sin(a)] for a in (2 * math.pi * k / 48 for k in range(48))]
loop = {"attributes": {"POSITION": add(circle, "f", "VEC3", True)}, "mode": 2}

grid = [[-3.0 + 0.5 * i, 2.0, -3.0 + 0.5 * j] for i in range(5) for j in range(5)]
points = {"attributes": {"POSITION": add(grid, "f", "VEC3", True),
                         "COLOR_0": add([[1.0, 0.2 + 0.15 * (k % 5), 0.1, 1.0] for k in range(25)], "f", "VEC4")},
          "mode": 0, "material": 2}

rails = [[x, 0.02 + 0.0, z] for z in (-2.0, -2.4, -2.8) for x in (-3.5, 3.5)]
lit = {"attributes": {"POSITION": add([[x, 0.3, z] for x, _, z in rails], "f", "VEC3", True),
                      "NORMAL": add([[0, 1, 0]] * len(rails), "f", "VEC3")},
       "mode": 1, "material": 3}

doc = {
    "asset": {"version": "2.0", "generator": "tests/assets/PointsAndLines/make.py"},
    "extensionsUsed": ["KHR_lights_punctual"],
    "extensions": {"KHR_lights_punctual": {"lights": [
        {"name": "sun", "type": "directional", "intensity": 3.0}]}},
    "scene": 0,
    "scenes": [{"nodes": [0, 1, 2, 3]}],
    "nodes": [
        {"name": "floor", "mesh": 0},
        {"name": "wires", "mesh": 1},
        {"name": "sun", "rotation": [-0.4, 0.2, 0.1, 0.89],
         "extensions": {"KHR_lights_punctual": {"light": 0}}},
        {"name": "camera", "camera": 0, "translation": [0.0, 6.5, 7.5],
         "rotation": [-0.3007058, 0.0, 0.0, 0.953717]},
    ],
    "cameras": [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.1, "zfar": 50.0}}],
    "meshes": [{"name": "floor", "primitives": [floor]},
               {"name": "wires", "primitives": [box_edges, strip, loop, points, lit]}],
    "materials": [
        {"name": "floor", "pbrMetallicRoughness": {"baseColorFactor": [0.6, 0.6, 0.6, 1], "metallicFactor": 0}},
        {"name": "red", "pbrMetallicRoughness": {"baseColorFactor": [1, 0.1, 0.05, 1], "metallicFactor": 0}},
        {"name": "white", "pbrMetallicRoughness": {"metallicFactor": 0}},
        {"name": "grey", "pbrMetallicRoughness": {"baseColorFactor": [0.4, 0.4, 0.4, 1], "metallicFactor": 0}},
    ],
    "accessors": accessors,
    "bufferViews": views,
    "buffers": [{"byteLength": len(buffer),
                 "uri": "data:application/octet-stream;base64," + base64.b64encode(bytes(buffer)).decode()}],
}
with open("points-and-lines.gltf", "w") as f:
    json.dump(doc, f, indent=1)
