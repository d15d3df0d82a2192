"""Writes boxes-nodes.gltf: one box mesh placed by 64 nodes (an 8 x 8 grid, each turned
and scaled its own way) on a floor, under a sun and a spot light, seen by a camera.
`gltf-transform instance boxes-nodes.gltf boxes-instanced.glb` turns it into the same
scene with one EXT_mesh_gpu_instancing node. Run with python3; no dependencies.
`python3 make_nodes.py SIDE OUT.gltf` writes a SIDE x SIDE grid instead (the benchmark's
10,000 boxes: SIDE 100), spaced to fit the same floor."""

import base64
import json
import math
import struct
import sys

SIDE = int(sys.argv[1]) if len(sys.argv) > 1 else 8
OUT = sys.argv[2] if len(sys.argv) > 2 else "boxes-nodes.gltf"
SPACING = 10.0 / SIDE


def box():
    positions, normals, indices = [], [], []
    for axis in range(3):
        for sign in (1.0, -1.0):
            n = [0.0, 0.0, 0.0]
            n[axis] = sign
            u, v = [a for a in range(3) if a != axis]
            base = len(positions)
            for du, dv in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
                p = [0.0, 0.0, 0.0]
                p[axis], p[u], p[v] = 0.5 * sign, 0.5 * du, 0.5 * dv
                positions.append(p)
                normals.append(n)
            quad = [0, 1, 2, 0, 2, 3] if sign > 0 else [0, 2, 1, 0, 3, 2]
            # Counter-clockwise seen from outside: the (u, v) frame's handedness decides.
            if (axis == 1) == (sign > 0):
                quad = [0, 2, 1, 0, 3, 2] if sign > 0 else [0, 1, 2, 0, 2, 3]
            indices += [base + i for i in quad]
    return positions, normals, indices


def floor(size):
    h = size / 2
    return [[-h, 0, -h], [h, 0, -h], [h, 0, h], [-h, 0, h]], [[0, 1, 0]] * 4, [0, 2, 1, 0, 3, 2]


def quat_y(angle):
    return [0.0, math.sin(angle / 2), 0.0, math.cos(angle / 2)]


buffer = bytearray()
views, accessors, meshes = [], [], []


def add(values, fmt, kind, target, bounds=False):
    offset = len(buffer)
    for v in values:
        buffer.extend(struct.pack("<" + fmt * len(v) if isinstance(v, list) else "<" + fmt, *(v if isinstance(v, list) else [v])))
    while len(buffer) % 4:
        buffer.append(0)
    views.append({"buffer": 0, "byteOffset": offset, "byteLength": len(buffer) - offset, "target": target})
    accessor = {"bufferView": len(views) - 1, "componentType": 5126 if fmt == "f" else 5125,
                "count": len(values), "type": kind}
    if bounds:
        accessor["min"] = [min(v[k] for v in values) for k in range(3)]
        accessor["max"] = [max(v[k] for v in values) for k in range(3)]
    accessors.append(accessor)
    return len(accessors) - 1


for name, (p, n, i), material in (("box", box(), 0), ("floor", floor(12.0), 1)):
    meshes.append({"name": name, "primitives": [{
        "attributes": {"POSITION": add(p, "f", "VEC3", 34962, True), "NORMAL": add(n, "f", "VEC3", 34962)},
        "indices": add(i, "I", "SCALAR", 34963), "material": material}]})

nodes = [{"name": "floor", "mesh": 1}]
for row in range(SIDE):
    for column in range(SIDE):
        k = row * SIDE + column
        size = SPACING / 1.25
        # Every box floats at least 2% of its size above the floor: a bottom edge lying in
        # the floor's plane makes depths tie exactly, and ties have no right winner.
        nodes.append({"name": f"box {k}", "mesh": 0,
                      "translation": [(column - (SIDE - 1) / 2) * SPACING, size * (0.52 + 0.0625 * (k % 3)),
                                      (row - (SIDE - 1) / 2) * SPACING],
                      "rotation": quat_y(0.3 * k), "scale": [size * (0.75 + 0.0625 * (k % 4)), size, size * 0.75]})
nodes.append({"name": "sun", "rotation": [-0.3535534, 0.3535534, 0.1464466, 0.8535534],
              "extensions": {"KHR_lights_punctual": {"light": 0}}})
nodes.append({"name": "spot", "translation": [0.0, 6.0, 0.0], "rotation": [-0.7071068, 0.0, 0.0, 0.7071068],
              "extensions": {"KHR_lights_punctual": {"light": 1}}})
nodes.append({"name": "camera", "translation": [0.0, 9.0, 11.0], "rotation": [-0.3535534, 0.0, 0.0, 0.9354143],
              "camera": 0})

doc = {
    "asset": {"version": "2.0", "generator": "Chiaro tests/assets/InstancedBoxes/make_nodes.py"},
    "extensionsUsed": ["KHR_lights_punctual"],
    "scene": 0,
    "scenes": [{"nodes": list(range(len(nodes)))}],
    "nodes": nodes,
    "meshes": meshes,
    "materials": [{"name": "box", "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.35, 0.2, 1.0], "metallicFactor": 0.0}},
                  {"name": "floor", "pbrMetallicRoughness": {"baseColorFactor": [0.7, 0.7, 0.7, 1.0], "metallicFactor": 0.0}}],
    "cameras": [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.1, "zfar": 100.0, "aspectRatio": 1.0}}],
    "extensions": {"KHR_lights_punctual": {"lights": [
        {"name": "sun", "type": "directional", "intensity": 3.0},
        {"name": "spot", "type": "spot", "intensity": 300.0, "range": 20.0,
         "spot": {"innerConeAngle": 0.5, "outerConeAngle": 0.7}}]}},
    "accessors": accessors,
    "bufferViews": views,
    "buffers": [{"byteLength": len(buffer),
                 "uri": "data:application/octet-stream;base64," + base64.b64encode(bytes(buffer)).decode()}],
}
with open(OUT, "w") as f:
    json.dump(doc, f, indent=1)
