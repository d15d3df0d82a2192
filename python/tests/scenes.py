"""Small glTF scenes written by the tests themselves: a floor, a labelled box, a sun at
a known angle and a camera, with every number the tests check against kept here."""

import base64
import json
import math
import struct
import zlib

import numpy as np

FLOOR_HALF = 10.0          # the floor spans [-10, 10] m in x and z, at y = 0
BOX_MIN = np.array([-0.5, 0.0, -0.5])
BOX_MAX = np.array([0.5, 1.0, 0.5])
BOX_LABEL = 7
FLOOR_NODE, BOX_NODE, SUN_NODE, CAMERA_NODE = 0, 1, 2, 3
# Low enough for a shadow about 1.6 m long, falling towards the camera.
SUN_DIRECTION = np.array([0.8, -0.6, 0.5]) / np.linalg.norm([0.8, -0.6, 0.5])
CAMERA_EYE = np.array([3.0, 5.0, 6.0])
CAMERA_TARGET = np.array([0.0, 0.0, 0.0])
CAMERA_YFOV_DEG = 50.0


def quat_from_to(a, b):
    """The unit quaternion (x, y, z, w) turning direction a onto direction b."""
    a, b = np.asarray(a, float) / np.linalg.norm(a), np.asarray(b, float) / np.linalg.norm(b)
    axis = np.cross(a, b)
    w = 1.0 + float(np.dot(a, b))
    q = np.array([axis[0], axis[1], axis[2], w])
    return q / np.linalg.norm(q)


def look_at_quat(eye, target):
    """The rotation of a glTF camera node at eye looking at target with +Y up."""
    f = (target - eye) / np.linalg.norm(target - eye)
    r = np.cross(f, [0.0, 1.0, 0.0]); r /= np.linalg.norm(r)
    u = np.cross(r, f)
    m = np.stack([r, u, -f], axis=1)  # columns: the node's x, y, z axes
    w = np.sqrt(max(0.0, 1.0 + m[0, 0] + m[1, 1] + m[2, 2])) / 2.0
    x = (m[2, 1] - m[1, 2]) / (4 * w)
    y = (m[0, 2] - m[2, 0]) / (4 * w)
    z = (m[1, 0] - m[0, 1]) / (4 * w)
    return [x, y, z, w]


def box_geometry(lo, hi):
    """An axis-aligned box from lo to hi: 24 vertices with face normals, 36 indices wound
    counter-clockwise seen from outside."""
    positions, normals, indices = [], [], []
    for axis in range(3):
        u, v = [a for a in range(3) if a != axis]
        for sign in (-1.0, 1.0):
            n = np.zeros(3)
            n[axis] = sign
            base = len(positions)
            for cu, cv in ((0, 0), (1, 0), (1, 1), (0, 1)):
                p = np.zeros(3)
                p[axis] = hi[axis] if sign > 0 else lo[axis]
                p[u] = (lo[u], hi[u])[cu]
                p[v] = (lo[v], hi[v])[cv]
                positions.append(p)
                normals.append(n)
            if np.dot(np.cross(np.eye(3)[u], np.eye(3)[v]), n) > 0:
                indices += [base, base + 1, base + 2, base, base + 2, base + 3]
            else:
                indices += [base, base + 2, base + 1, base, base + 3, base + 2]
    return np.array(positions, np.float32), np.array(normals, np.float32), np.array(indices, np.uint16)


def _floor_geometry():
    h = FLOOR_HALF
    positions = np.array([[-h, 0, -h], [h, 0, -h], [h, 0, h], [-h, 0, h]], np.float32)
    normals = np.tile(np.array([0, 1, 0], np.float32), (4, 1))
    indices = np.array([0, 2, 1, 0, 3, 2], np.uint16)
    return positions, normals, indices


def embed_meshes(parts):
    """glTF meshes for (name, (positions, normals, indices), material) parts, with their
    accessors, buffer views and one data-URI buffer, as a dict to merge into a document."""
    blob = bytearray()
    views, accessors, meshes = [], [], []

    def add(array, target, kind):
        while len(blob) % 4:
            blob.append(0)
        views.append({"buffer": 0, "byteOffset": len(blob), "byteLength": array.nbytes, "target": target})
        blob.extend(array.tobytes())
        acc = {"bufferView": len(views) - 1, "count": int(array.shape[0]),
               "componentType": 5126 if array.dtype == np.float32 else 5123, "type": kind}
        if kind == "VEC3" and array.dtype == np.float32:
            acc["min"] = array.min(axis=0).tolist(); acc["max"] = array.max(axis=0).tolist()
        accessors.append(acc)
        return len(accessors) - 1

    for name, (p, n, i), material in parts:
        attributes = {"POSITION": add(p, 34962, "VEC3"), "NORMAL": add(n, 34962, "VEC3")}
        meshes.append({"name": name, "primitives": [{"attributes": attributes, "indices": add(i, 34963, "SCALAR"),
                                                     "material": material}]})
    uri = "data:application/octet-stream;base64," + base64.b64encode(bytes(blob)).decode()
    return {"meshes": meshes, "accessors": accessors, "bufferViews": views,
            "buffers": [{"byteLength": len(blob), "uri": uri}]}


def rgbd_png(size, radiance):
    """A `size` x `size` PNG data URI of one RGBD pixel (gamma 2.2, as EXT_lights_image_based
    writers encode): the radiance `radiance` (three floats) everywhere."""
    scale = min(max(math.floor(255 / max(max(radiance), 1e-6)), 1), 255) / 255
    pixel = bytes([min(255, round(255 * (c * scale) ** (1 / 2.2))) for c in radiance] + [round(255 * scale)])
    raw = b"".join(b"\x00" + pixel * size for _ in range(size))

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))
    png = (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", size, size, 8, 6, 0, 0, 0))
           + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))
    return "data:image/png;base64," + base64.b64encode(png).decode()


def image_based_light(radiance, size=8):
    """The parts of a document that give its scene an EXT_lights_image_based light whose six
    faces all hold `radiance`: (root extension, scene extension, images)."""
    light = {"name": "grey studio", "intensity": 1.0, "rotation": [0, 0, 0, 1],
             "irradianceCoefficients": [[0, 0, 0]] * 9, "specularImageSize": size,
             "specularImages": [[0, 1, 2, 3, 4, 5]]}
    images = [{"uri": rgbd_png(size, radiance)} for _ in range(6)]
    return {"lights": [light]}, {"light": 0}, images


def write_scene(path, box_label=BOX_LABEL, sun_lux=5.0, environment=None):
    """Writes the floor-box-sun-camera scene as one self-contained .gltf at `path`; with
    `environment` (a radiance, three floats), an EXT_lights_image_based light of it too."""
    mesh_data = embed_meshes([("floor", _floor_geometry(), 0), ("box", box_geometry(BOX_MIN, BOX_MAX), 0)])
    box_node = {"name": "box", "mesh": 1}
    if box_label is not None:
        box_node["extras"] = {"label": box_label}
    doc = {
        "asset": {"version": "2.0"},
        "extensionsUsed": ["KHR_lights_punctual"],
        "extensions": {"KHR_lights_punctual": {"lights": [
            {"name": "sun", "type": "directional", "intensity": sun_lux, "color": [1, 1, 1]}]}},
        "scene": 0,
        "scenes": [{"nodes": [FLOOR_NODE, BOX_NODE, SUN_NODE, CAMERA_NODE]}],
        "nodes": [
            {"name": "floor", "mesh": 0},
            box_node,
            {"name": "sun", "rotation": quat_from_to([0, 0, -1], SUN_DIRECTION).tolist(),
             "extensions": {"KHR_lights_punctual": {"light": 0}}},
            {"name": "camera", "camera": 0, "translation": CAMERA_EYE.tolist(),
             "rotation": look_at_quat(CAMERA_EYE, CAMERA_TARGET)},
        ],
        "cameras": [{"name": "overview", "type": "perspective",
                     "perspective": {"yfov": float(np.radians(CAMERA_YFOV_DEG)), "znear": 0.05, "zfar": 100.0}}],
        "materials": [{"name": "white", "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.8, 0.8, 1],
                                                                 "metallicFactor": 0.0, "roughnessFactor": 1.0}}],
        **mesh_data,
    }
    if environment is not None:
        root, scene, images = image_based_light(environment)
        doc["extensionsUsed"].append("EXT_lights_image_based")
        doc["extensions"]["EXT_lights_image_based"] = root
        doc["scenes"][0]["extensions"] = {"EXT_lights_image_based": scene}
        doc["images"] = images
    with open(path, "w") as f:
        json.dump(doc, f)
    return path


def add_animation(doc, name, times, values, value_type, target):
    """Appends to the glTF `doc` an animation of one LINEAR channel aimed at `target` (a
    channel target object), its key `times` (seconds) and flat `values` (floats,
    `value_type` each) in a data-URI buffer of their own."""
    keys = struct.pack(f"<{len(times)}f", *times) + struct.pack(f"<{len(values)}f", *values)
    doc["buffers"].append({"byteLength": len(keys),
                           "uri": "data:application/octet-stream;base64," + base64.b64encode(keys).decode()})
    buffer = len(doc["buffers"]) - 1
    doc["bufferViews"] += [{"buffer": buffer, "byteOffset": 0, "byteLength": 4 * len(times)},
                           {"buffer": buffer, "byteOffset": 4 * len(times), "byteLength": 4 * len(values)}]
    views = len(doc["bufferViews"])
    doc["accessors"] += [
        {"bufferView": views - 2, "componentType": 5126, "count": len(times), "type": "SCALAR",
         "min": [min(times)], "max": [max(times)]},
        {"bufferView": views - 1, "componentType": 5126, "count": len(times), "type": value_type},
    ]
    accessors = len(doc["accessors"])
    doc.setdefault("animations", []).append({
        "name": name,
        "samplers": [{"input": accessors - 2, "output": accessors - 1}],
        "channels": [{"sampler": 0, "target": target}]})


def view_rays(width, height, eye, target, yfov_deg, up=(0.0, 1.0, 0.0)):
    """Per pixel centre, the world-space ray direction whose view-space z is -1 (so the
    distance along the view axis to a point is its ray parameter), rows from the top."""
    f = (target - eye) / np.linalg.norm(target - eye)
    r = np.cross(f, up); r /= np.linalg.norm(r)
    u = np.cross(r, f)
    t = np.tan(np.radians(yfov_deg) / 2)
    aspect = width / height
    xs = ((np.arange(width) + 0.5) / width * 2 - 1) * t * aspect
    ys = (1 - (np.arange(height) + 0.5) / height * 2) * t
    x, y = np.meshgrid(xs, ys)
    return x[..., None] * r + y[..., None] * u + f


def hits_box(origins, direction, lo=BOX_MIN, hi=BOX_MAX, eps=1e-4):
    """Whether rays from `origins` (..., 3) along one `direction` hit the box (slab test)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        inv = 1.0 / direction
        t0 = (lo - origins) * inv
        t1 = (hi - origins) * inv
        # A ray in a slab's bounding plane (0 * inf) counts as inside that slab.
        near = np.where(np.isnan(t0) | np.isnan(t1), -np.inf, np.minimum(t0, t1))
        far = np.where(np.isnan(t0) | np.isnan(t1), np.inf, np.maximum(t0, t1))
    tmin = near.max(axis=-1)
    tmax = far.min(axis=-1)
    return (tmax >= np.maximum(tmin, eps))
