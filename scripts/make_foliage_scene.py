#!/usr/bin/env python3
"""Writes a foliage-like glTF scene for measuring alpha-tested shadows: a floor, rows of
upright and tilted quads cut out by three masked "leaf" textures (several KHR_texture_
transforms, one material reading TEXCOORD_1), a sun, a spot and a point light.

    scripts/make_foliage_scene.py OUT.gltf [--quads N] [--casting on|clip]

`--casting on` marks every material `"shadowCasting": "on"` (solid casters, holes
ignored), to time the shadow passes against the default clipped casters. Python's
standard library only.
"""

import argparse
import base64
import json
import math
import struct
import zlib


def png(width, height, rgba):
    """RGBA8 rows (bytes) as a PNG file."""
    raw = b"".join(b"\0" + rgba[y * width * 4:(y + 1) * width * 4] for y in range(height))

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

    header = struct.pack(">IIBBBBB", width, height, 8, 6, 0, 0, 0)
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b"")


def leaf_texture(size, leaves, seed):
    """Green leaves (opaque ellipses) on transparent ground."""
    state = seed

    def rand():
        nonlocal state
        state = (state * 1103515245 + 12345) & 0x7FFFFFFF
        return state / 0x7FFFFFFF

    shapes = [(rand() * size, rand() * size, size * (0.08 + 0.1 * rand()), size * (0.03 + 0.04 * rand()), rand() * math.pi)
              for _ in range(leaves)]
    pixels = bytearray(size * size * 4)
    for y in range(size):
        for x in range(size):
            inside = False
            for cx, cy, a, b, angle in shapes:
                dx, dy = x - cx, y - cy
                u = dx * math.cos(angle) + dy * math.sin(angle)
                v = -dx * math.sin(angle) + dy * math.cos(angle)
                if (u / a) ** 2 + (v / b) ** 2 <= 1.0:
                    inside = True
                    break
            i = (y * size + x) * 4
            pixels[i:i + 4] = bytes((40, 140, 50, 255 if inside else 0))
    return png(size, size, bytes(pixels))


def quad_nodes(count):
    """`count` leaf quads in a grid, each turned and tilted its own way."""
    nodes = []
    columns = max(1, int(math.sqrt(count)))
    for q in range(count):
        row, column = divmod(q, columns)
        x = (column - columns / 2) * 1.2
        z = (row - count / columns / 2) * 1.2
        yaw = (q * 0.7) % math.pi
        tilt = 0.3 * ((q % 3) - 1)
        rotation = [math.sin(tilt / 2) * math.cos(yaw / 2), math.sin(yaw / 2) * math.cos(tilt / 2), 0.0,
                    math.cos(yaw / 2) * math.cos(tilt / 2)]
        nodes.append({"name": "quad %d" % q, "mesh": 1 + q % 3, "translation": [x, 0.2, z],
                      "rotation": rotation, "scale": [1.6, 1.6, 1.6]})
    return nodes


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("out")
    parser.add_argument("--quads", type=int, default=48)
    parser.add_argument("--casting", choices=["on", "clip"], default="clip")
    args = parser.parse_args()

    # Geometry: a unit quad in XY (facing +Z) with two UV sets, and the floor.
    positions = [-0.5, 0, 0, 0.5, 0, 0, 0.5, 1, 0, -0.5, 1, 0]
    uv0 = [0, 1, 1, 1, 1, 0, 0, 0]
    uv1 = [0, 2, 2, 2, 2, 0, 0, 0]
    floor = [-10, 0, 10, 10, 0, 10, 10, 0, -10, -10, 0, -10]
    floor_uv = [0, 0, 1, 0, 1, 1, 0, 1]
    indices = [0, 1, 2, 0, 2, 3]
    blob = b"".join(struct.pack("<%df" % len(a), *a) for a in (positions, uv0, uv1, floor, floor_uv))
    blob += struct.pack("<6H", *indices) + b"\0\0"
    views = [(0, 48), (48, 32), (80, 32), (112, 48), (160, 32), (192, 12)]
    accessors = [
        {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-0.5, 0, 0], "max": [0.5, 1, 0]},
        {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC2"},
        {"bufferView": 2, "componentType": 5126, "count": 4, "type": "VEC2"},
        {"bufferView": 3, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-10, 0, -10], "max": [10, 0, 10]},
        {"bufferView": 4, "componentType": 5126, "count": 4, "type": "VEC2"},
        {"bufferView": 5, "componentType": 5123, "count": 6, "type": "SCALAR"},
    ]
    extras = {"shadowCasting": "on"} if args.casting == "on" else {}
    leaf = lambda index, transform=None, tex_coord=0: {
        "alphaMode": "MASK", "alphaCutoff": 0.5, "doubleSided": True, "extras": extras,
        "pbrMetallicRoughness": {"baseColorTexture": dict(
            {"index": index, "texCoord": tex_coord},
            **({"extensions": {"KHR_texture_transform": transform}} if transform else {}))},
    }
    materials = [
        {"name": "ground", "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.8, 0.8, 1], "metallicFactor": 0}},
        dict(leaf(0), name="leaves"),
        dict(leaf(1, {"scale": [2, 2], "rotation": 0.4, "offset": [0.1, 0.3]}), name="leaves tiled"),
        dict(leaf(2, {"scale": [1.5, 1]}, tex_coord=1), name="leaves second set"),
    ]
    meshes = [
        {"name": "floor", "primitives": [{"attributes": {"POSITION": 3, "TEXCOORD_0": 4}, "indices": 5, "material": 0}]},
    ] + [
        {"name": "leaf quad %d" % m, "primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1, "TEXCOORD_1": 2},
                                                       "indices": 5, "material": m}]}
        for m in (1, 2, 3)
    ]
    nodes = [{"name": "floor", "mesh": 0}] + quad_nodes(args.quads)
    lights = [
        {"type": "directional", "name": "sun", "intensity": 3},
        {"type": "spot", "name": "spot", "intensity": 60, "range": 20, "spot": {"innerConeAngle": 0.5, "outerConeAngle": 0.7}},
        {"type": "point", "name": "point", "intensity": 30, "range": 12},
    ]
    light_nodes = [
        {"name": "sun", "rotation": [-0.45, 0.3, 0.15, 0.83], "extensions": {"KHR_lights_punctual": {"light": 0}}},
        {"name": "spot", "translation": [-2, 6, 1], "rotation": [-0.7071, 0, 0, 0.7071],
         "extensions": {"KHR_lights_punctual": {"light": 1}}},
        {"name": "point", "translation": [2.5, 2.5, -1.5], "extensions": {"KHR_lights_punctual": {"light": 2}}},
        {"name": "camera", "translation": [0, 9, 11], "rotation": [-0.34, 0, 0, 0.94], "camera": 0},
    ]
    first_light_node = len(nodes)
    nodes += light_nodes
    doc = {
        "asset": {"version": "2.0", "generator": "scripts/make_foliage_scene.py"},
        "extensionsUsed": ["KHR_lights_punctual", "KHR_texture_transform"],
        "extensions": {"KHR_lights_punctual": {"lights": lights}},
        "scene": 0,
        "scenes": [{"nodes": list(range(len(nodes)))}],
        "nodes": nodes,
        "meshes": meshes,
        "materials": materials,
        "textures": [{"source": i, "sampler": 0} for i in range(3)],
        "samplers": [{"magFilter": 9729, "minFilter": 9987, "wrapS": 10497, "wrapT": 10497}],
        "images": [{"uri": "data:image/png;base64," + base64.b64encode(leaf_texture(64, n, s)).decode()}
                   for n, s in ((14, 1), (9, 2), (20, 3))],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.1}}],
        "buffers": [{"byteLength": len(blob), "uri": "data:application/octet-stream;base64," + base64.b64encode(blob).decode()}],
        "bufferViews": [{"buffer": 0, "byteOffset": o, "byteLength": n} for o, n in views],
        "accessors": accessors,
    }
    assert first_light_node > 0
    with open(args.out, "w") as f:
        json.dump(doc, f)


if __name__ == "__main__":
    main()
