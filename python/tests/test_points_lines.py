"""Points and lines from Python: the PointsAndLines test scene's wires draw (one pixel
wide, so a thin share of the image) in the instance output; and a KHR_animation_pointer
light's intensity follows Scene.pose as a node's transform does."""

import base64
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
    # One more buffer holding the keys: times 0 and 2 s, intensities 0 and the file's.
    sun = doc["extensions"]["KHR_lights_punctual"]["lights"][0]
    keys = np.array([0.0, 2.0, 0.0, sun["intensity"]], dtype="<f4").tobytes()
    doc["buffers"].append({"byteLength": len(keys),
                           "uri": "data:application/octet-stream;base64," + base64.b64encode(keys).decode()})
    buffer = len(doc["buffers"]) - 1
    doc["bufferViews"] += [{"buffer": buffer, "byteOffset": 0, "byteLength": 8},
                           {"buffer": buffer, "byteOffset": 8, "byteLength": 8}]
    views = len(doc["bufferViews"])
    doc["accessors"] += [{"bufferView": views - 2, "componentType": 5126, "count": 2, "type": "SCALAR",
                          "min": [0.0], "max": [2.0]},
                         {"bufferView": views - 1, "componentType": 5126, "count": 2, "type": "SCALAR"}]
    accessors = len(doc["accessors"])
    doc["animations"] = [{"samplers": [{"input": accessors - 2, "output": accessors - 1}], "channels": [
        {"sampler": 0, "target": {"path": "pointer", "extensions": {"KHR_animation_pointer": {
            "pointer": "/extensions/KHR_lights_punctual/lights/0/intensity"}}}}]}]
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
