# Writes cookies.gltf and its cookie images beside this script: a floor, boxes and three cookie-carrying lights.
import json, math, struct, zlib, base64, os
out = os.path.dirname(os.path.abspath(__file__))

def png(path, w, h, f):
    rows = b""
    for y in range(h):
        rows += b"\x00" + bytes(c for x in range(w) for c in f(x, y))
    def chunk(t, d):
        return struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d) & 0xffffffff)
    data = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
    data += chunk(b"IDAT", zlib.compress(rows, 9)) + chunk(b"IEND", b"")
    open(os.path.join(out, path), "wb").write(data)

# Spot gobo: a four-pane window with soft mullions, warm glass.
def window(x, y):
    u, v = (x + 0.5) / 128, (y + 0.5) / 128
    d = min(abs(u - 0.5), abs(v - 0.5), u, 1 - u, v, 1 - v)
    lit = max(0.0, min(1.0, (d - 0.03) / 0.02))
    return (int(255 * lit), int(235 * lit), int(190 * lit))
png("window.png", 128, 128, window)

# Point cookie: six faces, +X, -X, +Y, -Y, +Z, -Z, each a colour with a lattice of holes.
face_colours = [(255, 90, 60), (60, 200, 255), (255, 255, 255), (255, 220, 90), (120, 255, 120), (220, 120, 255)]
def lantern(x, y):
    face, fx = divmod(x, 64)
    u, v = (fx + 0.5) / 64, (y + 0.5) / 64
    hole = (math.cos(u * math.tau * 4) * math.cos(v * math.tau * 4)) > 0.2
    r, g, b = face_colours[face]
    k = 1.0 if hole else 0.12
    return (int(r * k), int(g * k), int(b * k))
png("lantern.png", 6 * 64, 64, lantern)

# Directional cookie: drifting cloud shadows, tiled.
def clouds(x, y):
    u, v = x / 64, y / 64
    s = 0.5 + 0.25 * math.sin(math.tau * (u + 0.3 * math.sin(math.tau * v))) + 0.25 * math.sin(math.tau * (2 * v + 0.2 * math.cos(math.tau * 2 * u)))
    k = 0.35 + 0.65 * max(0.0, min(1.0, (s - 0.3) * 2.0))
    return (int(255 * k),) * 3
png("clouds.png", 64, 64, clouds)

# Geometry: a 16 m floor and a unit cube (24 vertices, flat normals).
pos, nrm, idx = [], [], []
def quad(corners, n):
    base = len(pos)
    pos.extend(corners); nrm.extend([n] * 4)
    idx.extend([base, base + 1, base + 2, base, base + 2, base + 3])
quad([(-8, 0, 8), (8, 0, 8), (8, 0, -8), (-8, 0, -8)], (0, 1, 0))
floor_count = len(idx)
cube_first = len(idx)
h = 0.5
for axis in range(3):
    for sign in (1, -1):
        n = [0, 0, 0]; n[axis] = sign
        a, b = [(i) for i in range(3) if i != axis]
        corners = []
        for (s, t) in [(-1, -1), (1, -1), (1, 1), (-1, 1)]:
            p = [0, 0, 0]; p[axis] = sign * h; p[a] = s * h; p[b] = t * h
            corners.append(tuple(p))
        # Counter-clockwise seen from outside.
        e1 = [corners[1][i] - corners[0][i] for i in range(3)]
        e2 = [corners[2][i] - corners[0][i] for i in range(3)]
        c = [e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]]
        if sum(c[i] * n[i] for i in range(3)) < 0:
            corners.reverse()
        quad(corners, tuple(n))
blob = b"".join(struct.pack("<3f", *p) for p in pos) + b"".join(struct.pack("<3f", *n) for n in nrm)
index_offset = len(blob)
blob += b"".join(struct.pack("<I", i) for i in idx)
vcount = len(pos)

def rot_x(deg):
    a = math.radians(deg) / 2
    return [math.sin(a), 0, 0, math.cos(a)]
def mul(q, r):
    x1, y1, z1, w1 = q; x2, y2, z2, w2 = r
    return [w1*x2 + x1*w2 + y1*z2 - z1*y2, w1*y2 - x1*z2 + y1*w2 + z1*x2, w1*z2 + x1*y2 - y1*x2 + z1*w2, w1*w2 - x1*x2 - y1*y2 - z1*z2]
def rot_y(deg):
    a = math.radians(deg) / 2
    return [0, math.sin(a), 0, math.cos(a)]

boxes = [((-2.2, 0.6, -0.8), (1.2, 1.2, 1.2), 20), ((1.8, 0.4, 0.6), (0.8, 0.8, 0.8), -30), ((0.2, 0.75, -2.6), (1.0, 1.5, 1.0), 10)]
nodes = [{"name": "floor", "mesh": 0}]
for i, (t, s, yaw) in enumerate(boxes):
    nodes.append({"name": f"box {i}", "mesh": 1, "translation": list(t), "scale": list(s), "rotation": rot_y(yaw)})
lights = [
    {"name": "window spot", "type": "spot", "color": [1, 1, 1], "intensity": 70, "range": 14,
     "spot": {"innerConeAngle": 0.45, "outerConeAngle": 0.55}, "extras": {"cookie": {"image": 0}}},
    {"name": "lantern", "type": "point", "color": [1, 1, 1], "intensity": 14, "range": 9,
     "extras": {"cookie": {"image": 1}}},
    {"name": "cloudy sun", "type": "directional", "color": [1, 0.97, 0.92], "intensity": 0.9,
     "extras": {"cookie": {"image": 2, "size": [6, 6]}}},
]
nodes.append({"name": "window spot", "translation": [-2.5, 5.0, 3.0], "rotation": mul(rot_y(-35), rot_x(-60)),
              "extensions": {"KHR_lights_punctual": {"light": 0}}})
nodes.append({"name": "lantern", "translation": [2.4, 1.3, -1.4], "rotation": rot_y(20),
              "extensions": {"KHR_lights_punctual": {"light": 1}}})
nodes.append({"name": "cloudy sun", "rotation": mul(rot_y(30), rot_x(-55)),
              "extensions": {"KHR_lights_punctual": {"light": 2}}})
nodes.append({"name": "camera", "translation": [0, 7.5, 10], "rotation": rot_x(-34), "camera": 0})
doc = {
    "asset": {"version": "2.0", "generator": "docs/examples/cookies/make.py"},
    "scene": 0,
    "scenes": [{"nodes": list(range(len(nodes)))}],
    "extensionsUsed": ["KHR_lights_punctual"],
    "extensions": {"KHR_lights_punctual": {"lights": lights}},
    "nodes": nodes,
    "cameras": [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.1}}],
    "meshes": [
        {"name": "floor", "primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2, "material": 0}]},
        {"name": "cube", "primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 3, "material": 1}]},
    ],
    "materials": [
        {"name": "floor", "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.8, 0.8, 1], "metallicFactor": 0, "roughnessFactor": 0.9}},
        {"name": "box", "pbrMetallicRoughness": {"baseColorFactor": [0.85, 0.8, 0.75, 1], "metallicFactor": 0, "roughnessFactor": 0.7}},
    ],
    "images": [{"uri": "window.png"}, {"uri": "lantern.png"}, {"uri": "clouds.png"}],
    "buffers": [{"uri": "data:application/octet-stream;base64," + base64.b64encode(blob).decode(), "byteLength": len(blob)}],
    "bufferViews": [
        {"buffer": 0, "byteOffset": 0, "byteLength": vcount * 12},
        {"buffer": 0, "byteOffset": vcount * 12, "byteLength": vcount * 12},
        {"buffer": 0, "byteOffset": index_offset, "byteLength": len(idx) * 4},
    ],
    "accessors": [
        {"bufferView": 0, "componentType": 5126, "count": vcount, "type": "VEC3",
         "min": [min(p[i] for p in pos) for i in range(3)], "max": [max(p[i] for p in pos) for i in range(3)]},
        {"bufferView": 1, "componentType": 5126, "count": vcount, "type": "VEC3"},
        {"bufferView": 2, "componentType": 5125, "count": floor_count, "type": "SCALAR"},
        {"bufferView": 2, "byteOffset": floor_count * 4, "componentType": 5125, "count": len(idx) - floor_count, "type": "SCALAR"},
    ],
}
json.dump(doc, open(os.path.join(out, "cookies.gltf"), "w"), indent=1)
