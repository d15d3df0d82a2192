"""Every exception the package raises, with its message: Chiaro's errors as ChiaroError
subclasses, bad arguments as ValueError or TypeError naming them."""

import pickle

import numpy as np
import pytest

import chiaro
import scenes


def test_the_exception_hierarchy():
    for error in (chiaro.SceneError, chiaro.SettingsError, chiaro.DeviceError, chiaro.RenderError):
        assert issubclass(error, chiaro.ChiaroError)
    assert issubclass(chiaro.ChiaroError, Exception)
    assert chiaro.SceneError.__module__ == "chiaro"


def test_a_missing_file_is_a_scene_error_naming_it(tmp_path):
    missing = tmp_path / "missing.gltf"
    with pytest.raises(chiaro.SceneError) as e:
        chiaro.load(missing)
    assert str(e.value).startswith(str(missing) + ": cannot read file")


def test_broken_gltf_is_a_scene_error_with_the_problem(tmp_path):
    broken = tmp_path / "broken.gltf"
    broken.write_text('{"asset": {"version": "2.0"}, "nodes": [{"mesh": 5}], "scenes": [{"nodes": [0]}]}')
    with pytest.raises(chiaro.SceneError) as e:
        chiaro.load(broken)
    assert str(e.value).startswith(str(broken) + ": "), str(e.value)
    not_json = tmp_path / "not.gltf"
    not_json.write_text("{ this is not json")
    with pytest.raises(chiaro.SceneError, match="not a valid glTF file"):
        chiaro.load(not_json)


def test_a_node_label_that_is_not_an_integer_is_refused(tmp_path):
    path = scenes.write_scene(str(tmp_path / "bad_label.gltf"), box_label="wall")
    with pytest.raises(chiaro.SceneError, match=r"node 1 \(box\)"):
        chiaro.load(path)


def test_bad_settings_are_settings_errors(tmp_path):
    with pytest.raises(chiaro.SettingsError, match="msaa"):
        chiaro.Renderer(settings={"render": {"msaa": 3}})
    with pytest.raises(chiaro.SettingsError, match="no_such_section"):
        chiaro.Renderer(settings={"no_such_section": {"x": 1}})
    toml = tmp_path / "settings.toml"
    toml.write_text("[shadows]\nmax_distance = -4.0\n")
    with pytest.raises(chiaro.SettingsError) as e:
        chiaro.Renderer(settings=toml)
    assert str(toml) in str(e.value)
    with pytest.raises(chiaro.SettingsError, match="cannot read"):
        chiaro.Renderer(settings=tmp_path / "absent.toml")
    with pytest.raises(TypeError, match="settings"):
        chiaro.Renderer(settings=42)


def test_settings_from_a_dict_are_used(scene):
    r = chiaro.Renderer(settings={"render": {"msaa": 1, "width": 40, "height": 30}})
    assert "msaa = 1" in r.settings
    assert r.render(scene, camera=0)["rgb"].shape == (30, 40, 3)


def test_bad_devices_are_device_errors_or_value_errors():
    count = len(chiaro.devices())
    with pytest.raises(chiaro.DeviceError, match="there are %d devices" % count):
        chiaro.Renderer(device=count)
    with pytest.raises(chiaro.DeviceError, match="no adapter at PCI bus id 0000:7f:1f.7"):
        chiaro.Renderer(device="pci:0000:7f:1f.7")
    with pytest.raises(ValueError, match="expected 'auto'"):
        chiaro.Renderer(device="tpu")
    with pytest.raises(TypeError, match="device"):
        chiaro.Renderer(device=1.5)


def test_bad_render_arguments_name_the_argument(renderer, scene):
    with pytest.raises(ValueError, match="outputs: 'colour' is not one of rgb, hdr"):
        renderer.render(scene, outputs=("colour",))
    with pytest.raises(TypeError, match="outputs"):
        renderer.render(scene, outputs=3)
    with pytest.raises(ValueError, match="width: 0 is not between 1 and 16384"):
        renderer.render(scene, width=0, height=10)
    with pytest.raises(ValueError, match="height: -5"):
        renderer.render(scene, width=10, height=-5)
    with pytest.raises(ValueError, match=r"no camera 'nope' in the scene \(cameras: 0: overview\)"):
        renderer.render(scene, camera="nope", width=8, height=8)
    with pytest.raises(ValueError, match="no camera '3'"):
        renderer.render(scene, camera=3, width=8, height=8)
    with pytest.raises(TypeError, match="camera: expected a chiaro.Camera"):
        renderer.render(scene, camera=[1, 2, 3], width=8, height=8)
    with pytest.raises(TypeError, match="cameras: expected a sequence"):
        renderer.render_many(scene, cameras="overview", width=8, height=8)
    with pytest.raises(TypeError):
        renderer.render("scene.gltf")


def test_bad_cameras_and_transforms_are_value_errors(scene):
    with pytest.raises(ValueError, match="eye and target are the same point"):
        chiaro.Camera.look_at((1, 2, 3), (1, 2, 3))
    with pytest.raises(ValueError, match="parallel"):
        chiaro.Camera.look_at((0, 5, 0), (0, 0, 0))
    with pytest.raises(ValueError, match="yfov_deg: 180"):
        chiaro.Camera.look_at((0, 5, 5), (0, 0, 0), yfov_deg=180)
    with pytest.raises(ValueError, match="no node 99 in the scene"):
        scene.set_transform(99, np.eye(4))
    with pytest.raises(ValueError, match="cannot be inverted"):
        scene.set_transform(scenes.BOX_NODE, np.diag([0.0, 0.0, 0.0, 1.0]))
    with pytest.raises(ValueError, match=r"expected shape \(4, 4\)"):
        scene.set_transform(scenes.BOX_NODE, np.eye(3))


def test_renderers_and_scenes_refuse_to_be_pickled(renderer, scene):
    with pytest.raises(TypeError, match="make one per process"):
        pickle.dumps(renderer)
    with pytest.raises(TypeError, match="cannot be pickled"):
        pickle.dumps(scene)


def test_a_transposed_matrix_and_too_many_shadow_layers_are_value_errors(renderer, scene):
    moved = np.eye(4)
    moved[:3, 3] = (1.0, 0.0, 0.0)
    with pytest.raises(ValueError, match=r"not affine.*\(transposed\?\)"):
        scene.set_transform(scenes.BOX_NODE, moved.T)
    with pytest.raises(ValueError, match="node: -1 is not a node index"):
        scene.set_transform(-1, moved)
    with pytest.raises(ValueError, match="lights: -1 is not between 0 and 65536"):
        chiaro.Scene.demo(lights=-1)
    crowded = chiaro.Scene.demo(lights=65536)
    with pytest.raises(ValueError, match="'shadow' takes one layer per light"):
        renderer.render(crowded, width=8, height=8, outputs=("shadow",))
