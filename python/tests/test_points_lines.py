"""Points and lines from Python: the PointsAndLines test scene's wires draw (one pixel
wide, so a thin share of the image) in the instance output; and a KHR_animation_pointer
light's intensity follows Scene.pose as a node's transform does."""

import json
import os

import numpy as np

import chiaro
import scenes

ASSET = os.path.join(os.path.dirname(__file__), "..", "..", "tests", "assets", "PointsAndLines",
                     "points-and-lines.gltf")
WIRES_NODE = 1


def test_points_and_lines_draw_one_pixel_wide(renderer):
    scene = chiaro.load(ASSET)
    assert scene.triangle_count == 2, "points and lines are not triangles"
    out = renderer.render(scene, width=160, height=120, outputs=("instance", "rgb"))
    wires = out["instance"] == WIRES_NODE
    # The box's edges, the strip, the loop, the rails and 25 points: hundreds of pixels,
    # but thin ones, never a filled area.
    assert 300 < wires.sum() < 0.1 * wires.size
    assert out["rgb"][wires].max() > 0


def test_an_animated_light_intensity_follows_time(renderer, tmp_path):
    path = scenes.write_scene(str(tmp_path / "pulse.gltf"))
    doc = json.loads(open(path).read())
    sun = doc["extensions"]["KHR_lights_punctual"]["lights"][0]
    pointer = "/extensions/KHR_lights_punctual/lights/0/intensity"
    scenes.add_animation(doc, "pulse", [0.0, 2.0], [0.0, sun["intensity"]], "SCALAR",
                         {"path": "pointer", "extensions": {"KHR_animation_pointer": {"pointer": pointer}}})
    doc.setdefault("extensionsUsed", []).append("KHR_animation_pointer")
    with open(path, "w") as f:
        json.dump(doc, f)
    scene = chiaro.load(path)
    camera = chiaro.Camera.look_at(scenes.CAMERA_EYE, scenes.CAMERA_TARGET, yfov_deg=scenes.CAMERA_YFOV_DEG)
    lit = {}
    for t in (0.5, 1.0, 2.0):
        scene.pose(t)
        lit[t] = renderer.render(scene, camera=camera, width=48, height=36, outputs=("hdr",))["hdr"]
    floor = lit[2.0][..., 0] > 1e-3
    assert floor.sum() > 100
    # Intensity grows linearly from 0: a quarter, then half, of the full light (the
    # ambient term adds the same to each, so the differences scale).
    quarter = lit[0.5][..., 0][floor]
    half = lit[1.0][..., 0][floor]
    full = lit[2.0][..., 0][floor]
    np.testing.assert_allclose(full - half, 2.0 * (half - quarter), rtol=2e-2, atol=1e-4)
