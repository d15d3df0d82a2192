"""The dataset example of docs/python.md runs, resumes, and writes what it says."""

import importlib.util
import os

import numpy as np

EXAMPLE = os.path.join(os.path.dirname(__file__), "..", "examples", "dataset.py")


def load_example():
    spec = importlib.util.spec_from_file_location("dataset_example", EXAMPLE)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_the_dataset_example_writes_samples_and_resumes(tmp_path, scene_path, capsys):
    example = load_example()
    out = str(tmp_path / "ds")
    args = [scene_path, "--samples", "3", "--width", "64", "--height", "48", "--out", out]
    example.main(args)
    files = sorted(os.listdir(out))
    assert files == ["00000.npz", "00001.npz", "00002.npz"]
    sample = np.load(os.path.join(out, files[0]))
    assert sample["rgb"].shape == (48, 64, 3) and sample["depth"].shape == (48, 64)
    assert sample["shadow"].shape == (1, 48, 64) and list(sample["shadow_lights"]) == [2]
    assert set(np.unique(sample["instance"])) <= {0, 1, 0xFFFFFFFF}
    first = {k: sample[k].copy() for k in sample.files}
    capsys.readouterr()
    os.remove(os.path.join(out, files[1]))
    example.main(args)
    assert "1 rendered, 2 already there" in capsys.readouterr().out
    again = np.load(os.path.join(out, files[0]))
    for k, v in first.items():
        np.testing.assert_array_equal(again[k], v)
