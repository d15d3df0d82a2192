"""The "ao" output: the ambient occlusion the shading used, checked against the scene's
geometry (the box's foot is occluded, open floor is not) and against itself with AO off."""

import numpy as np

import chiaro
import scenes

W, H = 160, 120


def overview():
    return chiaro.Camera.look_at(scenes.CAMERA_EYE, scenes.CAMERA_TARGET, yfov_deg=scenes.CAMERA_YFOV_DEG)


def test_ao_is_one_channel_darker_at_the_box_foot_than_on_open_floor(scene):
    renderer = chiaro.Renderer(settings={"ambient_occlusion": {"enabled": True}})
    out = renderer.render(scene, camera=overview(), width=W, height=H, outputs=("ao", "position", "instance"))
    ao = out["ao"]
    assert ao.shape == (H, W) and ao.dtype == np.float32
    assert np.all((ao >= 0.0) & (ao <= 1.0))
    floor = out["instance"] == scenes.FLOOR_NODE
    position = out["position"]
    # Floor pixels within 10 cm of the box's sides, and those farther than 1.5 m from it.
    outside = np.maximum(np.abs(position[..., [0, 2]]) - 0.5, 0.0)
    gap = np.linalg.norm(outside, axis=-1)
    foot = floor & (gap < 0.1) & (np.max(np.abs(position[..., [0, 2]]), axis=-1) > 0.5)
    open_floor = floor & (gap > 1.5)
    assert foot.sum() > 20 and open_floor.sum() > 1000
    assert ao[foot].mean() < 0.8, ao[foot].mean()
    assert ao[open_floor].mean() > 0.99, ao[open_floor].mean()


def test_ao_is_one_everywhere_when_it_is_off(renderer, scene):
    out = renderer.render(scene, camera=overview(), width=W, height=H, outputs=("ao",))
    assert np.all(out["ao"] == 1.0)
