#!/usr/bin/env python3
"""Writes small glTF test scenes for judging materials against Blender Cycles
(scripts/compare_cycles.py): a row of UV spheres over a grey floor, one material
parameter spanned across the row, lit by a sun, a point light or an environment.

    python3 scripts/cycles_scenes.py OUT.gltf --light sun|point|environment|rect|disk
        [--base-color R,G,B] [--metallic M] [--roughness R]
        [--param NAME VALUES]... [--extension NAME] [--ext-param KEY VALUES]...
        [--ext-fixed JSON] [--extra-extension NAME JSON]... [--materials FILE.json]
        [--sun-lux E] [--point-cd I] [--env-nits L] [--env-kind uniform|gradient]
        [--area-nits L] [--area-size S] [--area-aspect A] [--area-tilt-deg T] [--area-shadows MODE]
        [--aspect W/H] [--segments 48] [--rings 24] [--no-floor] [--sphere-shadows off]

Materials. Every sphere starts from the plain metallic-roughness material the
--base-color, --metallic and --roughness options give; then:
- `--param NAME VALUES` (repeatable) sets one value per sphere. NAME is `roughness`,
  `metallic`, `baseColor` or a dotted path into the glTF material
  (`pbrMetallicRoughness.roughnessFactor`, `extensions.KHR_materials_ior.ior`). VALUES
  is a comma list of numbers (`0.1,0.3,0.5`) or a JSON list (`[[1,0,0],[0,1,0]]`).
- `--extension NAME` adds that extension to every sphere; `--ext-fixed JSON` is its
  dict of fixed values, `--ext-param KEY VALUES` (repeatable) spans one of its keys.
- `--extra-extension NAME JSON` (repeatable) adds one more extension with those fixed
  values to every sphere (KHR_materials_volume beside KHR_materials_transmission).
- `--materials FILE.json` replaces all of the above: a JSON list of glTF material
  dicts, one per sphere (names are given if missing).
The row has as many spheres as there are values (5 with the defaults). Every extension
found in a material is listed in `extensionsUsed`.

Lights (KHR_lights_punctual, no `range`):
- `sun`: a directional light of --sun-lux (default 3) from above, left and in front;
- `point`: a point light of --point-cd candela (default 60) 3.5 m up and 1.5 m in front
  of the middle of the row;
- `rect`, `disk`: an EXT_lights_area light of --area-nits (default 400) luminance,
  --area-size metres (default 1: a rect's height, a disk's diameter) and, for a rect,
  --area-aspect (default 2, width over height, along the row), 3 m up and 1.5 m in front
  of the middle of the row, shining down and tilted --area-tilt-deg (default 30) towards
  the camera; `extras.shadows` --area-shadows (default none: compare with
  `--cycles-arg=--unshadowed`). Cycles renders it through scripts/cycles_area_render.py
  (compare_cycles.py --cycles-script scripts/cycles_area_render.py);
- `environment`: no punctual light; an equirectangular Radiance image
  `OUT-stem.environment.hdr` is written beside the scene, `uniform` (--env-nits
  everywhere, a white furnace) or `gradient` (--env-nits overhead, falling linearly to a
  fifth of it straight down). Pass it to compare_cycles.py with `--environment`.

Geometry: spheres of radius 0.5 m resting on the floor (y = 0), 1.25 m apart along x,
smooth normals, UVs and tangents (u around, v down; tangent along +u, w = +1), 48 x 24
segments by default; a 40 m grey floor (base colour 0.5, roughness 0.8); a camera 8.7 m
away looking slightly down at the row (aspect --aspect, default 1). Node and material
names say what they span (`sphere 2 roughness=0.5`). `--no-floor` leaves the floor out
(a refracting sphere then shows the environment behind it in both renderers: Cycles'
refracted rays do not see opaque objects under --direct-only). `--sphere-shadows off`
gives the sphere nodes `extras.castShadows = "off"`, which Chiaro reads and Cycles
follows with cycles_render.py's --node-shadow-extras (compare_cycles.py
--cycles-arg=--node-shadow-extras). Standard library only.
"""

from __future__ import annotations

import argparse
import base64
import json
import math
import struct
import sys
from pathlib import Path
from typing import Any, Sequence

Vec3 = tuple[float, float, float]
Json = dict[str, Any]

SPHERE_RADIUS_M = 0.5
SPHERE_SPACING_M = 1.25
FLOOR_HALF_SIZE_M = 20.0
FLOOR_MATERIAL: Json = {
    "name": "floor",
    "pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.5, 0.5, 1.0], "metallicFactor": 0.0,
                             "roughnessFactor": 0.8},
}
CAMERA_POSITION: Vec3 = (0.0, 2.5, 8.5)
CAMERA_TARGET: Vec3 = (0.0, 0.5, 0.0)
CAMERA_YFOV_RAD = 0.75
SUN_TRAVEL: Vec3 = (0.5, -1.0, -0.6)  # the direction the sunlight travels in
POINT_POSITION: Vec3 = (0.0, 3.5, 1.5)
ALIASES = {
    "roughness": "pbrMetallicRoughness.roughnessFactor",
    "metallic": "pbrMetallicRoughness.metallicFactor",
    "baseColor": "pbrMetallicRoughness.baseColorFactor",
}


class SceneError(ValueError):
    """A bad option value; the message names the option."""


# ---------------------------------------------------------------- vectors


def normalize(v: Sequence[float]) -> Vec3:
    n = math.sqrt(sum(c * c for c in v))
    return (v[0] / n, v[1] / n, v[2] / n)


def cross(a: Sequence[float], b: Sequence[float]) -> Vec3:
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def quat_from_basis(x: Vec3, y: Vec3, z: Vec3) -> list[float]:
    """The unit quaternion [x, y, z, w] of the rotation whose matrix columns are x, y, z."""
    m00, m11, m22 = x[0], y[1], z[2]
    trace = m00 + m11 + m22
    if trace > 0.0:
        s = 2.0 * math.sqrt(trace + 1.0)
        q = [(y[2] - z[1]) / s, (z[0] - x[2]) / s, (x[1] - y[0]) / s, 0.25 * s]
    elif m00 > m11 and m00 > m22:
        s = 2.0 * math.sqrt(1.0 + m00 - m11 - m22)
        q = [0.25 * s, (y[0] + x[1]) / s, (z[0] + x[2]) / s, (y[2] - z[1]) / s]
    elif m11 > m22:
        s = 2.0 * math.sqrt(1.0 + m11 - m00 - m22)
        q = [(y[0] + x[1]) / s, 0.25 * s, (z[1] + y[2]) / s, (z[0] - x[2]) / s]
    else:
        s = 2.0 * math.sqrt(1.0 + m22 - m00 - m11)
        q = [(z[0] + x[2]) / s, (z[1] + y[2]) / s, 0.25 * s, (x[1] - y[0]) / s]
    return [round(c, 7) for c in q]


def looking_along(forward: Sequence[float]) -> list[float]:
    """Rotation of a glTF camera or light (which look along their -Z, up +Y) to `forward`."""
    back = normalize([-c for c in forward])
    right = normalize(cross((0.0, 1.0, 0.0), back))
    up = cross(back, right)
    return quat_from_basis(right, up, back)


# ---------------------------------------------------------------- meshes


class Buffer:
    """One binary buffer growing by accessors, each in its own buffer view."""

    def __init__(self) -> None:
        self.data = bytearray()
        self.views: list[Json] = []
        self.accessors: list[Json] = []

    def add(self, fmt: str, values: Sequence[float] | Sequence[int], kind: str, component: int,
            target: int, minmax: bool = False) -> int:
        while len(self.data) % 4:
            self.data.append(0)
        width = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4}[kind]
        self.views.append({"buffer": 0, "byteOffset": len(self.data),
                           "byteLength": struct.calcsize(f"<{len(values)}{fmt}"), "target": target})
        self.data += struct.pack(f"<{len(values)}{fmt}", *values)
        accessor: Json = {"bufferView": len(self.views) - 1, "componentType": component,
                          "count": len(values) // width, "type": kind}
        if minmax:
            columns = [values[i::width] for i in range(width)]
            accessor["min"] = [min(c) for c in columns]
            accessor["max"] = [max(c) for c in columns]
        self.accessors.append(accessor)
        return len(self.accessors) - 1

    def primitive(self, positions: list[float], normals: list[float], uvs: list[float],
                  tangents: list[float], indices: list[int], material: int) -> Json:
        attributes = {
            "POSITION": self.add("f", positions, "VEC3", 5126, 34962, minmax=True),
            "NORMAL": self.add("f", normals, "VEC3", 5126, 34962),
            "TEXCOORD_0": self.add("f", uvs, "VEC2", 5126, 34962),
            "TANGENT": self.add("f", tangents, "VEC4", 5126, 34962),
        }
        return {"attributes": attributes, "indices": self.add("H", indices, "SCALAR", 5123, 34963),
                "material": material}


def uv_sphere(radius: float, segments: int, rings: int) -> tuple[list[float], list[float], list[float],
                                                                  list[float], list[int]]:
    """Positions, normals, UVs, tangents and counter-clockwise triangles of a UV sphere
    around the origin: theta from +Y (v = 0) down to -Y (v = 1), phi around from +Z
    towards +X (u = 0 to 1, the seam duplicated)."""
    positions: list[float] = []
    normals: list[float] = []
    uvs: list[float] = []
    tangents: list[float] = []
    for j in range(rings + 1):
        theta = math.pi * j / rings
        for i in range(segments + 1):
            phi = 2.0 * math.pi * i / segments
            n = (math.sin(theta) * math.sin(phi), math.cos(theta), math.sin(theta) * math.cos(phi))
            positions += [radius * c for c in n]
            normals += n
            uvs += [i / segments, j / rings]
            tangents += [math.cos(phi), 0.0, -math.sin(phi), 1.0]
    indices: list[int] = []
    row = segments + 1
    for j in range(rings):
        for i in range(segments):
            a, b = j * row + i, (j + 1) * row + i
            c, d = b + 1, a + 1
            if j != rings - 1:
                indices += [a, b, c]
            if j != 0:
                indices += [a, c, d]
    return positions, normals, uvs, tangents, indices


def floor_quad(half: float) -> tuple[list[float], list[float], list[float], list[float], list[int]]:
    """A square at y = 0 facing +Y: u along +x, v along +z."""
    corners = [(-half, -half), (-half, half), (half, half), (half, -half)]
    positions = [c for x, z in corners for c in (x, 0.0, z)]
    uvs = [c for x, z in corners for c in ((x + half) / (2 * half), (z + half) / (2 * half))]
    return positions, [0.0, 1.0, 0.0] * 4, uvs, [1.0, 0.0, 0.0, 1.0] * 4, [0, 1, 2, 0, 2, 3]


# ---------------------------------------------------------------- materials


def parse_values(text: str, option: str) -> list[Any]:
    """`0.1,0.3,0.5` or a JSON list."""
    try:
        values = json.loads(text) if text.lstrip().startswith("[") else [float(v) for v in text.split(",")]
    except ValueError as err:
        raise SceneError(f"{option}: {text!r} is neither a comma list of numbers nor a JSON list ({err})")
    if not isinstance(values, list) or not values:
        raise SceneError(f"{option}: {text!r} is not a non-empty list")
    return values


def set_path(material: Json, path: str, value: Any) -> None:
    keys = ALIASES.get(path, path).split(".")
    node = material
    for key in keys[:-1]:
        node = node.setdefault(key, {})
    if keys[-1] == "baseColorFactor" and isinstance(value, list) and len(value) == 3:
        value = value + [1.0]
    node[keys[-1]] = value


def label_of(path: str, value: Any) -> str:
    short = path.split(".")[-1]
    text = json.dumps(value, separators=(",", ":")) if isinstance(value, list) else f"{value:g}"
    return f"{short}={text}"


def spanned_materials(args: argparse.Namespace) -> list[Json]:
    """One glTF material per sphere from the options (see the module docstring)."""
    if args.materials:
        try:
            materials = json.loads(Path(args.materials).read_text())
        except (OSError, ValueError) as err:
            raise SceneError(f"--materials {args.materials}: {err}")
        if not isinstance(materials, list) or not all(isinstance(m, dict) for m in materials) or not materials:
            raise SceneError(f"--materials {args.materials}: not a non-empty JSON list of material dicts")
        for i, given in enumerate(materials):
            given.setdefault("name", f"sphere {i}")
        return materials
    spans: list[tuple[str, list[Any]]] = [(path, parse_values(v, f"--param {path}")) for path, v in args.param]
    if args.ext_param and not args.extension:
        raise SceneError("--ext-param needs --extension")
    for key, v in args.ext_param:
        spans.append((f"extensions.{args.extension}.{key}", parse_values(v, f"--ext-param {key}")))
    if not spans:
        spans = [("roughness", [0.1, 0.3, 0.5, 0.7, 0.9])]
    counts = {len(values) for _, values in spans}
    if len(counts) != 1:
        raise SceneError(f"--param/--ext-param: value lists differ in length ({sorted(counts)})")
    fixed: Json = {}
    if args.ext_fixed:
        if not args.extension:
            raise SceneError("--ext-fixed needs --extension")
        try:
            fixed = json.loads(args.ext_fixed)
        except ValueError as err:
            raise SceneError(f"--ext-fixed: not JSON ({err})")
        if not isinstance(fixed, dict):
            raise SceneError("--ext-fixed: not a JSON object")
    extras: list[tuple[str, Json]] = []
    for name, text in args.extra_extension:
        try:
            values = json.loads(text)
        except ValueError as err:
            raise SceneError(f"--extra-extension {name}: not JSON ({err})")
        if not isinstance(values, dict) or name == args.extension:
            raise SceneError(f"--extra-extension {name}: not a JSON object, or the --extension itself")
        extras.append((name, values))
    materials = []
    for i in range(counts.pop()):
        m: Json = {"pbrMetallicRoughness": {"baseColorFactor": list(args.base_color) + [1.0],
                                            "metallicFactor": args.metallic, "roughnessFactor": args.roughness}}
        if args.extension:
            m["extensions"] = {args.extension: dict(fixed)}
        for name, values in extras:
            m.setdefault("extensions", {})[name] = dict(values)
        labels = []
        for path, values in spans:
            set_path(m, path, values[i])
            labels.append(label_of(path, values[i]))
        m["name"] = f"sphere {i} " + " ".join(labels)
        materials.append(m)
    return materials


# ---------------------------------------------------------------- environment


def rgbe(r: float, g: float, b: float) -> bytes:
    """Radiance's shared-exponent encoding of one texel."""
    top = max(r, g, b)
    if top < 1e-32:
        return b"\0\0\0\0"
    mantissa, exponent = math.frexp(top)
    scale = mantissa * 256.0 / top
    return bytes([int(r * scale), int(g * scale), int(b * scale), exponent + 128])


def write_environment(path: Path, kind: str, nits: float, width: int = 64) -> None:
    """An equirectangular (2:1) Radiance .hdr, flat scanlines. Rows run from +Y (top) to -Y;
    `gradient` goes linearly in the direction's y from `nits` overhead to nits / 5 below."""
    height = width // 2
    rows = []
    for row in range(height):
        y = math.cos(math.pi * (row + 0.5) / height)
        value = nits if kind == "uniform" else nits * (0.6 + 0.4 * y)
        rows.append(rgbe(value, value, value) * width)
    header = f"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y {height} +X {width}\n".encode()
    path.write_bytes(header + b"".join(rows))


# ---------------------------------------------------------------- the scene


AREA_POSITION: Vec3 = (0.0, 3.0, 1.5)


def area_light_nodes(kind: str, nits: float, size: float, aspect: float, tilt_deg: float,
                     shadows: str) -> tuple[list[Json], list[Json]]:
    """An EXT_lights_area light and its node: shining down, tilted towards the camera (+z)."""
    light: Json = {"name": kind, "type": kind, "color": [1.0, 1.0, 1.0], "intensity": nits, "size": size,
                   "extras": {"shadows": shadows}}
    if kind == "rect":
        light["rect"] = {"aspect": aspect}
    tilt = math.radians(tilt_deg)
    forward = normalize([0.0, -math.cos(tilt), math.sin(tilt)])
    node = {"name": kind, "translation": list(AREA_POSITION), "rotation": looking_along(forward),
            "extensions": {"EXT_lights_area": {"light": 0}}}
    return [light], [node]


def light_nodes(kind: str, sun_lux: float, point_cd: float) -> tuple[list[Json], list[Json]]:
    """KHR_lights_punctual lights and their nodes (none for the environment)."""
    if kind == "sun":
        light = {"name": "sun", "type": "directional", "color": [1.0, 1.0, 1.0], "intensity": sun_lux}
        node = {"name": "sun", "rotation": looking_along(normalize(SUN_TRAVEL)),
                "extensions": {"KHR_lights_punctual": {"light": 0}}}
        return [light], [node]
    if kind == "point":
        light = {"name": "point", "type": "point", "color": [1.0, 1.0, 1.0], "intensity": point_cd}
        node = {"name": "point", "translation": list(POINT_POSITION),
                "extensions": {"KHR_lights_punctual": {"light": 0}}}
        return [light], [node]
    return [], []


def build_scene(materials: list[Json], light: str, sun_lux: float, point_cd: float, aspect: float,
                segments: int, rings: int, with_floor: bool = True, sphere_shadows: bool = True,
                area: tuple[float, float, float, float, str] = (400.0, 1.0, 2.0, 30.0, "none")) -> Json:
    """The glTF document, its buffer embedded as a data URI."""
    buf = Buffer()
    sphere = buf.primitive(*uv_sphere(SPHERE_RADIUS_M, segments, rings), material=0)
    meshes: list[Json] = [{"name": f"sphere {i}", "primitives": [dict(sphere, material=i)]}
                          for i in range(len(materials))]
    if with_floor:
        floor_prim = buf.primitive(*floor_quad(FLOOR_HALF_SIZE_M), material=len(materials))
        meshes.append({"name": "floor", "primitives": [floor_prim]})
    nodes: list[Json] = []
    first_x = -SPHERE_SPACING_M * (len(materials) - 1) / 2
    for i, m in enumerate(materials):
        nodes.append({"name": m["name"], "mesh": i,
                      "translation": [round(first_x + i * SPHERE_SPACING_M, 6), SPHERE_RADIUS_M, 0.0]})
        if not sphere_shadows:
            nodes[-1]["extras"] = {"castShadows": "off"}
    if with_floor:
        nodes.append({"name": "floor", "mesh": len(materials)})
    forward = normalize([t - p for t, p in zip(CAMERA_TARGET, CAMERA_POSITION)])
    nodes.append({"name": "camera", "camera": 0, "translation": list(CAMERA_POSITION),
                  "rotation": looking_along(forward)})
    is_area = light in ("rect", "disk")
    lights, lnodes = area_light_nodes(light, *area) if is_area else light_nodes(light, sun_lux, point_cd)
    nodes += lnodes
    light_extension = "EXT_lights_area" if is_area else "KHR_lights_punctual"
    used = sorted({e for m in materials for e in m.get("extensions", {})} | ({light_extension} if lights else set()))
    doc: Json = {
        "asset": {"version": "2.0", "generator": "chiaro scripts/cycles_scenes.py"},
        "scene": 0,
        "scenes": [{"nodes": list(range(len(nodes)))}],
        "nodes": nodes,
        "meshes": meshes,
        "materials": materials + ([dict(FLOOR_MATERIAL)] if with_floor else []),
        "cameras": [{"type": "perspective", "perspective": {"yfov": CAMERA_YFOV_RAD, "aspectRatio": aspect,
                                                            "znear": 0.1, "zfar": 100.0}}],
        "buffers": [{"byteLength": len(buf.data),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(bytes(buf.data)).decode()}],
        "bufferViews": buf.views,
        "accessors": buf.accessors,
    }
    if used:
        doc["extensionsUsed"] = used
    if lights:
        doc["extensions"] = {light_extension: {"lights": lights}}
    return doc


def parse_floats(text: str) -> list[float]:
    return [float(v) for v in text.split(",")]


def parser() -> argparse.ArgumentParser:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0] if __doc__ else None,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("out", help="the .gltf file to write")
    ap.add_argument("--light", choices=("sun", "point", "environment", "rect", "disk"), required=True)
    ap.add_argument("--base-color", type=parse_floats, default=[0.8, 0.8, 0.8], help="R,G,B (linear)")
    ap.add_argument("--metallic", type=float, default=0.0)
    ap.add_argument("--roughness", type=float, default=0.5)
    ap.add_argument("--param", nargs=2, action="append", default=[], metavar=("NAME", "VALUES"))
    ap.add_argument("--extension", help="a KHR_materials_* name added to every sphere")
    ap.add_argument("--ext-param", nargs=2, action="append", default=[], metavar=("KEY", "VALUES"))
    ap.add_argument("--ext-fixed", help="JSON object of the extension's fixed values")
    ap.add_argument("--materials", help="JSON file: a list of glTF material dicts, one per sphere")
    ap.add_argument("--sun-lux", type=float, default=3.0)
    ap.add_argument("--point-cd", type=float, default=60.0)
    ap.add_argument("--env-nits", type=float, default=1.0)
    ap.add_argument("--area-nits", type=float, default=400.0)
    ap.add_argument("--area-size", type=float, default=1.0)
    ap.add_argument("--area-aspect", type=float, default=2.0)
    ap.add_argument("--area-tilt-deg", type=float, default=30.0)
    ap.add_argument("--area-shadows", choices=("none", "hard", "soft", "pcss"), default="none")
    ap.add_argument("--env-kind", choices=("uniform", "gradient"), default="uniform")
    ap.add_argument("--aspect", type=float, default=1.0, help="the camera's width / height")
    ap.add_argument("--segments", type=int, default=48)
    ap.add_argument("--rings", type=int, default=24)
    ap.add_argument("--extra-extension", nargs=2, action="append", default=[], metavar=("NAME", "JSON"),
                    help="one more extension with these fixed values on every sphere (repeatable)")
    ap.add_argument("--no-floor", action="store_true", help="leave the floor out")
    ap.add_argument("--sphere-shadows", choices=("on", "off"), default="on",
                    help="off: the sphere nodes get extras.castShadows = \"off\"")
    return ap


def main(argv: list[str] | None = None) -> int:
    args = parser().parse_args(argv)
    out = Path(args.out)
    try:
        if len(args.base_color) != 3:
            raise SceneError(f"--base-color: {args.base_color} is not three numbers")
        if args.segments < 3 or args.rings < 2 or args.segments * args.rings > 20000:
            raise SceneError("--segments/--rings: need at least 3 x 2 and at most 20000 quads (16-bit indices)")
        doc = build_scene(spanned_materials(args), args.light, args.sun_lux, args.point_cd, args.aspect,
                          args.segments, args.rings, with_floor=not args.no_floor,
                          sphere_shadows=args.sphere_shadows == "on",
                          area=(args.area_nits, args.area_size, args.area_aspect, args.area_tilt_deg,
                                args.area_shadows))
        out.write_text(json.dumps(doc, indent=1))
        print(f"cycles_scenes: wrote {out} ({len(doc['meshes']) - (0 if args.no_floor else 1)} spheres, {args.light})")
        if args.light == "environment":
            env = out.with_name(out.stem + ".environment.hdr")
            write_environment(env, args.env_kind, args.env_nits)
            print(f"cycles_scenes: wrote {env} ({args.env_kind}, {args.env_nits:g} nits); "
                  f"compare with --environment {env}")
    except (SceneError, OSError) as err:
        print(f"cycles_scenes: {out}: {err}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
