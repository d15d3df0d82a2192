# Writes room.gltf beside this script: a room open towards the camera (white floor,
# ceiling and back wall, a red left wall, a green right wall, every face turned inwards),
# two static boxes, one dynamic box (extras.static false, lit by the probes), and a baked
# point light under the ceiling. See docs/baking.md.
import json, math, struct, base64, os
out = os.path.dirname(os.path.abspath(__file__))

pos, nrm, idx = [], [], []
meshes = []
def quad(corners, n):
    base = len(pos)
    pos.extend(corners); nrm.extend([n] * 4)
    # Counter-clockwise seen from the side n points to.
    e1 = [corners[1][i] - corners[0][i] for i in range(3)]
    e2 = [corners[2][i] - corners[0][i] for i in range(3)]
    c = [e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]]
    order = [0, 1, 2, 0, 2, 3] if sum(c[i] * n[i] for i in range(3)) > 0 else [0, 2, 1, 0, 3, 2]
    idx.extend(base + k for k in order)

def mesh(name, material, make):
    first = len(idx)
    make()
    meshes.append((name, material, first, len(idx) - first))

W, H, D = 2.0, 2.4, 2.0  # half width, height, half depth
mesh("floor", 0, lambda: quad([(-W, 0, -D), (W, 0, -D), (W, 0, D), (-W, 0, D)], (0, 1, 0)))
mesh("ceiling", 0, lambda: quad([(-W, H, -D), (W, H, -D), (W, H, D), (-W, H, D)], (0, -1, 0)))
mesh("back wall", 0, lambda: quad([(-W, 0, -D), (W, 0, -D), (W, H, -D), (-W, H, -D)], (0, 0, 1)))
mesh("left wall", 1, lambda: quad([(-W, 0, -D), (-W, 0, D), (-W, H, D), (-W, H, -D)], (1, 0, 0)))
mesh("right wall", 2, lambda: quad([(W, 0, -D), (W, 0, D), (W, H, D), (W, H, -D)], (-1, 0, 0)))
def cube():
    h = 0.5
    for axis in range(3):
        for sign in (1, -1):
            n = [0, 0, 0]; n[axis] = sign
            a, b = [i for i in range(3) if i != axis]
            corners = []
            for (s, t) in [(-1, -1), (1, -1), (1, 1), (-1, 1)]:
                p = [0, 0, 0]; p[axis] = sign * h; p[a] = s * h; p[b] = t * h
                corners.append(tuple(p))
            quad(corners, tuple(n))
mesh("cube", 0, cube)
mesh("dynamic cube", 3, cube)

blob = b"".join(struct.pack("<3f", *p) for p in pos) + b"".join(struct.pack("<3f", *n) for n in nrm)
index_offset = len(blob)
blob += b"".join(struct.pack("<I", i) for i in idx)
vcount = len(pos)

def rot_y(deg):
    a = math.radians(deg) / 2
    return [0, math.sin(a), 0, math.cos(a)]
def rot_x(deg):
    a = math.radians(deg) / 2
    return [math.sin(a), 0, 0, math.cos(a)]

nodes = [{"name": name, "mesh": k} for k, (name, *_rest) in enumerate(meshes[:5])]
nodes.append({"name": "tall box", "mesh": 5, "translation": [-0.7, 0.75, -0.6], "scale": [0.7, 1.5, 0.7], "rotation": rot_y(20)})
nodes.append({"name": "short box", "mesh": 5, "translation": [0.8, 0.35, 0.4], "scale": [0.7, 0.7, 0.7], "rotation": rot_y(-25)})
nodes.append({"name": "moving box", "mesh": 6, "translation": [0.2, 0.2, 1.3], "scale": [0.4, 0.4, 0.4], "rotation": rot_y(40),
              "extras": {"static": False}})
nodes.append({"name": "lamp", "translation": [0, 1.75, 0.2], "extensions": {"KHR_lights_punctual": {"light": 0}}})
nodes.append({"name": "camera", "translation": [0, 1.3, 5.6], "rotation": rot_x(-5), "camera": 0})

accessors = [
    {"bufferView": 0, "componentType": 5126, "count": vcount, "type": "VEC3",
     "min": [min(p[i] for p in pos) for i in range(3)], "max": [max(p[i] for p in pos) for i in range(3)]},
    {"bufferView": 1, "componentType": 5126, "count": vcount, "type": "VEC3"},
]
gltf_meshes = []
for name, material, first, count in meshes:
    accessors.append({"bufferView": 2, "byteOffset": first * 4, "componentType": 5125, "count": count, "type": "SCALAR"})
    gltf_meshes.append({"name": name, "primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": len(accessors) - 1, "material": material}]})

def matte(name, rgb):
    return {"name": name, "pbrMetallicRoughness": {"baseColorFactor": rgb + [1], "metallicFactor": 0, "roughnessFactor": 1}}
doc = {
    "asset": {"version": "2.0", "generator": "docs/examples/baking/make.py"},
    "scene": 0,
    "scenes": [{"nodes": list(range(len(nodes)))}],
    "extensionsUsed": ["KHR_lights_punctual"],
    "extensions": {"KHR_lights_punctual": {"lights": [
        {"name": "lamp", "type": "point", "color": [1, 0.95, 0.85], "intensity": 6, "range": 12,
         "extras": {"mode": "baked", "shadows": "soft"}}]}},
    "nodes": nodes,
    "cameras": [{"type": "perspective", "perspective": {"yfov": 0.75, "znear": 0.05}}],
    "meshes": gltf_meshes,
    "materials": [matte("white", [0.8, 0.8, 0.8]), matte("red", [0.75, 0.1, 0.08]), matte("green", [0.12, 0.6, 0.15]),
                  matte("blue", [0.2, 0.3, 0.85])],
    "buffers": [{"uri": "data:application/octet-stream;base64," + base64.b64encode(blob).decode(), "byteLength": len(blob)}],
    "bufferViews": [
        {"buffer": 0, "byteOffset": 0, "byteLength": vcount * 12},
        {"buffer": 0, "byteOffset": vcount * 12, "byteLength": vcount * 12},
        {"buffer": 0, "byteOffset": index_offset, "byteLength": len(idx) * 4},
    ],
    "accessors": accessors,
}
json.dump(doc, open(os.path.join(out, "room.gltf"), "w"), indent=1)
open(os.path.join(out, "settings.toml"), "w").write(
    "# The room is lit by its baked lamp alone.\n[render]\nambient = [0.0, 0.0, 0.0]\nexposure_ev100 = -0.5\n\n"
    "[bake]\nsamples = 1024\nbounces = 4\ntexels_per_metre = 24.0\nprobe_spacing = 0.5\n")
