#!/usr/bin/env python3
"""Writes the light-scaling glTF scene: a 120 m floor under N point lights whose ranges
shrink as N grows, so that about three lights reach any point of the floor whatever N is.
The work per lit pixel is then the same at every N; what grows with N is only the cost
of finding the lights that reach each pixel.

    scripts/make_light_scaling_scene.py OUT.gltf --lights N [--seed S]

N is a square (64, 256, 1024, 4096 ...): the lights stand on a k x k grid, each jittered
within its cell, at a height of a quarter of their range. A light of range r gets
0.05 r^2 candela, so the floor looks alike at every N. No light casts shadows (Chiaro's
`"shadows": "none"`; no name contains "shadow", so the Bevy peer turns none on). The
camera stands 14 m above one edge, looking across the floor. Python's standard library
only.
"""

import argparse
import base64
import colorsys
import json
import math
import random
import struct

FLOOR_SIZE_M = 120.0
LIGHTS_OVER_A_POINT = 3.0


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("out")
    parser.add_argument("--lights", type=int, required=True)
    parser.add_argument("--seed", type=int, default=1)
    args = parser.parse_args()
    k = math.isqrt(args.lights)
    if k * k != args.lights or k < 1:
        parser.error("--lights must be a square number (64, 256, 1024, 4096)")
    rng = random.Random(args.seed)

    # A range covering LIGHTS_OVER_A_POINT lights per point: N pi r^2 = 3 A.
    area = FLOOR_SIZE_M * FLOOR_SIZE_M
    light_range = math.sqrt(LIGHTS_OVER_A_POINT * area / (math.pi * args.lights))
    cell = FLOOR_SIZE_M / k
    lights, nodes = [], []
    for i in range(args.lights):
        gx, gz = i % k, i // k
        x = -FLOOR_SIZE_M / 2 + (gx + 0.2 + 0.6 * rng.random()) * cell
        z = -FLOOR_SIZE_M / 2 + (gz + 0.2 + 0.6 * rng.random()) * cell
        r, g, b = colorsys.hsv_to_rgb(rng.random(), 0.5, 1.0)
        lights.append({
            "type": "point", "color": [round(r, 4), round(g, 4), round(b, 4)],
            "intensity": round(0.05 * light_range * light_range, 5), "range": round(light_range, 5),
            "extras": {"shadows": "none"},
        })
        nodes.append({"name": "light %d" % i, "translation": [round(x, 4), round(0.25 * light_range, 4), round(z, 4)],
                      "extensions": {"KHR_lights_punctual": {"light": i}}})

    half = FLOOR_SIZE_M / 2
    positions = [-half, 0, half, half, 0, half, half, 0, -half, -half, 0, -half]
    normals = [0, 1, 0] * 4
    indices = [0, 1, 2, 0, 2, 3]
    blob = struct.pack("<12f", *positions) + struct.pack("<12f", *normals) + struct.pack("<6H", *indices) + b"\0\0"
    # Looking down 20 degrees across the floor from above its +Z edge.
    pitch = math.radians(-20.0)
    camera_rotation = [math.sin(pitch / 2), 0.0, 0.0, math.cos(pitch / 2)]
    nodes.append({"name": "floor", "mesh": 0})
    nodes.append({"name": "camera", "translation": [0.0, 14.0, half], "rotation": camera_rotation, "camera": 0})
    gltf = {
        "asset": {"version": "2.0", "generator": "chiaro scripts/make_light_scaling_scene.py"},
        "extensionsUsed": ["KHR_lights_punctual"],
        "extensions": {"KHR_lights_punctual": {"lights": lights}},
        "scene": 0,
        "scenes": [{"nodes": list(range(len(nodes)))}],
        "nodes": nodes,
        "cameras": [{"type": "perspective",
                     "perspective": {"yfov": 0.9, "znear": 0.1, "zfar": 400.0, "aspectRatio": 16 / 9}}],
        "materials": [{"name": "floor", "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.8, 0.8, 1],
                                                                 "metallicFactor": 0, "roughnessFactor": 0.8}}],
        "meshes": [{"name": "floor", "primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2,
                                                     "material": 0}]}],
        "buffers": [{"byteLength": len(blob),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(blob).decode()}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": 48, "target": 34962},
            {"buffer": 0, "byteOffset": 48, "byteLength": 48, "target": 34962},
            {"buffer": 0, "byteOffset": 96, "byteLength": 12, "target": 34963},
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
             "min": [-half, 0, -half], "max": [half, 0, half]},
            {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC3"},
            {"bufferView": 2, "componentType": 5123, "count": 6, "type": "SCALAR"},
        ],
    }
    with open(args.out, "w") as f:
        json.dump(gltf, f)


if __name__ == "__main__":
    main()
