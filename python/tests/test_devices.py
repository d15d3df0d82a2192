"""Device choice over made-up device lists: "auto", "cpu", indices, PCI bus ids and CUDA
ordinals (with CUDA_VISIBLE_DEVICES), and the real list and doctor on this machine."""

import pytest

import chiaro
from chiaro import _devices


def device(index, kind, bus=""):
    return {"index": index, "name": "gpu %d" % index, "backend": "vulkan", "device_type": kind,
            "driver": "", "pci_bus_id": bus}


MACHINE = [device(0, "cpu"), device(1, "integrated_gpu", "0000:00:02.0"),
           device(2, "discrete_gpu", "0000:01:00.0"), device(3, "discrete_gpu", "0000:41:00.0")]
# nvidia-smi's order (PCI order) and what it prints for the two discrete GPUs.
SMI = """0, GPU-aaaa1111-0000-0000-0000-000000000000, 00000000:01:00.0
1, GPU-bbbb2222-0000-0000-0000-000000000000, 00000000:41:00.0
"""
GPUS = _devices.parse_nvidia_smi(SMI)


def test_auto_prefers_discrete_then_integrated_then_cpu():
    assert _devices.choose("auto", MACHINE, environ={}) == 2
    assert _devices.choose("auto", MACHINE[:2], environ={}) == 1
    assert _devices.choose("auto", MACHINE[:1], environ={}) == 0
    assert _devices.choose("cpu", MACHINE, environ={}) == 0
    assert _devices.choose(3, MACHINE, environ={}) == 3
    assert _devices.choose("1", MACHINE, environ={}) == 1


def test_chiaro_device_sets_the_default():
    assert _devices.choose(None, MACHINE, environ={"CHIARO_DEVICE": "cpu"}) == 0
    assert _devices.choose(None, MACHINE, environ={}) == 2


def test_pci_bus_ids_match_whatever_their_spelling():
    assert _devices.normalize_bus_id("00000000:41:00.0") == "0000:41:00.0"
    assert _devices.normalize_bus_id("41:00.0") == "0000:41:00.0"
    assert _devices.normalize_bus_id("not a bus") is None
    assert _devices.choose("pci:0000:41:00.0", MACHINE, environ={}) == 3
    assert _devices.choose("pci:00000000:01:00.0", MACHINE, environ={}) == 2


def test_cuda_ordinals_follow_cuda_visible_devices():
    assert GPUS[1] == (1, "GPU-bbbb2222-0000-0000-0000-000000000000", "0000:41:00.0")
    assert _devices.choose("cuda:0", MACHINE, environ={}, gpus=GPUS) == 2
    assert _devices.choose("cuda:1", MACHINE, environ={}, gpus=GPUS) == 3
    # A job scheduled on the second GPU sees it as cuda:0.
    assert _devices.choose("cuda:0", MACHINE, environ={"CUDA_VISIBLE_DEVICES": "1"}, gpus=GPUS) == 3
    assert _devices.choose("cuda:0", MACHINE, environ={"CUDA_VISIBLE_DEVICES": "GPU-bbbb"}, gpus=GPUS) == 3
    with pytest.raises(chiaro.DeviceError, match="sees 1 CUDA devices with CUDA_VISIBLE_DEVICES='1'"):
        _devices.choose("cuda:1", MACHINE, environ={"CUDA_VISIBLE_DEVICES": "1"}, gpus=GPUS)
    # CUDA ignores the list from its first unusable entry on.
    with pytest.raises(chiaro.DeviceError, match="sees 0 CUDA devices"):
        _devices.choose("cuda:0", MACHINE, environ={"CUDA_VISIBLE_DEVICES": "7,0"}, gpus=GPUS)
    with pytest.raises(ValueError, match="cuda:N"):
        _devices.choose("cuda:x", MACHINE, environ={}, gpus=GPUS)


def test_no_device_is_a_device_error_with_the_doctors_advice():
    with pytest.raises(chiaro.DeviceError, match="No device can render"):
        _devices.choose("auto", [], environ={})


def test_this_machine_lists_its_devices_and_the_doctor_names_them(renderer):
    found = chiaro.devices()
    assert found, chiaro.doctor()
    keys = {"index", "name", "backend", "device_type", "driver", "pci_bus_id"}
    assert all(keys <= set(d) for d in found)
    assert [d["index"] for d in found] == list(range(len(found)))
    report = chiaro.doctor()
    assert "Vulkan loader:" in report
    for d in found:
        assert d["name"] in report
    assert renderer.device["name"] in {d["name"] for d in found}
    assert chiaro.__version__.count(".") == 2
