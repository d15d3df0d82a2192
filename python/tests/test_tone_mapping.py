"""[render] tone_mapping from Python: the four display curves, each its own picture, and
an unknown one refused naming the key."""

import pytest

import chiaro
import scenes


def test_tone_mapping_is_a_setting_with_four_curves(tmp_path):
    camera = chiaro.Camera.look_at(scenes.CAMERA_EYE, scenes.CAMERA_TARGET, yfov_deg=scenes.CAMERA_YFOV_DEG)
    scene = chiaro.load(scenes.write_scene(str(tmp_path / "tone.gltf"), sun_lux=20.0))
    images = {}
    for curve in ("pbr-neutral", "aces", "agx", "linear"):
        r = chiaro.Renderer(settings={"render": {"tone_mapping": curve, "msaa": 1}})
        images[curve] = r.render(scene, camera=camera, width=40, height=30, outputs=("rgb",))["rgb"].astype(int)
    for curve in ("aces", "agx", "linear"):
        assert (abs(images[curve] - images["pbr-neutral"]) > 2).sum() > 100, curve
    with pytest.raises(chiaro.SettingsError, match="tone_mapping"):
        chiaro.Renderer(settings={"render": {"tone_mapping": "filmic"}})
