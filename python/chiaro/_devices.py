"""Choosing a device: "auto", "cpu", an index into devices(), "pci:<bus id>", or
"cuda:N" (the CUDA ordinal N as this process sees it, matched to its Vulkan adapter by
PCI bus id). Pure functions over the device list, so that they are tested without GPUs."""

from __future__ import annotations

import importlib
import os
import re
import shutil
import subprocess
from typing import Any, List, Mapping, Optional, Sequence, Tuple

from ._chiaro import DeviceError
from ._types import DeviceArg, DeviceInfo

Gpu = Tuple[int, str, Optional[str]]
"""An NVIDIA GPU: its index in the driver's order, its UUID ("GPU-..."), its PCI bus id
(normalized; None when the driver gave none that reads as one)."""

# "auto" prefers a discrete GPU, then an integrated one, then anything but the CPU.
_TYPE_RANK = {"discrete_gpu": 0, "integrated_gpu": 1, "virtual_gpu": 2, "other": 3, "cpu": 4}


def normalize_bus_id(bus_id: str) -> Optional[str]:
    """A PCI bus id as "dddd:bb:dd.f" in lower case ("00000000:01:00.0" from nvidia-smi and
    "0000:01:00.0" from Vulkan both become "0000:01:00.0"); None when it is not one."""
    m = re.fullmatch(r"(?:([0-9a-fA-F]+):)?([0-9a-fA-F]{1,2}):([0-9a-fA-F]{1,2})\.([0-7])", bus_id.strip())
    if not m:
        return None
    domain, bus, device, function = m.groups()
    return "%04x:%02x:%02x.%x" % (int(domain or "0", 16), int(bus, 16), int(device, 16), int(function, 16))


def parse_nvidia_smi(text: str) -> List[Gpu]:
    """nvidia-smi's `--query-gpu=index,uuid,pci.bus_id --format=csv,noheader` lines as
    (index, uuid, bus id) tuples."""
    gpus: List[Gpu] = []
    for line in text.strip().splitlines():
        parts = [p.strip() for p in line.split(",")]
        if len(parts) == 3 and parts[0].isdigit():
            gpus.append((int(parts[0]), parts[1], normalize_bus_id(parts[2])))
    return gpus


def _query_gpus() -> List[Gpu]:
    """NVIDIA GPUs in the driver's order: from NVML (pynvml) when installed, else nvidia-smi."""
    # pynvml is optional and untyped: imported by name, as Any.
    pynvml: Any
    try:
        pynvml = importlib.import_module("pynvml")
    except ImportError:
        pynvml = None
    if pynvml is not None:
        try:
            pynvml.nvmlInit()
            try:
                gpus: List[Gpu] = []
                for i in range(pynvml.nvmlDeviceGetCount()):
                    handle = pynvml.nvmlDeviceGetHandleByIndex(i)
                    uuid = pynvml.nvmlDeviceGetUUID(handle)
                    bus = pynvml.nvmlDeviceGetPciInfo(handle).busId
                    uuid = uuid.decode() if isinstance(uuid, bytes) else uuid
                    bus = bus.decode() if isinstance(bus, bytes) else bus
                    gpus.append((i, uuid, normalize_bus_id(bus)))
                return gpus
            finally:
                pynvml.nvmlShutdown()
        except Exception:  # NVML present but no driver: fall back to nvidia-smi
            pass
    smi = shutil.which("nvidia-smi")
    if smi is None:
        raise DeviceError(
            "cuda devices need NVIDIA's driver: neither NVML (pip install nvidia-ml-py) nor nvidia-smi was found"
        )
    try:
        text = subprocess.run(
            [smi, "--query-gpu=index,uuid,pci.bus_id", "--format=csv,noheader"],
            capture_output=True, text=True, timeout=30, check=True,
        ).stdout
    except (OSError, subprocess.SubprocessError) as e:
        raise DeviceError("nvidia-smi failed: %s" % e) from None
    return parse_nvidia_smi(text)


def cuda_bus_id(ordinal: int, environ: Optional[Mapping[str, str]] = None,
                gpus: Optional[Sequence[Gpu]] = None) -> Optional[str]:
    """The PCI bus id of CUDA device `ordinal` as this process sees it: the ordinal-th
    entry of CUDA_VISIBLE_DEVICES (an index or a UUID prefix) when it is set, else the
    ordinal-th GPU in the driver's (PCI) order, which is CUDA's with
    CUDA_DEVICE_ORDER=PCI_BUS_ID and on machines of one GPU model."""
    environ = os.environ if environ is None else environ
    gpus = _query_gpus() if gpus is None else gpus
    visible = environ.get("CUDA_VISIBLE_DEVICES")
    if visible is None:
        candidates = list(gpus)
    else:
        candidates = []
        for entry in (e.strip() for e in visible.split(",")):
            if entry.isdigit():
                found = [g for g in gpus if g[0] == int(entry)]
            elif entry:
                found = [g for g in gpus if g[1].startswith(entry)]
            else:
                found = []
            if len(found) != 1:
                break  # CUDA ignores the list from the first entry it cannot use
            candidates.append(found[0])
    if ordinal >= len(candidates):
        where = "" if visible is None else " with CUDA_VISIBLE_DEVICES=%r" % visible
        raise DeviceError("cuda:%d: this process sees %d CUDA devices%s" % (ordinal, len(candidates), where))
    return candidates[ordinal][2]


def choose(spec: DeviceArg, devices: Sequence[DeviceInfo], environ: Optional[Mapping[str, str]] = None,
           gpus: Optional[Sequence[Gpu]] = None) -> int:
    """The index into `devices` (dicts as chiaro.devices() returns) that `spec` names
    (None: the CHIARO_DEVICE environment variable's choice, else "auto"); `environ` and
    `gpus` stand in for os.environ and the NVIDIA driver's GPU list in tests."""
    environ = os.environ if environ is None else environ
    if spec is None:
        spec = environ.get("CHIARO_DEVICE") or "auto"
    if isinstance(spec, bool) or not isinstance(spec, (int, str)):
        raise TypeError("device: expected 'auto', 'cpu', an index, 'pci:<bus id>' or 'cuda:N', not %r" % (spec,))
    if not devices:
        from ._doctor import doctor

        raise DeviceError(doctor(devices))
    if isinstance(spec, int) or spec.strip().isdigit():
        index = int(spec)
        if not 0 <= index < len(devices):
            raise DeviceError("device %d: there are %d devices (chiaro.devices())" % (index, len(devices)))
        return index
    spec = spec.strip()
    if spec == "auto":
        return min(devices, key=lambda d: (_TYPE_RANK.get(d["device_type"], 3), d["index"]))["index"]
    if spec == "cpu":
        for d in devices:
            if d["device_type"] == "cpu":
                return d["index"]
        raise DeviceError("device 'cpu': no CPU device (install Mesa's lavapipe: apt-get install mesa-vulkan-drivers)")
    if spec.startswith("pci:") or spec.startswith("cuda:"):
        if spec.startswith("pci:"):
            wanted = normalize_bus_id(spec[4:])
            if wanted is None:
                raise ValueError("device %r: expected a PCI bus id such as 'pci:0000:01:00.0'" % spec)
        else:
            ordinal = spec[5:]
            if not ordinal.isdigit():
                raise ValueError("device %r: expected 'cuda:N' with N a CUDA device ordinal" % spec)
            wanted = cuda_bus_id(int(ordinal), environ, gpus)
        for d in devices:
            if d["pci_bus_id"] and normalize_bus_id(d["pci_bus_id"]) == wanted:
                return d["index"]
        seen = ", ".join("%d: %s (%s)" % (d["index"], d["name"], d["pci_bus_id"] or "no bus id") for d in devices)
        raise DeviceError("device %r: no adapter at PCI bus id %s (adapters: %s)" % (spec, wanted, seen))
    raise ValueError("device %r: expected 'auto', 'cpu', an index, 'pci:<bus id>' or 'cuda:N'" % spec)
