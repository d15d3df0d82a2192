"""Orthographic cameras from Python: Camera.orthographic, a glTF file's orthographic
camera (is_orthographic, ymag, no yfov_deg), and depth and positions that follow parallel
rays, checked against the floor's geometry."""

import os

import numpy as np
import pytest

import chiaro
import scenes

W, H = 96, 72
YMAG = 4.0
ASSET = os.path.join(os.path.dirname(__file__), "..", "..", "tests", "assets", "ShadowsDirectional",
                     "orthographic", "shadows-directional-orthographic.gltf")


def parallel_rays(width, height, eye, target, ymag, up=(0.0, 1.0, 0.0)):
    """Per pixel centre (rows from the top), the origin on the camera's plane through
    `eye`, and the one direction every ray shares."""
    f = (target - eye) / np.linalg.norm(target - eye)
    r = np.cross(f, up); r /= np.linalg.norm(r)
    u = np.cross(r, f)
    xs = ((np.arange(width) + 0.5) / width * 2 - 1) * ymag * width / height
    ys = (1 - (np.arange(height) + 0.5) / height * 2) * ymag
    x, y = np.meshgrid(xs, ys)
    return eye + x[..., None] * r + y[..., None] * u, f


def test_depth_and_positions_follow_parallel_rays_to_the_floor(renderer, scene):
    camera = chiaro.Camera.orthographic(scenes.CAMERA_EYE, scenes.CAMERA_TARGET, ymag=YMAG, zfar=50.0)
    assert camera.is_orthographic and camera.ymag == YMAG and camera.yfov_deg is None
    assert "orthographic" in repr(camera)
    out = renderer.render(scene, camera=camera, width=W, height=H, outputs=("depth", "instance", "position"))
    origins, direction = parallel_rays(W, H, scenes.CAMERA_EYE, scenes.CAMERA_TARGET, YMAG)
    # The ray parameter where each ray meets y = 0 is its view depth (the rays are unit
    # steps along the view axis).
    expected = -origins[..., 1] / direction[1]
    on_floor = out["instance"] == scenes.FLOOR_NODE
    assert on_floor.sum() > 0.5 * W * H
    np.testing.assert_allclose(out["depth"][on_floor], expected[on_floor], rtol=1e-3)
    hit = origins + expected[..., None] * direction
    np.testing.assert_allclose(out["position"][on_floor], hit[on_floor], atol=5e-3)
    # The box seen where parallel rays hit it (bar a pixel centre on its silhouette).
    box = out["instance"] == scenes.BOX_NODE
    assert box.sum() > 50
    assert np.mean(box != scenes.hits_box(origins, direction)) < 0.005


def test_an_orthographic_camera_needs_a_height_and_a_far_plane():
    with pytest.raises(ValueError, match="ymag: 0 is not a positive distance"):
        chiaro.Camera.orthographic((0, 5, 5), (0, 0, 0), ymag=0.0)
    with pytest.raises(ValueError, match="zfar: 0.01 is not beyond znear"):
        chiaro.Camera.orthographic((0, 5, 5), (0, 0, 0), znear=0.05, zfar=0.01)


def test_a_files_orthographic_camera_renders_by_name_and_index(renderer):
    scene = chiaro.load(ASSET)
    plan, perspective = scene.cameras
    assert plan.is_orthographic and plan.yfov_deg is None
    assert plan.ymag == pytest.approx(5.625) and plan.zfar == pytest.approx(100.0)
    assert not perspective.is_orthographic and perspective.ymag is None
    by_name = renderer.render(scene, camera="Plan", width=64, height=36, outputs=("depth",))["depth"]
    by_index = renderer.render(scene, camera=0, width=64, height=36, outputs=("depth",))["depth"]
    given = renderer.render(scene, camera=plan, width=64, height=36, outputs=("depth",))["depth"]
    assert np.array_equal(by_name, by_index) and np.array_equal(by_name, given)
    assert np.isfinite(by_name).sum() > 64 * 36 // 8
