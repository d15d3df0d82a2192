"""time=: scenes posed at a time of their glTF animations, from Python."""

import json
import math

import numpy as np
import pytest

import chiaro
from scenes import BOX_NODE, add_animation, write_scene


def write_sliding_box(path):
    """The floor-box-sun scene with the box sliding linearly from x = 0 at 0 s to x = 2 at
    2 s (a second, data-URI buffer holds the keys)."""
    write_scene(path)
    doc = json.loads(path.read_text())
    add_animation(doc, "slide", [0.0, 2.0], [0, 0, 0, 2, 0, 0], "VEC3", {"node": BOX_NODE, "path": "translation"})
    path.write_text(json.dumps(doc))
    return path


def test_a_scene_loads_and_poses_at_a_time(tmp_path):
    path = write_sliding_box(tmp_path / "slide.gltf")
    scene = chiaro.load(path, time=0.5)
    assert scene.duration == 2.0
    assert scene.time == 0.5
    assert scene.transform(BOX_NODE)[0, 3] == pytest.approx(0.5)
    scene.pose(1.5)
    assert scene.transform(BOX_NODE)[0, 3] == pytest.approx(1.5)
    scene.pose(None)
    assert scene.time is None and scene.transform(BOX_NODE)[0, 3] == 0.0
    with pytest.raises(ValueError, match="time: NaN is not a finite number of seconds"):
        scene.pose(math.nan)
    with pytest.raises(ValueError, match="time"):
        chiaro.load(path, time=math.inf)
    assert chiaro.load(write_scene(tmp_path / "still.gltf")).duration is None


def test_render_at_a_time_moves_the_box_and_equals_a_scene_loaded_at_that_time(tmp_path, renderer):
    path = write_sliding_box(tmp_path / "slide.gltf")
    scene = chiaro.load(path)
    at_rest = renderer.render(scene, width=96, height=72, outputs=("instance", "depth"))
    moved = renderer.render(scene, width=96, height=72, outputs=("instance", "depth"), time=2.0)
    assert scene.time == 2.0, "render(time=) poses the scene and it stays posed"
    box_columns = lambda frame: np.nonzero((frame["instance"] == BOX_NODE).any(axis=0))[0]
    # The box slid 2 m along +x: its pixels moved right (the camera looks from +x, +z).
    assert box_columns(moved).mean() > box_columns(at_rest).mean() + 5
    loaded = renderer.render(chiaro.load(path, time=2.0), width=96, height=72, outputs=("instance", "depth"))
    np.testing.assert_array_equal(loaded["instance"], moved["instance"])
    np.testing.assert_array_equal(loaded["depth"], moved["depth"])
