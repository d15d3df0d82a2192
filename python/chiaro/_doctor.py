"""What Chiaro finds of Vulkan on this machine, and what to install when it finds nothing."""

from __future__ import annotations

import ctypes
import ctypes.util
import glob
import os
import sys
from typing import List, Optional, Sequence, Tuple

from ._types import DeviceInfo

_ICD_DIRS = [
    "/usr/share/vulkan/icd.d", "/usr/local/share/vulkan/icd.d", "/etc/vulkan/icd.d",
    os.path.expanduser("~/.local/share/vulkan/icd.d"),
]


def _vulkan_loader() -> Optional[str]:
    """The Vulkan loader library that opens, by name; None when none does."""
    names = {"win32": ["vulkan-1.dll"], "darwin": ["libvulkan.1.dylib", "libMoltenVK.dylib"]}
    for name in names.get(sys.platform, ["libvulkan.so.1", "libvulkan.so"]):
        try:
            ctypes.CDLL(name)
            return name
        except OSError:
            continue
    return ctypes.util.find_library("vulkan")


def _icd_files() -> Tuple[List[str], Optional[str]]:
    """The Vulkan drivers' ICD files, and the environment variable that listed them (None:
    found in the usual folders)."""
    for var in ("VK_DRIVER_FILES", "VK_ICD_FILENAMES"):
        if os.environ.get(var):
            return [f for f in os.environ[var].split(os.pathsep) if f], var
    return sorted(f for d in _ICD_DIRS for f in glob.glob(os.path.join(d, "*.json"))), None


def doctor(devices: Optional[Sequence[DeviceInfo]] = None) -> str:
    """A report of the Vulkan loader, the drivers (ICDs) and the adapters found, ending
    with what to do when no device can render, as text of several lines. `devices`: the
    adapters as `chiaro.devices()` lists them (None: asked for here)."""
    from . import _chiaro

    loader = _vulkan_loader()
    icds, var = _icd_files()
    if devices is None:
        devices = _chiaro.adapters()
    lines = ["chiaro %s" % _chiaro.__version__]
    lines.append("Vulkan loader: %s" % (loader or "not found"))
    source = " (from %s)" % var if var else ""
    lines.append("Vulkan drivers (ICD files)%s: %s" % (source, ", ".join(icds) if icds else "none"))
    if devices:
        lines.append("Devices:")
        for d in devices:
            lines.append("  %d: %s (%s, %s, driver %s, PCI %s)" % (
                d["index"], d["name"], d["device_type"], d["backend"], d["driver"] or "?", d["pci_bus_id"] or "none"))
    else:
        lines.append("Devices: none")
    if not devices:
        if sys.platform.startswith("linux"):
            lines.append(
                "No device can render. Install the Vulkan loader and Mesa's CPU driver (lavapipe): "
                "`sudo apt-get install libvulkan1 mesa-vulkan-drivers` on Debian or Ubuntu "
                "(the Chiaro repository's scripts/setup.sh does it), or your GPU vendor's Vulkan driver.")
        elif sys.platform == "darwin":
            lines.append("No device can render: Chiaro uses Metal on macOS; check that this Mac supports Metal.")
        else:
            lines.append("No device can render: install your GPU vendor's current driver (Vulkan or DX12).")
    elif all(d["device_type"] == "cpu" for d in devices):
        lines.append("Only a CPU device: rendering works, slowly. For a GPU, install its vendor's Vulkan driver.")
    return "\n".join(lines)
