"""The shapes of the dicts Chiaro returns, as `TypedDict`s for type checkers, and the
types its arguments take. At run time they are plain dicts: these classes only describe
them (`chiaro.RenderOutputs` and the others are exported from the package).

numpy is imported for the type checker only, so that `import chiaro` stays as quick as
it was: the annotations name `numpy.typing.NDArray` as text. To evaluate them at run time,
give numpy's names: `typing.get_type_hints(chiaro.RenderOutputs, localns={"np": numpy,
"NDArray": numpy.typing.NDArray})`."""

from __future__ import annotations

import os
from typing import TYPE_CHECKING, Any, Dict, Iterable, List, Optional, Tuple, TypedDict, Union

from ._chiaro import Camera

if TYPE_CHECKING:
    import numpy as np
    from numpy.typing import NDArray

__all__ = [
    "CameraArg", "DeviceArg", "DeviceInfo", "JobsArg", "JobsSummary", "LightComparison", "PathArg",
    "RenderOutputs", "RendererDevice", "SettingsArg", "ShardArg",
]

# Argument types. Aliases are evaluated at run time: typing's constructs that Python 3.9
# knows (Union, not |).
PathArg = Union[str, os.PathLike[str]]
"""A file or folder: a str or an os.PathLike such as pathlib.Path."""
SettingsArg = Union[str, bytes, os.PathLike[str], os.PathLike[bytes], Dict[str, Any], None]
"""A settings.toml path, a dict of its sections ({"render": {"msaa": 1}}), or None (the defaults)."""
DeviceArg = Union[str, int, None]
"""A device: "auto", "cpu", an index into `chiaro.devices()`, "pci:<bus id>" or "cuda:N";
None for the CHIARO_DEVICE environment variable's choice (else "auto")."""
CameraArg = Union[Camera, str, int, None]
"""A render's camera: a `chiaro.Camera`, a glTF camera's name or index, or None (the file's
first camera, else one framing the scene)."""
ShardArg = Union[Tuple[int, int], str, None]
"""A share of a job list: an (index, count) pair, an "I/N" string, or None (every job)."""
JobsArg = Union[str, bytes, os.PathLike[str], os.PathLike[bytes], Iterable[Union[Dict[str, Any], str]]]
"""A job list: a .jsonl file's path, or an iterable of job dicts (or their JSON text)."""


class RenderOutputs(TypedDict, total=False):
    """What `Renderer.render` returns (and `render_many`, per frame): the outputs asked
    for, by name, and `shadow_lights` beside `shadow`. H and W are the image's height and
    width in pixels, L the scene's lights; row 0 is the top of the image."""

    rgb: NDArray[np.uint8]
    """(H, W, 3) tone-mapped sRGB, as `chiaro render` writes PNG."""
    hdr: NDArray[np.float32]
    """(H, W, 3) linear radiance, as the EXR."""
    depth: NDArray[np.float32]
    """(H, W) linear view depth in metres; inf where nothing is hit."""
    normal: NDArray[np.float32]
    """(H, W, 3) world-space unit shading normal; NaN on the sky."""
    position: NDArray[np.float32]
    """(H, W, 3) world-space position in metres; NaN on the sky."""
    instance: NDArray[np.uint32]
    """(H, W) glTF node index of the mesh seen; 0xFFFFFFFF on the sky."""
    label: NDArray[np.uint32]
    """(H, W) the node's `extras.label` (a class id); 0 where none."""
    shadow: NDArray[np.float32]
    """(L, H, W) per light, the realtime shadow attenuation the shading used: 1 lit, 0
    shadowed; NaN on the sky."""
    shadow_lights: List[int]
    """The glTF node indices of the L lights of `shadow`, in its order (present with it)."""
    ao: NDArray[np.float32]
    """(H, W) the ambient occlusion the shading used: 1 open, 0 hidden; 1 on the sky and
    everywhere without `[ambient_occlusion] enabled`."""


class _CoreDevice(TypedDict):
    """The adapter a renderer holds, as the extension describes it."""

    name: str
    """The adapter's name, as its driver reports it."""
    backend: str
    """The graphics API: "vulkan", "metal", "dx12" or "gl"."""
    device_type: str
    """The kind of adapter: "discrete_gpu", "integrated_gpu", "virtual_gpu", "cpu" or "other"."""
    driver: str
    """The driver's name ("" when it gives none)."""
    pci_bus_id: str
    """The PCI bus id, "dddd:bb:dd.f", or "" when the adapter has none (lavapipe)."""


class RendererDevice(_CoreDevice):
    """`Renderer.device`: the adapter in use."""

    index: int
    """Its index into `chiaro.devices()`."""


class DeviceInfo(RendererDevice):
    """One adapter of `chiaro.devices()`."""

    driver_info: str
    """The driver's version text ("" when it gives none)."""
    vendor_id: int
    """The PCI vendor id (0x10de NVIDIA, 0x1002 AMD, 0x8086 Intel; Mesa's software drivers have their own)."""
    device_id: int
    """The PCI device id (0 when there is none)."""


class JobsSummary(TypedDict):
    """What `chiaro.render_jobs` returns: counts of jobs, and each failure's message."""

    done: int
    """Jobs rendered now."""
    skipped: int
    """Jobs whose folder was current already."""
    failed: int
    """Jobs that could not be rendered (each wrote output/<id>.error.json)."""
    errors: Dict[str, str]
    """The failed jobs' messages, by job id."""


class LightComparison(TypedDict):
    """One light's row of `chiaro.compare`: how its realtime shadows agree with a
    ray-traced reference of the same view. Percentages are of the pixels compared; they are
    None for a light that was not compared."""

    node: int
    """The glTF node index that carries the light."""
    light: str
    """The light's name."""
    kind: str
    """The light's type: "directional", "point" or "spot"."""
    compared: int
    """Pixels judged (0 when the light was not compared)."""
    disagree_percent: Optional[float]
    """Pixels where realtime and reference disagree, percent."""
    false_percent: Optional[float]
    """Shadow where the reference has light (acne), percent."""
    missed_percent: Optional[float]
    """Light where the reference has shadow (peter-panning, leaks), percent."""
    not_compared: Optional[str]
    """Why the light was not judged; None when it was."""
    shadow_mask_only: bool
    """Judged by its baked shadow mask alone (no shadow map tile)."""
    visibility_mean_abs: Optional[float]
    """For a "pcss" light: mean |rendered - reference| visibility (0 to 1); else None."""
    visibility_p95_abs: Optional[float]
    """For a "pcss" light: 95th percentile of |rendered - reference| visibility; else None."""
    visibility_far_off_percent: Optional[float]
    """For a "pcss" light: pixels whose visibility is off by more than 0.1, percent; else None."""
    penumbra_mean_abs: Optional[float]
    """For a "pcss" or area light: mean |rendered - reference| visibility over the pixels the
    reference sees partly lit (0.02 to 0.98); else None."""
    penumbra_far_off_percent: Optional[float]
    """For a "pcss" or area light: those pixels off by more than 0.1, percent; else None."""
