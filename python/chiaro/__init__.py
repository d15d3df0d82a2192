"""Chiaro: real-time lights and shadows for glTF 2.0 scenes, rendered to numpy arrays.

    import chiaro
    scene = chiaro.load("scene.glb")            # or chiaro.Scene.demo(lights=8)
    renderer = chiaro.Renderer()                # device="auto", settings=None
    camera = chiaro.Camera.look_at((4, 3, 6), (0, 0.5, 0))
    out = renderer.render(scene, camera=camera, width=640, height=480,
                          outputs=("rgb", "depth", "instance", "shadow"))

Units are metres, lux (directional lights) and candela (point and spot lights). Arrays are
row-major images, row 0 at the top. See docs/python.md in the Chiaro repository.

The package is typed (PEP 561): `RenderOutputs` describes what a render returns,
`DeviceInfo`, `RendererDevice`, `JobsSummary` and `LightComparison` the other dicts.
"""

from __future__ import annotations

import atexit as _atexit
import json as _json
import os as _os
import shutil as _shutil
import struct as _struct
import sys as _sys
import tempfile as _tempfile
from typing import Iterable as _Iterable
from typing import List as _List
from typing import NoReturn as _NoReturn
from typing import Optional as _Optional
from typing import Sequence as _Sequence
from typing import Tuple as _Tuple


def _quiet_wayland_probe() -> None:
    """Mesa's Vulkan drivers load libwayland, which prints "XDG_RUNTIME_DIR is invalid or
    not set" on every device it opens when the variable is missing, as on servers. As the
    CLI does, point it at a private folder made for this process (there is no Wayland
    session to find then anyway), removed at exit."""
    if not _sys.platform.startswith("linux"):
        return
    current = _os.environ.get("XDG_RUNTIME_DIR")
    if current and _os.path.isdir(current):
        return
    folder = _tempfile.mkdtemp(prefix="chiaro-runtime-")
    _os.environ["XDG_RUNTIME_DIR"] = folder
    _atexit.register(_shutil.rmtree, folder, True)


_quiet_wayland_probe()

from . import _chiaro, _devices  # noqa: E402
from ._chiaro import (  # noqa: E402
    OUTPUTS,
    Camera,
    ChiaroError,
    DeviceError,
    Light,
    RenderError,
    Scene,
    SceneError,
    SettingsError,
)
from ._doctor import doctor  # noqa: E402
from ._types import (  # noqa: E402
    CameraArg,
    DeviceArg,
    DeviceInfo,
    JobsArg,
    JobsSummary,
    LightComparison,
    PathArg,
    RenderOutputs,
    RendererDevice,
    SettingsArg,
    ShardArg,
)

__version__ = _chiaro.__version__

__all__ = [
    "OUTPUTS", "Camera", "ChiaroError", "DeviceError", "DeviceInfo", "JobsSummary", "Light", "LightComparison",
    "RenderError", "RenderOutputs", "Renderer", "RendererDevice", "Scene", "SceneError", "SettingsError", "compare",
    "devices", "doctor", "load", "render_jobs", "__version__",
]


def devices() -> _List[DeviceInfo]:
    """The adapters Chiaro can render with, as dicts: index (what `Renderer(device=...)`
    takes), name, backend, device_type ("discrete_gpu", "integrated_gpu", "virtual_gpu",
    "cpu" or "other"), driver, driver_info, vendor_id, device_id, pci_bus_id."""
    return _chiaro.adapters()


def load(path: PathArg, time: _Optional[float] = None, variant: _Optional[str] = None) -> Scene:
    """Loads a .gltf or .glb file into a `Scene`, posed at `time` seconds of its glTF
    animations (None: the rest pose; see `Scene.pose`), in the KHR_materials_variants
    variant named `variant` (None: the file's default materials; `Scene.variants` lists
    them, `Scene.select_variant` switches). Raises `SceneError` with the file and the
    problem (as `chiaro render` prints it), ValueError for a variant the file lacks."""
    return _chiaro.load(_os.fspath(path), time, variant)


def _settings_args(settings: SettingsArg) -> _Tuple[_Optional[str], _Optional[str]]:
    """`settings=` as the extension takes it: (a settings.toml path, a dict's JSON text)."""
    if settings is None:
        return None, None
    if isinstance(settings, dict):
        try:
            return None, _json.dumps(settings)
        except (TypeError, ValueError) as e:
            raise SettingsError("settings: %s" % e) from None
    if isinstance(settings, (str, bytes, _os.PathLike)):
        return _os.fsdecode(settings), None
    raise TypeError("settings: expected a TOML file's path or a dict, not %s" % type(settings).__name__)


class Renderer:
    """Renders scenes on one device.

    device: "auto" (a discrete GPU, else an integrated one, else a virtual or other
    adapter, else the CPU), "cpu", an index
    into `devices()`, "pci:0000:01:00.0", or "cuda:N" (the CUDA device N as this process
    sees it, after CUDA_VISIBLE_DEVICES, matched by PCI bus id). The CHIARO_DEVICE
    environment variable sets the default. Raises `DeviceError` when no device fits.
    settings: the path of a settings.toml (docs/settings.md) or a dict of the same
    sections, e.g. {"render": {"msaa": 1}, "shadows": {"max_distance": 30.0}}.

    A Renderer may be shared by threads (frames are rendered one at a time, without the
    GIL); it cannot be pickled: make one per process.
    """

    def __init__(self, device: DeviceArg = "auto", settings: SettingsArg = None) -> None:
        if device == "auto" and _os.environ.get("CHIARO_DEVICE"):
            device = None  # the environment's choice
        found = devices()
        index = _devices.choose(device, found)
        path, settings_json = _settings_args(settings)
        self._core = _chiaro._Renderer(index, path, settings_json)
        self._index = index

    @property
    def device(self) -> RendererDevice:
        """The adapter in use: index, name, backend, device_type, driver, pci_bus_id."""
        info: RendererDevice = {**self._core.device, "index": self._index}
        return info

    @property
    def settings(self) -> str:
        """The settings in use, as settings.toml text."""
        return self._core.settings_toml

    def render(self, scene: Scene, camera: CameraArg = None, width: _Optional[int] = None,
               height: _Optional[int] = None, outputs: _Optional[_Sequence[str]] = ("rgb",),
               time: _Optional[float] = None) -> RenderOutputs:
        """Renders one frame of `scene` and returns a dict of numpy arrays, by name (typed
        as `chiaro.RenderOutputs`, which holds the outputs asked for):

        rgb       (H, W, 3) uint8, tone-mapped sRGB, as `chiaro render` writes PNG
        hdr       (H, W, 3) float32 linear radiance, as the EXR
        depth     (H, W) float32 linear view depth in metres, inf where nothing is hit
        normal    (H, W, 3) float32 world-space shading normal, NaN on the sky
        position  (H, W, 3) float32 world-space position in metres, NaN on the sky
        instance  (H, W) uint32 glTF node index of the mesh seen, 0xFFFFFFFF on the sky
        label     (H, W) uint32 the node's extras "label" (a class id), 0 if none
        shadow    (L, H, W) float32 per light, the realtime shadow attenuation the shading
                  used (1 lit, 0 shadowed, NaN on the sky); "shadow_lights" lists the L
                  lights' nodes
        ao        (H, W) float32 the ambient occlusion the shading used (1 open, 0
                  hidden; all 1 without [ambient_occlusion] enabled)

        camera: a `Camera`, a glTF camera's name or index, or None (the file's first
        camera, else one framing the scene). width and height default to the settings'.
        Only the outputs asked for are rendered and read back; asking for anything but
        rgb and hdr renders the frame without MSAA, as the CLI's AOVs do.
        time: seconds into the scene's glTF animations; the scene is posed there first
        (`scene.pose(time)`, which it keeps). None renders the scene as it is posed.
        """
        _pose(scene, time)
        return self._core.render(scene, camera, width, height, outputs)

    def render_many(self, scene: Scene, cameras: _Iterable[CameraArg], width: _Optional[int] = None,
                    height: _Optional[int] = None, outputs: _Optional[_Sequence[str]] = ("rgb",),
                    time: _Optional[float] = None) -> _List[RenderOutputs]:
        """Renders one frame per camera of `cameras` and returns a list of dicts as
        `render` does (`chiaro.RenderOutputs`). Two frames are kept in flight: one is read
        back while the next renders. Every frame is held until the call returns: pass long
        lists in chunks. time: as for `render`, one time for every view."""
        _pose(scene, time)
        return self._core.render_many(scene, cameras, width, height, outputs)

    def compare(self, scene: Scene, camera: CameraArg = None, width: int = 256, height: int = 256,
                time: _Optional[float] = None, edge_band: _Optional[int] = None) -> _List[LightComparison]:
        """See `chiaro.compare`."""
        _pose(scene, time)
        return self._core.compare(scene, camera, width, height, edge_band)

    def __reduce__(self) -> _NoReturn:
        raise TypeError("a chiaro.Renderer cannot be pickled (it holds a GPU device): make one per process")

    def __repr__(self) -> str:
        d = self.device
        return "<chiaro.Renderer on %s (%s, %s)>" % (d["name"], d["device_type"], d["backend"])


def _pose(scene: Scene, time: _Optional[float]) -> None:
    """Poses `scene` at `time` unless time is None or the scene is already there."""
    # The scene keeps its time as a float32: compare in that precision.
    if time is not None and scene.time != _struct.unpack("f", _struct.pack("f", time))[0]:
        scene.pose(time)


def compare(scene: Scene, camera: CameraArg = None, width: int = 256, height: int = 256,
            renderer: _Optional[Renderer] = None, device: DeviceArg = "auto", settings: SettingsArg = None,
            time: _Optional[float] = None, edge_band: _Optional[int] = None) -> _List[LightComparison]:
    """Realtime shadows against a ray-traced reference of the same view, per light, as
    `chiaro compare` prints them: a list of dicts (`chiaro.LightComparison`) with node,
    light (its name), kind, compared (pixels judged), disagree_percent, false_percent
    (shadow where the reference has light: acne), missed_percent (light where it has
    shadow: peter-panning, leaks), not_compared (why a light was not judged, else None)
    and shadow_mask_only; for a light with "pcss" shadows and for rect and disk lights,
    visibility_mean_abs, visibility_p95_abs and visibility_far_off_percent (its rendered
    visibility against the share of its disc or shape the reference sees), and
    penumbra_mean_abs and penumbra_far_off_percent (the same over the reference's
    penumbra alone); None for other lights.
    time: seconds into the scene's animations to pose it at first (None: as it is).
    edge_band: pixels (0 to 64) around the reference's shadow edges left out of the
    disagreement counts, as `chiaro compare --edge-band`; 0 judges every pixel; None:
    the CLI's default, 3."""
    if renderer is None:
        renderer = Renderer(device=device, settings=settings)
    elif settings is not None:
        raise ValueError("compare: give settings to the renderer, not beside it")
    return renderer.compare(scene, camera, width, height, time, edge_band)


def _job_lines(jobs: JobsArg) -> _Tuple[_List[str], str]:
    """The job list as JSON text per job, and its name for messages."""
    if isinstance(jobs, (str, bytes, _os.PathLike)):
        path = _os.fsdecode(jobs)
        with open(path, encoding="utf-8") as f:
            text = f.read()
        # Split as `chiaro batch` does: on newlines only, a trailing carriage return dropped.
        return [line[:-1] if line.endswith("\r") else line for line in text.split("\n")], path
    if isinstance(jobs, dict):
        raise TypeError("jobs: expected a .jsonl file's path or an iterable of job dicts, not one dict")
    lines: _List[str] = []
    for i, job in enumerate(jobs):
        if isinstance(job, str):
            lines.append(job)
        elif isinstance(job, dict):
            try:
                lines.append(_json.dumps(job, allow_nan=False))
            except (TypeError, ValueError) as e:
                raise ValueError("jobs[%d]: %s" % (i, e)) from None
        else:
            raise TypeError("jobs[%d]: expected a dict or a JSON string, not %s" % (i, type(job).__name__))
    return lines, "<jobs>"


def render_jobs(jobs: JobsArg, output: PathArg, *, shard: ShardArg = None, renderer: _Optional[Renderer] = None,
                device: DeviceArg = "auto", settings: SettingsArg = None) -> JobsSummary:
    """Renders a job list into one folder per job under `output`, as `chiaro batch` does,
    and returns {"done": n, "skipped": n, "failed": n, "errors": {id: message}}
    (`chiaro.JobsSummary`).

    jobs: the path of a JSON Lines file (one job object per line, blank lines ignored) or
    an iterable of job dicts (or their JSON text). A job is
        {"id": "a", "scene": "scene.glb", "camera": "Cam" | 0 | {"eye": [x, y, z],
         "target": [x, y, z], "up": [0, 1, 0], "yfov_deg": 45}, "time": 1.5,
         "width": 640, "height": 480, "outputs": ["rgb", "depth"],
         "settings": {"render": {"msaa": 1}}, "seed": 7}
    with every key but id and scene optional: camera defaults to the scene's first camera
    (else one framing the scene); time is seconds into the glTF animations (None: the rest
    pose); width and height are pixels (default the settings'); outputs are names of
    `OUTPUTS` (default ["rgb"]); settings are sections merged over the renderer's settings;
    seed is recorded in meta.json and changes no pixel (the renderer draws nothing at
    random). eye and target are world-space metres, yfov_deg degrees. A relative scene
    path is relative to the current directory.

    Each job writes output/<id>/ (rgb.png, hdr.exr, depth.exr, normal.exr, position.exr,
    instance.exr, label.exr, shadow.<node>.exr as asked, and meta.json) whole or not at
    all. A job whose folder is current (same job, settings, Chiaro version and input file
    hashes) is skipped, so calling again resumes. A failed job writes
    output/<id>.error.json and the others go on; its message is in "errors".

    shard: None (every job), an (index, count) pair or an "I/N" string: the jobs whose
    position among the non-blank lines modulo count is index. renderer: a `Renderer` to
    render on (its settings are the base; the scene it last rendered is uploaded again on
    its next frame); else one is opened with `device` and `settings`, as `Renderer` takes
    them. The GIL is released while the jobs run.

    Raises ValueError for a list that is not jobs (a line that is not a JSON object with a
    safe, unique string "id"; the message names the line) or a bad shard, and OSError when
    `output` cannot be written."""
    lines, source = _job_lines(jobs)
    if renderer is None:
        renderer = Renderer(device=device, settings=settings)
    elif settings is not None:
        raise ValueError("render_jobs: give settings to the renderer, not beside it")
    return _chiaro.render_jobs(lines, _os.fspath(output), source, shard, renderer._core)
