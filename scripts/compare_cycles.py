#!/usr/bin/env python3
"""Renders one glTF scene with Chiaro and with Blender Cycles (an outside judge: a path
tracer written by others) and compares their radiance object by object.

    python3 scripts/compare_cycles.py SCENE.gltf|.glb [--camera N] [--width W --height H]
        [--samples S] [--direct-only] [--single-scatter] [--gltf-materials]
        [--environment FILE.hdr|.exr] [--chiaro-settings FILE.toml] [--strip-range]
        [--min-pixels N] [--erode PX] [--min-nv X] [--filter-width PX] [--threads N] [--seed N]
        [--cycles-arg ARG]... [--out DIR] [--fresh] [--markdown]
        [--chiaro BIN] [--cycles-script FILE] [--bpy-python PYTHON]

Python. The script needs numpy and OpenEXR, which the bpy virtual environment that Cycles
needs has too, so nothing else is installed. Run it with that environment's python, or
with any python3: lacking either module, it starts itself again under the bpy python
(--bpy-python, else $CHIARO_BPY_PYTHON, else target/bpy-venv/bin/python). Set-up:

    python3.11 -m venv target/bpy-venv && target/bpy-venv/bin/pip install bpy numpy OpenEXR

What runs.
- Chiaro: `chiaro render SCENE -o DIR/chiaro.exr --aov instance --no-bake` at the camera
  and size given (--chiaro BIN, else $CHIARO_BIN, else target/release/chiaro). The EXR is
  linear radiance in nits before exposure and tone mapping; the instance AOV names the
  glTF node each pixel shows, and asking for it turns MSAA off, so every pixel is one
  sample at its centre. Settings: --chiaro-settings FILE if given, over these defaults
  (written to DIR/chiaro-settings.toml): `render.ambient = [0, 0, 0]` (Cycles has no
  ambient term) and `lights.range_threshold_lux = 1e-6` (a 1 cd light without a range then
  reaches 1 km, and the window Chiaro puts on it is 1 to within 2e-5 out to 50 m). Chiaro's
  frame holds half floats: radiance over 65504 x 1.2 x 2^EV100 clips (Chiaro warns, and the
  warning is shown), so give bright scenes a `render.exposure_ev100` in the settings.
- Cycles: ../shared/peers/cycles/cycles_render.py beside the repository (--cycles-script)
  with --filter-width 0.01 (pixel centres, as Chiaro's frame; --filter-width changes it),
  --samples, --seed, --threads (default: all cores) and, passed through, --direct-only,
  --single-scatter, --gltf-materials and each --cycles-arg. Its render is kept in DIR and
  reused while the scene, the environment, the Cycles options and the script are
  unchanged (--fresh renders it again).
- Environment: --environment FILE gives both renderers the same equirectangular image of
  radiance in nits, Chiaro by `--environment FILE`, Cycles by `--environment FILE
  --unshadowed` (Chiaro's realtime environment light has no shadows, so no object blocks
  Cycles' either; this also unshadows any punctual light). A settings file whose
  `environment.source` is an image path stands for --environment; `neutral`, `sky`, an
  `intensity` other than 1 and a `rotation_deg` other than 0 are refused (Cycles would
  not see them).
- Light ranges: Blender ignores KHR_lights_punctual `range` (plain inverse square), so a
  scene whose lights have one is refused; --strip-range writes DIR/scene-norange.gltf
  (or .glb), a copy without ranges, and compares that.

What is reported. Luminance is Rec. 709 Y of linear RGB. For each glTF node (or instance
id) seen in at least --min-pixels pixels (default 50; after --erode and --min-nv, below):
its pixels, the pixels compared (those where Cycles' luminance is above 1e-3 x its 99th
percentile over the image's objects, and both are finite), the median of Chiaro / Cycles
luminance over them, the share within 10% (ratio in [0.9, 1.1]) and the mean ratio (the
sum of Chiaro's luminance over the sum of Cycles'). --erode PX drops pixels within PX pixels
(4-neighbourhood steps) of another id or the sky, to judge interiors without silhouettes.
--min-nv X keeps only pixels whose shading normal faces the camera by n.v >= X (from
Chiaro's normal and position AOVs, also written to DIR, and the camera node's world
transform), to judge a material away from grazing views.

Files in DIR (default target/compare-cycles/SCENE-STEM): chiaro.exr, chiaro.instance.exr,
cycles.exr; ratio.png, Chiaro / Cycles luminance in false colour (white at 1, red where
Chiaro is brighter, saturated at 1.5, blue where darker, saturated at 1 / 1.5, dark grey
where nothing is compared; each pixel repeated to make it at least 512 pixels across);
chiaro.png and cycles.png, both images at one linear scale, sRGB encoded, for the eye;
compare.json, the table, the commands, the checkout's commit and the Chiaro binary's
modification time (the binary may predate the checkout); cycles.key, what the kept Cycles
render was made from. Files are written atomically. The table goes to standard output
(--markdown: as a Markdown table). Bad input is an error that names the file; the exit status is 1 then, 0 otherwise.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import os
import shlex
import struct
import subprocess
import sys
import time
import tomllib
import urllib.parse
import zlib
from pathlib import Path
from typing import Any, Sequence, TypedDict

REPO_ROOT = Path(__file__).resolve().parent.parent
DEFAULT_BPY_PYTHON = REPO_ROOT / "target" / "bpy-venv" / "bin" / "python"
DEFAULT_CHIARO = REPO_ROOT / "target" / "release" / "chiaro"
DEFAULT_CYCLES_SCRIPT = REPO_ROOT.parent / "shared" / "peers" / "cycles" / "cycles_render.py"
SKY_ID = 0xFFFFFFFF
LUMA_709 = (0.2126, 0.7152, 0.0722)
CYCLES_ZERO_FRACTION = 1e-3   # of the 99th percentile of Cycles' luminance over objects
WITHIN = 0.10
RATIO_PNG_SATURATES_AT = 1.5
RATIO_PNG_MIN_SIZE_PX = 512
CHIARO_SETTINGS_DEFAULTS: dict[str, dict[str, Any]] = {
    "render": {"ambient": [0.0, 0.0, 0.0]},
    "lights": {"range_threshold_lux": 1e-6},
}
BINARY_WAIT_S = 180.0
REEXEC_MARK = "CHIARO_COMPARE_CYCLES_REEXEC"


def bpy_python(explicit: str | None) -> Path:
    """The python of the bpy virtual environment: --bpy-python, $CHIARO_BPY_PYTHON, the default."""
    return Path(explicit or os.environ.get("CHIARO_BPY_PYTHON") or DEFAULT_BPY_PYTHON)


def reexec_if_needed(argv: list[str]) -> None:
    """Start again under the bpy python when this one lacks numpy or OpenEXR."""
    try:
        import numpy  # noqa: F401
        import OpenEXR  # type: ignore[import-not-found,import-untyped,unused-ignore]  # noqa: F401
        return
    except ImportError as err:
        missing = err.name
    explicit = None
    for i, a in enumerate(argv):
        if a == "--bpy-python" and i + 1 < len(argv):
            explicit = argv[i + 1]
        elif a.startswith("--bpy-python="):
            explicit = a.split("=", 1)[1]
    python = bpy_python(explicit)
    if os.environ.get(REEXEC_MARK) or not python.exists():
        where = "lacks it too" if os.environ.get(REEXEC_MARK) else "does not exist"
        print(f"compare_cycles: this python ({sys.executable}) lacks {missing}, and the bpy "
              f"environment's {python} {where}: see the set-up line in this script's docstring",
              file=sys.stderr)
        sys.exit(1)
    os.environ[REEXEC_MARK] = "1"
    os.execv(str(python), [str(python), str(Path(__file__).resolve()), *argv])


reexec_if_needed(sys.argv[1:])

import numpy as np  # noqa: E402
import numpy.typing as npt  # noqa: E402
import OpenEXR  # type: ignore[import-not-found,import-untyped,unused-ignore]  # noqa: E402

FloatImage = npt.NDArray[np.float32]
IdImage = npt.NDArray[np.uint32]
MaskImage = npt.NDArray[np.bool_]


class CompareError(Exception):
    """A problem with the input or a renderer; the message names the file."""


class ObjectRow(TypedDict):
    """One object's numbers: ratios are Chiaro / Cycles luminance."""
    id: int
    name: str
    pixels: int
    compared: int
    median_ratio: float | None
    within_10pct: float | None
    mean_ratio: float | None


class Report(TypedDict):
    """What compare.json holds."""
    scene: str
    compared_scene: str
    chiaro_commit: str
    chiaro_binary: str
    width: int
    height: int
    camera: int
    samples: int
    environment: str | None
    chiaro_command: list[str]
    cycles_command: list[str]
    cycles_reused: bool
    cycles_zero_below_nits: float
    erode_px: int
    min_nv: float | None
    min_pixels: int
    objects: list[ObjectRow]


# ---------------------------------------------------------------- files


def write_atomic(path: Path, data: bytes) -> None:
    tmp = path.with_name(f".{path.name}.tmp{os.getpid()}")
    tmp.write_bytes(data)
    os.replace(tmp, path)


def read_gltf(path: Path) -> tuple[dict[str, Any], bytes | None]:
    """The JSON document and, for a .glb, its binary chunk."""
    try:
        data = path.read_bytes()
    except OSError as err:
        raise CompareError(f"{path}: cannot read: {err.strerror}")
    try:
        if data[:4] == b"glTF":
            (json_len,) = struct.unpack_from("<I", data, 12)
            doc = json.loads(data[20:20 + json_len])
            rest = data[20 + json_len:]
            binary = None
            if len(rest) >= 8:
                (bin_len, kind) = struct.unpack_from("<II", rest, 0)
                if kind == 0x004E4942:
                    binary = rest[8:8 + bin_len]
            return doc, binary
        return json.loads(data), None
    except (ValueError, struct.error) as err:
        raise CompareError(f"{path}: not a glTF file: {err}")


def glb_bytes(doc: dict[str, Any], binary: bytes | None) -> bytes:
    text = json.dumps(doc).encode()
    text += b" " * (-len(text) % 4)
    chunks = struct.pack("<II", len(text), 0x4E4F534A) + text
    if binary is not None:
        padded = binary + b"\0" * (-len(binary) % 4)
        chunks += struct.pack("<II", len(padded), 0x004E4942) + padded
    return struct.pack("<4sII", b"glTF", 2, 12 + len(chunks)) + chunks


def lights_with_range(doc: dict[str, Any]) -> list[str]:
    lights = doc.get("extensions", {}).get("KHR_lights_punctual", {}).get("lights", [])
    return [f"light {i} ({light.get('name', 'unnamed')})" for i, light in enumerate(lights) if "range" in light]


def copy_without_range(scene: Path, doc: dict[str, Any], binary: bytes | None, out_dir: Path) -> Path:
    """A copy of the scene without light ranges, its relative URIs made absolute."""
    doc = json.loads(json.dumps(doc))
    for light in doc.get("extensions", {}).get("KHR_lights_punctual", {}).get("lights", []):
        light.pop("range", None)
    base = scene.resolve().parent
    for key in ("buffers", "images"):
        for item in doc.get(key, []):
            uri = item.get("uri")
            if uri and not uri.startswith("data:") and not os.path.isabs(uri):
                item["uri"] = str(base / urllib.parse.unquote(uri))
    is_glb = scene.read_bytes()[:4] == b"glTF"
    out = out_dir / ("scene-norange.glb" if is_glb else "scene-norange.gltf")
    write_atomic(out, glb_bytes(doc, binary) if is_glb else json.dumps(doc).encode())
    return out


def read_exr(path: Path) -> dict[str, Any]:
    try:
        with OpenEXR.File(str(path)) as f:
            return {name: np.array(ch.pixels) for name, ch in f.channels().items()}
    except Exception as err:  # OpenEXR raises plain Exceptions
        raise CompareError(f"{path}: cannot read the EXR: {err}")


def read_rgb(path: Path) -> FloatImage:
    """(H, W, 3) float32 linear radiance."""
    ch = read_exr(path)
    if "RGB" in ch:
        rgb = ch["RGB"][..., :3]
    elif all(c in ch for c in "RGB"):
        rgb = np.stack([ch[c] for c in "RGB"], axis=-1)
    else:
        raise CompareError(f"{path}: no RGB channels (has {sorted(ch)})")
    return np.asarray(rgb, dtype=np.float32)


def read_ids(path: Path) -> IdImage:
    """(H, W) uint32 glTF node index per pixel, SKY_ID on the sky."""
    ch = read_exr(path)
    if "Y" not in ch or ch["Y"].dtype != np.uint32:
        raise CompareError(f"{path}: no uint32 Y channel (has {sorted(ch)})")
    return np.asarray(ch["Y"], dtype=np.uint32)


def png_bytes(rgb: npt.NDArray[np.uint8]) -> bytes:
    """An 8-bit RGB PNG of an (H, W, 3) uint8 array."""
    h, w, _ = rgb.shape
    raw = b"".join(b"\0" + rgb[y].tobytes() for y in range(h))

    def chunk(kind: bytes, body: bytes) -> bytes:
        return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body))

    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
            + chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))


# ---------------------------------------------------------------- settings


def toml_value(v: Any) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, (int, float)):
        return repr(v)
    if isinstance(v, str):
        return json.dumps(v)
    if isinstance(v, list):
        return "[" + ", ".join(toml_value(x) for x in v) + "]"
    raise CompareError(f"settings: cannot write {v!r} back to TOML")


def toml_text(table: dict[str, Any], prefix: str = "") -> str:
    """TOML of nested tables of scalars and lists (what Chiaro's settings hold)."""
    scalars = [f"{k} = {toml_value(v)}" for k, v in table.items() if not isinstance(v, dict)]
    text = (f"[{prefix}]\n" if prefix and scalars else "") + "".join(s + "\n" for s in scalars)
    for k, v in table.items():
        if isinstance(v, dict):
            text += toml_text(v, f"{prefix}.{k}" if prefix else k)
    return text


def chiaro_settings(user_file: Path | None) -> tuple[dict[str, Any], Path | None]:
    """The settings Chiaro renders with (the defaults under the user's file) and the
    environment image the file names, if any."""
    settings: dict[str, Any] = json.loads(json.dumps(CHIARO_SETTINGS_DEFAULTS))
    if user_file is None:
        return settings, None
    try:
        user = tomllib.loads(user_file.read_text())
    except OSError as err:
        raise CompareError(f"{user_file}: cannot read: {err.strerror}")
    except tomllib.TOMLDecodeError as err:
        raise CompareError(f"{user_file}: not TOML: {err}")
    for table, values in user.items():
        if isinstance(values, dict):
            settings.setdefault(table, {}).update(values)
        else:
            settings[table] = values
    env = settings.get("environment", {})
    if env.get("intensity", 1.0) != 1.0 or env.get("rotation_deg", 0.0) != 0.0:
        raise CompareError(f"{user_file}: environment.intensity and rotation_deg must stay 1 and 0 "
                           f"(Cycles takes the image as it is)")
    source = env.get("source", "none")
    if source in ("neutral", "sky"):
        raise CompareError(f"{user_file}: environment.source = {source!r} has no Cycles counterpart; "
                           f"give an image")
    image = None
    if source not in ("none", "ambient"):
        image = (user_file.resolve().parent / source).resolve()
        env["source"] = str(image)
    return settings, image


# ---------------------------------------------------------------- renderers


def run(cmd: Sequence[str], what: str) -> None:
    proc = subprocess.run(list(cmd), capture_output=True, text=True)
    if proc.returncode != 0:
        tail = "\n".join((proc.stderr or proc.stdout).strip().splitlines()[-15:])
        raise CompareError(f"{what} failed (exit {proc.returncode}): {shlex.join(cmd)}\n{tail}")
    for line in proc.stderr.splitlines():
        if "warn" in line.lower():
            print(f"  {what}: {line}", file=sys.stderr)


def wait_for(binary: Path) -> None:
    """The Chiaro binary may be briefly missing while it is rebuilt."""
    deadline = time.monotonic() + BINARY_WAIT_S
    while not binary.exists():
        if time.monotonic() > deadline:
            raise CompareError(f"{binary}: no Chiaro binary (build it: cargo build --release)")
        time.sleep(2.0)


def chiaro_command(binary: Path, scene: Path, out_dir: Path, settings: Path, args: argparse.Namespace,
                   environment: Path | None) -> list[str]:
    cmd = [str(binary), "render", str(scene), "-o", str(out_dir / "chiaro.exr"), "--width", str(args.width),
           "--height", str(args.height), "--camera", str(args.camera), "--settings", str(settings),
           "--aov", "instance", "--no-bake"]
    if args.min_nv is not None:
        cmd += ["--aov", "normal", "--aov", "position"]
    if environment is not None:
        cmd += ["--environment", str(environment)]
    return cmd


def cycles_command(python: Path, script: Path, scene: Path, out: Path, args: argparse.Namespace,
                   environment: Path | None) -> list[str]:
    cmd = [str(python), str(script), str(scene), str(out), "--width", str(args.width), "--height",
           str(args.height), "--camera", str(args.camera), "--samples", str(args.samples), "--seed",
           str(args.seed), "--threads", str(args.threads), "--filter-width", str(args.filter_width)]
    for flag in ("direct_only", "single_scatter", "gltf_materials"):
        if getattr(args, flag):
            cmd.append("--" + flag.replace("_", "-"))
    if environment is not None:
        cmd += ["--environment", str(environment), "--unshadowed"]
    return cmd + list(args.cycles_arg)


def cycles_key(cmd: list[str], scene: Path, script: Path, environment: Path | None) -> str:
    """What a Cycles render depends on: its options (less the output path) and the bytes of
    the scene, its buffers and images, the environment and the script."""
    h = hashlib.sha256(json.dumps(cmd[2:3] + cmd[4:]).encode())
    paths = [scene, script] + ([environment] if environment else [])
    doc, _ = read_gltf(scene)
    base = scene.resolve().parent
    for key in ("buffers", "images"):
        for item in doc.get(key, []):
            uri = item.get("uri")
            if uri and not uri.startswith("data:"):
                paths.append(base / urllib.parse.unquote(uri))
    for p in paths:
        try:
            h.update(p.read_bytes())
        except OSError as err:
            raise CompareError(f"{p}: cannot read: {err.strerror}")
    return h.hexdigest()


def render_cycles(cmd: list[str], key: str, out_dir: Path, fresh: bool) -> bool:
    """Renders unless DIR holds a render of the same key; True when one was reused."""
    key_file, exr = out_dir / "cycles.key", out_dir / "cycles.exr"
    if not fresh and exr.exists() and key_file.exists() and key_file.read_text().strip() == key:
        return True
    key_file.unlink(missing_ok=True)
    run(cmd, "cycles")
    write_atomic(key_file, key.encode() + b"\n")
    return False


def binary_note(binary: Path) -> str:
    """The binary and when it was built: the commit is the checkout's, the binary may be older."""
    built = time.strftime("%Y-%m-%d %H:%M:%S UTC", time.gmtime(binary.stat().st_mtime))
    return f"{binary} (modified {built})"


def git_commit() -> str:
    def git(*a: str) -> str:
        p = subprocess.run(["git", "-C", str(REPO_ROOT), *a], capture_output=True, text=True)
        return p.stdout.strip() if p.returncode == 0 else ""
    commit = git("rev-parse", "--short", "HEAD") or "unknown"
    return commit + ("+dirty" if git("status", "--porcelain", "--untracked-files=no") else "")


# ---------------------------------------------------------------- comparison


def luminance(rgb: FloatImage) -> FloatImage:
    return np.asarray(rgb @ np.array(LUMA_709, dtype=np.float32), dtype=np.float32)


def interior(ids: IdImage, erode_px: int) -> MaskImage:
    """Pixels more than erode_px 4-neighbour steps from a pixel of another id."""
    keep = np.ones(ids.shape, dtype=bool)
    for _ in range(erode_px):
        same = keep.copy()
        same[1:, :] &= (ids[1:, :] == ids[:-1, :]) & keep[:-1, :]
        same[:-1, :] &= (ids[:-1, :] == ids[1:, :]) & keep[1:, :]
        same[:, 1:] &= (ids[:, 1:] == ids[:, :-1]) & keep[:, :-1]
        same[:, :-1] &= (ids[:, :-1] == ids[:, 1:]) & keep[:, 1:]
        keep = same
    return keep


def quat_matrix(q: Sequence[float]) -> npt.NDArray[np.float64]:
    x, y, z, w = q
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def local_matrix(node: dict[str, Any]) -> npt.NDArray[np.float64]:
    if "matrix" in node:
        return np.array(node["matrix"], dtype=np.float64).reshape(4, 4).T  # column-major in glTF
    m = np.eye(4)
    m[:3, :3] = quat_matrix(node.get("rotation", [0, 0, 0, 1])) * np.array(node.get("scale", [1, 1, 1]))
    m[:3, 3] = node.get("translation", [0, 0, 0])
    return m


def world_from_camera(doc: dict[str, Any], camera: int, scene: Path) -> npt.NDArray[np.float64]:
    """The world matrix of the first node of the rendered scene (depth first) carrying the camera."""
    nodes = doc.get("nodes", [])
    scenes = doc.get("scenes", [])
    todo = [(i, np.eye(4)) for i in reversed(scenes[doc.get("scene", 0)].get("nodes", []))] if scenes else []
    while todo:
        i, parent = todo.pop()
        world = parent @ local_matrix(nodes[i])
        if nodes[i].get("camera") == camera:
            return world
        todo += [(c, world) for c in reversed(nodes[i].get("children", []))]
    raise CompareError(f"{scene}: no node of the rendered scene carries camera {camera} (needed by --min-nv)")


def facing(doc: dict[str, Any], camera: int, scene: Path, normal_ws: FloatImage,
           position_ws: FloatImage) -> FloatImage:
    """n.v per pixel: the shading normal against the direction to the camera (NaN on the sky)."""
    world = world_from_camera(doc, camera, scene)
    if doc["cameras"][camera].get("type") == "orthographic":
        to_camera = np.broadcast_to(world[:3, 2] / np.linalg.norm(world[:3, 2]), position_ws.shape)
    else:
        to_camera = world[:3, 3] - position_ws.astype(np.float64)
        to_camera = to_camera / np.linalg.norm(to_camera, axis=-1, keepdims=True)
    return np.asarray(np.sum(normal_ws * to_camera, axis=-1), dtype=np.float32)


def node_names(doc: dict[str, Any]) -> dict[int, str]:
    return {i: n.get("name") or f"node {i}" for i, n in enumerate(doc.get("nodes", []))}


def ratio_image(y_chiaro: FloatImage, y_cycles: FloatImage, ids: IdImage) -> tuple[FloatImage, MaskImage, float]:
    """Chiaro / Cycles luminance, where it is judged, and the Cycles threshold (nits) below which not."""
    objects = ids != SKY_ID
    top = float(np.percentile(y_cycles[objects], 99)) if objects.any() else 0.0
    zero = max(CYCLES_ZERO_FRACTION * top, 1e-9)
    valid = objects & np.isfinite(y_chiaro) & np.isfinite(y_cycles) & (y_cycles > zero)
    ratio = np.where(valid, y_chiaro / np.where(valid, y_cycles, 1.0), np.nan).astype(np.float32)
    return ratio, valid, zero


def object_rows(ids: IdImage, ratio: FloatImage, valid: MaskImage, y_chiaro: FloatImage, y_cycles: FloatImage,
                names: dict[int, str], keep: MaskImage, min_pixels: int) -> list[ObjectRow]:
    rows: list[ObjectRow] = []
    for oid in np.unique(ids[keep]):
        oid = int(oid)
        if oid == SKY_ID:
            continue
        mask = keep & (ids == oid)
        pixels = int(mask.sum())
        if pixels < min_pixels:
            continue
        judged = mask & valid
        r = ratio[judged]
        n = int(r.size)
        rows.append(ObjectRow(
            id=oid, name=names.get(oid, f"instance {oid}"), pixels=pixels, compared=n,
            median_ratio=float(np.median(r)) if n else None,
            within_10pct=float(np.mean(np.abs(r - 1.0) <= WITHIN + 1e-7)) if n else None,
            mean_ratio=float(y_chiaro[judged].sum() / y_cycles[judged].sum()) if n else None))
    return rows


def false_colour(ratio: FloatImage, valid: MaskImage) -> npt.NDArray[np.uint8]:
    """White at 1; towards red (Chiaro brighter) or blue (darker), saturated at 1.5 and 1 / 1.5."""
    t = np.clip(np.log(np.maximum(np.where(valid, ratio, 1.0), 1e-6)) / np.log(RATIO_PNG_SATURATES_AT), -1.0, 1.0)
    up, down = np.clip(t, 0, 1), np.clip(-t, 0, 1)
    rgb = np.stack([1.0 - 0.8 * down, 1.0 - 0.8 * (up + down), 1.0 - 0.8 * up], axis=-1)
    rgb[~valid] = 0.15
    return np.asarray(np.round(rgb * 255), dtype=np.uint8)


def enlarged(rgb: npt.NDArray[np.uint8], at_least_px: int = RATIO_PNG_MIN_SIZE_PX) -> npt.NDArray[np.uint8]:
    """Each pixel repeated n x n times, n the smallest whole factor making the image at least
    at_least_px across (1 when it already is)."""
    n = max(1, -(-at_least_px // max(rgb.shape[:2])))
    return np.asarray(np.repeat(np.repeat(rgb, n, axis=0), n, axis=1), dtype=np.uint8)


def preview(rgb: FloatImage, scale: float) -> npt.NDArray[np.uint8]:
    """Linear radiance x scale, clamped and sRGB encoded."""
    x = np.clip(np.nan_to_num(rgb * scale), 0.0, 1.0)
    srgb = np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1 / 2.4) - 0.055)
    return np.asarray(np.round(srgb * 255), dtype=np.uint8)


def fmt(v: float | None, spec: str) -> str:
    return "-" if v is None else format(v, spec)


def markdown(rows: list[ObjectRow]) -> str:
    lines = ["| object | pixels | compared | median | within 10% | mean |", "|---|---:|---:|---:|---:|---:|"]
    for r in rows:
        within = "-" if r["within_10pct"] is None else f"{100 * r['within_10pct']:.1f}%"
        lines.append(f"| {r['name']} | {r['pixels']} | {r['compared']} | {fmt(r['median_ratio'], '.3f')} | "
                     f"{within} | {fmt(r['mean_ratio'], '.3f')} |")
    return "\n".join(lines)


def table(rows: list[ObjectRow]) -> str:
    width = max([len(r["name"]) for r in rows] + [6])
    lines = [f"{'object':<{width}}  {'pixels':>6}  {'compared':>8}  {'median':>7}  {'within 10%':>10}  {'mean':>7}"]
    for r in rows:
        within = "-" if r["within_10pct"] is None else f"{100 * r['within_10pct']:.1f}%"
        lines.append(f"{r['name']:<{width}}  {r['pixels']:>6}  {r['compared']:>8}  "
                     f"{fmt(r['median_ratio'], '.4f'):>7}  {within:>10}  {fmt(r['mean_ratio'], '.4f'):>7}")
    return "\n".join(lines)


# ---------------------------------------------------------------- main


def parser() -> argparse.ArgumentParser:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0] if __doc__ else None,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("scene", type=Path)
    ap.add_argument("--camera", type=int, default=0, help="the glTF camera index (default 0)")
    ap.add_argument("--width", type=int, default=256)
    ap.add_argument("--height", type=int, default=256)
    ap.add_argument("--samples", type=int, default=128, help="Cycles samples per pixel")
    ap.add_argument("--direct-only", action="store_true", help="Cycles: no bounces")
    ap.add_argument("--single-scatter", action="store_true", help="Cycles: single-scattering GGX")
    ap.add_argument("--gltf-materials", action="store_true", help="Cycles: KHR_materials_* as specified")
    ap.add_argument("--environment", type=Path, help="an equirectangular .hdr/.exr both renderers light with")
    ap.add_argument("--chiaro-settings", type=Path, help="Chiaro settings TOML over this script's defaults")
    ap.add_argument("--strip-range", action="store_true", help="compare a copy of the scene without light ranges")
    ap.add_argument("--min-pixels", type=int, default=50)
    ap.add_argument("--erode", type=int, default=0, metavar="PX", help="drop pixels this close to another id")
    ap.add_argument("--min-nv", type=float, metavar="X",
                    help="judge only pixels whose shading normal faces the camera by n.v >= X")
    ap.add_argument("--filter-width", type=float, default=0.01, help="Cycles pixel filter (0.01: pixel centres)")
    ap.add_argument("--threads", type=int, default=os.cpu_count() or 2)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--cycles-arg", action="append", default=[], metavar="ARG",
                    help="passed on to cycles_render.py (repeatable; --cycles-arg=--node-shadow-extras)")
    ap.add_argument("--out", type=Path)
    ap.add_argument("--markdown", action="store_true", help="print the table as Markdown")
    ap.add_argument("--fresh", action="store_true", help="render Cycles again even if DIR holds its render")
    ap.add_argument("--chiaro", type=Path, default=Path(os.environ.get("CHIARO_BIN") or DEFAULT_CHIARO))
    ap.add_argument("--cycles-script", type=Path, default=DEFAULT_CYCLES_SCRIPT)
    ap.add_argument("--bpy-python", help="the bpy environment's python (default $CHIARO_BPY_PYTHON, "
                                         "else target/bpy-venv/bin/python)")
    return ap


def check_inputs(args: argparse.Namespace, doc: dict[str, Any]) -> None:
    if not 1 <= args.width <= 4096 or not 1 <= args.height <= 4096:
        raise CompareError(f"--width/--height: {args.width} x {args.height} is outside 1 to 4096")
    if args.samples < 1 or args.min_pixels < 1 or args.erode < 0:
        raise CompareError("--samples and --min-pixels must be at least 1, --erode at least 0")
    cameras = doc.get("cameras", [])
    if not 0 <= args.camera < len(cameras):
        raise CompareError(f"{args.scene}: no camera {args.camera} (the file has {len(cameras)}; "
                           f"Cycles needs one of the file's)")
    for p, what in ((args.cycles_script, "--cycles-script"), (bpy_python(args.bpy_python), "--bpy-python")):
        if not p.exists():
            raise CompareError(f"{p}: {what} does not exist")
    if args.environment is not None and not args.environment.is_file():
        raise CompareError(f"{args.environment}: --environment: no such file")


def compare(args: argparse.Namespace) -> Report:
    doc, binary = read_gltf(args.scene)
    check_inputs(args, doc)
    out_dir: Path = args.out or REPO_ROOT / "target" / "compare-cycles" / args.scene.stem
    out_dir.mkdir(parents=True, exist_ok=True)

    scene = args.scene
    ranged = lights_with_range(doc)
    if ranged and not args.strip_range:
        raise CompareError(f"{args.scene}: {', '.join(ranged)} has a range, which Blender ignores; "
                           f"remove it or pass --strip-range")
    if ranged:
        scene = copy_without_range(args.scene, doc, binary, out_dir)

    settings, settings_env = chiaro_settings(args.chiaro_settings)
    environment = args.environment.resolve() if args.environment else settings_env
    if environment is not None and not environment.is_file():
        raise CompareError(f"{environment}: the environment image does not exist")
    settings_path = out_dir / "chiaro-settings.toml"
    write_atomic(settings_path, toml_text(settings).encode())

    if not args.direct_only:
        print("compare_cycles: note: without --direct-only Cycles adds bounced light, which Chiaro "
              "(ambient 0, no bake) has not", file=sys.stderr)
    wait_for(args.chiaro)
    ccmd = chiaro_command(args.chiaro, scene, out_dir, settings_path, args, environment)
    python = bpy_python(args.bpy_python)
    ycmd = cycles_command(python, args.cycles_script, scene, out_dir / "cycles.exr", args, environment)
    t0 = time.monotonic()
    run(ccmd, "chiaro" + (f" (settings from {args.chiaro_settings})" if args.chiaro_settings else ""))
    t1 = time.monotonic()
    reused = render_cycles(ycmd, cycles_key(ycmd, scene, args.cycles_script, environment), out_dir, args.fresh)
    t2 = time.monotonic()
    print(f"compare_cycles: chiaro {t1 - t0:.1f} s, cycles "
          f"{'kept from ' + str(out_dir / 'cycles.exr') if reused else f'{t2 - t1:.1f} s'}")

    rgb_chiaro = read_rgb(out_dir / "chiaro.exr")
    rgb_cycles = read_rgb(out_dir / "cycles.exr")
    ids = read_ids(out_dir / "chiaro.instance.exr")
    if rgb_chiaro.shape != rgb_cycles.shape or ids.shape != rgb_chiaro.shape[:2]:
        raise CompareError(f"{out_dir}: image sizes differ: chiaro {rgb_chiaro.shape}, cycles {rgb_cycles.shape}, "
                           f"ids {ids.shape}")
    y_chiaro, y_cycles = luminance(rgb_chiaro), luminance(rgb_cycles)
    ratio, valid, zero = ratio_image(y_chiaro, y_cycles, ids)
    keep = interior(ids, args.erode)
    if args.min_nv is not None:
        nv = facing(doc, args.camera, args.scene, read_rgb(out_dir / "chiaro.normal.exr"),
                    read_rgb(out_dir / "chiaro.position.exr"))
        keep &= np.nan_to_num(nv, nan=-1.0) >= args.min_nv
    rows = object_rows(ids, ratio, valid & keep, y_chiaro, y_cycles, node_names(doc), keep, args.min_pixels)

    write_atomic(out_dir / "ratio.png", png_bytes(enlarged(false_colour(ratio, valid & keep))))
    scale = 0.8 / max(zero / CYCLES_ZERO_FRACTION, 1e-9)
    write_atomic(out_dir / "chiaro.png", png_bytes(preview(rgb_chiaro, scale)))
    write_atomic(out_dir / "cycles.png", png_bytes(preview(rgb_cycles, scale)))
    report = Report(scene=str(args.scene), compared_scene=str(scene), chiaro_commit=git_commit(),
                    chiaro_binary=binary_note(args.chiaro),
                    width=args.width, height=args.height, camera=args.camera, samples=args.samples,
                    environment=str(environment) if environment else None, chiaro_command=ccmd,
                    cycles_command=ycmd, cycles_reused=reused, cycles_zero_below_nits=zero,
                    erode_px=args.erode, min_nv=args.min_nv, min_pixels=args.min_pixels, objects=rows)
    write_atomic(out_dir / "compare.json", (json.dumps(report, indent=1) + "\n").encode())
    print(markdown(rows) if args.markdown else table(rows))
    print(f"compare_cycles: wrote {out_dir}/compare.json, ratio.png, chiaro.exr, cycles.exr")
    return report


def main(argv: list[str] | None = None) -> int:
    args = parser().parse_args(argv)
    try:
        compare(args)
    except CompareError as err:
        print(f"compare_cycles: {err}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
