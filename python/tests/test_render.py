"""Rendered arrays checked against geometry: depth against the floor plane, ids against
the box, shadows against rays cast towards the sun."""

import json
import os
import threading

import numpy as np
import pytest

import chiaro
import scenes

W, H = 160, 120


def overview():
    return chiaro.Camera.look_at(scenes.CAMERA_EYE, scenes.CAMERA_TARGET, yfov_deg=scenes.CAMERA_YFOV_DEG)


def test_outputs_have_their_shapes_and_types(renderer, scene):
    out = renderer.render(scene, camera=overview(), width=W, height=H, outputs=chiaro.OUTPUTS)
    assert out["rgb"].shape == (H, W, 3) and out["rgb"].dtype == np.uint8
    assert out["hdr"].shape == (H, W, 3) and out["hdr"].dtype == np.float32
    assert out["depth"].shape == (H, W) and out["depth"].dtype == np.float32
    for key in ("normal", "position"):
        assert out[key].shape == (H, W, 3) and out[key].dtype == np.float32
    for key in ("instance", "label"):
        assert out[key].shape == (H, W) and out[key].dtype == np.uint32
    assert out["shadow"].shape == (1, H, W) and out["shadow"].dtype == np.float32
    assert out["shadow_lights"] == [scenes.SUN_NODE]
    assert out["ao"].shape == (H, W) and out["ao"].dtype == np.float32
    # The arrays hold the memory the renderer read back, writable and contiguous.
    assert out["depth"].flags.writeable and out["rgb"].flags.c_contiguous


def test_only_what_is_asked_for_comes_back(renderer, scene):
    out = renderer.render(scene, camera=overview(), width=W, height=H)
    assert set(out) == {"rgb"}
    out = renderer.render(scene, camera=overview(), width=W, height=H, outputs=("instance",))
    assert set(out) == {"instance"}


def test_depth_is_the_distance_along_the_view_axis_to_the_floor(renderer, scene):
    out = renderer.render(scene, camera=overview(), width=W, height=H, outputs=("depth", "instance", "position"))
    rays = scenes.view_rays(W, H, scenes.CAMERA_EYE, scenes.CAMERA_TARGET, scenes.CAMERA_YFOV_DEG)
    # The ray parameter where each pixel's ray meets y = 0 is its view depth (view z is -1).
    expected = -scenes.CAMERA_EYE[1] / rays[..., 1]
    on_floor = out["instance"] == scenes.FLOOR_NODE
    assert on_floor.sum() > 0.5 * W * H
    np.testing.assert_allclose(out["depth"][on_floor], expected[on_floor], rtol=1e-3)
    # Positions agree with the same geometry.
    hit = scenes.CAMERA_EYE + expected[..., None] * rays
    np.testing.assert_allclose(out["position"][on_floor], hit[on_floor], atol=5e-3)
    sky = out["instance"] == 0xFFFFFFFF
    assert np.all(np.isinf(out["depth"][sky])) and np.all(np.isnan(out["position"][sky]))


def test_instance_and_label_name_the_node_whose_geometry_holds_the_pixel(renderer, scene):
    out = renderer.render(scene, camera=overview(), width=W, height=H, outputs=("instance", "label", "position"))
    instance, label, position = out["instance"], out["label"], out["position"]
    on_box = instance == scenes.BOX_NODE
    assert on_box.sum() > 100
    inside = np.all((position >= scenes.BOX_MIN - 1e-3) & (position <= scenes.BOX_MAX + 1e-3), axis=-1)
    assert np.all(inside[on_box]), "a pixel called the box lies outside it"
    above_floor = position[..., 1] > 1e-3
    assert np.array_equal(on_box, above_floor & ~np.isnan(position[..., 1])), "box pixels are not the raised ones"
    assert np.all(label[on_box] == scenes.BOX_LABEL)
    assert np.all(label[instance == scenes.FLOOR_NODE] == 0)
    # The box's centre projects onto a box pixel.
    rays = scenes.view_rays(W, H, scenes.CAMERA_EYE, scenes.CAMERA_TARGET, scenes.CAMERA_YFOV_DEG)
    centre = (scenes.BOX_MIN + scenes.BOX_MAX) / 2 - scenes.CAMERA_EYE
    cos = (rays / np.linalg.norm(rays, axis=-1, keepdims=True)) @ (centre / np.linalg.norm(centre))
    row, col = np.unravel_index(np.argmax(cos), cos.shape)
    assert instance[row, col] == scenes.BOX_NODE


def assert_the_box_shadow_falls_where_rays_to_the_sun_meet_the_box(renderer, scene):
    out = renderer.render(scene, camera=overview(), width=W, height=H, outputs=("shadow", "instance", "position"))
    on_floor = out["instance"] == scenes.FLOOR_NODE
    position = out["position"]
    blocked = scenes.hits_box(position, -scenes.SUN_DIRECTION)
    shadowed = out["shadow"][0] < 0.5
    # Pixels within a few centimetres of the shadow's edge are left out (filtering blurs it).
    near_edge = np.zeros_like(blocked)
    for offset in np.linspace(-0.04, 0.04, 5):
        for axis in (0, 2):
            shifted = position.copy()
            shifted[..., axis] += offset
            near_edge |= scenes.hits_box(shifted, -scenes.SUN_DIRECTION) != blocked
    judged = on_floor & ~near_edge
    assert (judged & blocked).sum() > 50, "the test view must see the shadow"
    disagree = (shadowed != blocked) & judged
    assert disagree.sum() <= 0.005 * judged.sum(), "%d of %d floor pixels disagree" % (disagree.sum(), judged.sum())


def test_the_box_shadow_falls_where_rays_to_the_sun_meet_the_box(renderer, scene):
    assert_the_box_shadow_falls_where_rays_to_the_sun_meet_the_box(renderer, scene)


def test_virtual_shadow_maps_put_the_box_shadow_where_the_rays_do(scene):
    virtual = chiaro.Renderer(device=os.environ.get("CHIARO_TEST_DEVICE", "auto"),
                              settings={"shadows": {"technique": "virtual", "virtual_pool_mb": 32}})
    assert 'technique = "virtual"' in virtual.settings
    assert_the_box_shadow_falls_where_rays_to_the_sun_meet_the_box(virtual, scene)


def test_the_same_frame_twice_gives_identical_arrays(renderer, scene):
    outputs = ("rgb", "hdr", "depth", "instance", "shadow")
    a = renderer.render(scene, camera=overview(), width=W, height=H, outputs=outputs)
    b = renderer.render(scene, camera=overview(), width=W, height=H, outputs=outputs)
    for key in outputs:
        np.testing.assert_array_equal(a[key], b[key], err_msg=key)


def test_four_threads_at_once_give_what_one_gives(renderer, scene):
    cameras = [chiaro.Camera.look_at((3.0 + i, 5.0, 6.0 - i), (0, 0, 0)) for i in range(4)]
    outputs = ("rgb", "depth", "instance")
    alone = [renderer.render(scene, camera=c, width=W, height=H, outputs=outputs) for c in cameras]
    results = [None] * 4
    errors = []

    def work(i):
        try:
            results[i] = renderer.render(scene, camera=cameras[i], width=W, height=H, outputs=outputs)
        except Exception as e:  # reported below
            errors.append(e)

    threads = [threading.Thread(target=work, args=(i,)) for i in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert not errors, errors
    for one, many in zip(alone, results):
        for key in outputs:
            np.testing.assert_array_equal(one[key], many[key], err_msg=key)


def test_render_many_equals_one_render_per_camera(renderer, scene):
    cameras = [chiaro.Camera.look_at((4.0 * np.cos(a), 3.0, 4.0 * np.sin(a)), (0, 0.5, 0)) for a in (0.3, 1.9, 3.5)]
    outputs = ("rgb", "depth", "shadow")
    many = renderer.render_many(scene, cameras=cameras, width=W, height=H, outputs=outputs)
    assert len(many) == 3
    for camera, frame in zip(cameras, many):
        one = renderer.render(scene, camera=camera, width=W, height=H, outputs=outputs)
        for key in outputs:
            np.testing.assert_array_equal(one[key], frame[key], err_msg=key)


def test_cameras_by_name_index_and_default(renderer, scene):
    by_name = renderer.render(scene, camera="overview", width=W, height=H, outputs=("depth",))
    by_index = renderer.render(scene, camera=0, width=W, height=H, outputs=("depth",))
    default = renderer.render(scene, width=W, height=H, outputs=("depth",))
    np.testing.assert_array_equal(by_name["depth"], by_index["depth"])
    np.testing.assert_array_equal(by_name["depth"], default["depth"])
    # The file's camera is the one the tests place by hand.
    camera = scene.cameras[0]
    assert camera.name == "overview"
    np.testing.assert_allclose(camera.eye, scenes.CAMERA_EYE, atol=1e-5)
    np.testing.assert_allclose(camera.yfov_deg, scenes.CAMERA_YFOV_DEG, rtol=1e-5)


def test_moving_a_node_moves_its_pixels(renderer, scene):
    camera = overview()
    before = renderer.render(scene, camera=camera, width=W, height=H, outputs=("instance", "position"))
    moved = np.eye(4)
    moved[:3, 3] = (2.0, 0.0, -1.0)
    scene.set_transform(scenes.BOX_NODE, moved)
    np.testing.assert_allclose(scene.transform(scenes.BOX_NODE), moved, atol=1e-6)
    after = renderer.render(scene, camera=camera, width=W, height=H, outputs=("instance", "position"))
    on_box = after["instance"] == scenes.BOX_NODE
    assert on_box.sum() > 100
    lo, hi = scenes.BOX_MIN + moved[:3, 3], scenes.BOX_MAX + moved[:3, 3]
    p = after["position"][on_box]
    assert np.all((p >= lo - 1e-3) & (p <= hi + 1e-3))
    assert not np.array_equal(before["instance"], after["instance"])


def test_lights_are_live_and_checked(renderer, scene):
    (sun,) = scene.lights
    assert (sun.name, sun.node, sun.kind) == ("sun", scenes.SUN_NODE, "directional")
    assert sun.shadows and sun.shadow_mode == "soft" and sun.mode == "realtime"
    np.testing.assert_allclose(sun.direction, scenes.SUN_DIRECTION, atol=1e-5)
    assert sun.inner_cone_deg is None
    camera = overview()
    lit = renderer.render(scene, camera=camera, width=W, height=H, outputs=("hdr", "shadow", "instance"))
    sun.intensity = 2 * sun.intensity
    assert scene.lights[0].intensity == pytest.approx(10.0)
    brighter = renderer.render(scene, camera=camera, width=W, height=H, outputs=("hdr",))
    floor_lit = (lit["instance"] == scenes.FLOOR_NODE) & (lit["shadow"][0] > 0.99)
    gain = brighter["hdr"][floor_lit].sum() / lit["hdr"][floor_lit].sum()
    assert 1.5 < gain <= 2.0 + 1e-3, gain  # the sun doubles; the ambient term stays
    sun.shadows = False
    unshadowed = renderer.render(scene, camera=camera, width=W, height=H, outputs=("shadow",))
    assert np.all(unshadowed["shadow"][0][lit["instance"] != 0xFFFFFFFF] == 1.0)
    with pytest.raises(ValueError, match="intensity: -1 is negative"):
        sun.intensity = -1.0
    with pytest.raises(ValueError, match="not a spot"):
        sun.outer_cone_deg = 30.0
    with pytest.raises(ValueError, match="'sometimes' is not one of"):
        sun.shadows = "sometimes"


def test_spot_cones_in_the_demo(renderer):
    demo = chiaro.Scene.demo(lights=4)
    spots = [l for l in demo.lights if l.kind == "spot"]
    assert spots and all(l.outer_cone_deg > l.inner_cone_deg for l in spots)
    spots[0].outer_cone_deg = 40.0
    spots[0].inner_cone_deg = 10.0
    (again,) = [l for l in demo.lights if l.node == spots[0].node]
    assert again.outer_cone_deg == pytest.approx(40.0) and again.inner_cone_deg == pytest.approx(10.0)
    with pytest.raises(ValueError, match="cone angles must satisfy"):
        spots[0].inner_cone_deg = 45.0
    assert len(demo.node_names) > len(demo.lights)
    out = renderer.render(demo, width=64, height=48, outputs=("rgb",))
    assert out["rgb"].mean() > 10


def test_spot_shadow_masks_read_lit_outside_the_cone(renderer):
    demo = chiaro.Scene.demo(lights=4)
    camera = chiaro.Camera.look_at((7.0, 6.0, 9.0), (0.0, 0.5, 0.0))
    out = renderer.render(demo, camera=camera, width=W, height=H, outputs=("shadow", "position"))
    position = out["position"]
    checked = 0
    for layer, node in enumerate(out["shadow_lights"]):
        (light,) = [l for l in demo.lights if l.node == node]
        if light.kind != "spot" or not light.shadows:
            continue
        to_surface = position - np.array(light.position)
        cos = (to_surface @ np.array(light.direction)) / np.linalg.norm(to_surface, axis=-1)
        # A degree beyond the outer cone, so rounding at the edge is left out.
        outside = cos < np.cos(np.radians(light.outer_cone_deg + 1.0))
        mask = out["shadow"][layer]
        assert outside.sum() > 100
        assert np.all(mask[outside] == 1.0), "light %s: shadowed outside its cone" % light.name
        assert (mask[~outside & ~np.isnan(cos)] < 0.5).any(), "light %s casts no shadow at all" % light.name
        checked += 1
    assert checked >= 2


def test_depth_alone_equals_the_depth_of_a_full_aov_frame(renderer, scene):
    alone = renderer.render(scene, camera=overview(), width=W, height=H, outputs=("depth",))
    full = renderer.render(scene, camera=overview(), width=W, height=H, outputs=("depth", "normal"))
    np.testing.assert_array_equal(alone["depth"], full["depth"])
    assert np.isinf(alone["depth"]).any() and np.isfinite(alone["depth"]).any()


def test_an_environment_lights_the_scene_and_fills_the_background(scene, tmp_path):
    camera = overview()
    plain = chiaro.Renderer(settings={"render": {"ambient": [0, 0, 0], "msaa": 1}})
    studio = chiaro.Renderer(settings={"render": {"ambient": [0, 0, 0], "msaa": 1},
                                       "environment": {"source": "neutral"}})
    without = plain.render(scene, camera=camera, width=W, height=H, outputs=("hdr", "depth"))
    lit = studio.render(scene, camera=camera, width=W, height=H, outputs=("hdr", "depth"))
    sky = ~np.isfinite(lit["depth"])
    assert sky.any() and (~sky).any()
    # Behind the scene: black without an environment, the studio's grey room with one
    # (scaled to the scene's 5-lux sun, it lights the ground with 1 lux: its darkest grey,
    # underfoot, is about 0.05 nit).
    assert without["hdr"][sky].max() == 0.0 and lit["hdr"][sky].min() > 0.04
    # Every surface gets the studio's light on top of the sun's.
    gain = lit["hdr"][~sky].sum(axis=-1) - without["hdr"][~sky].sum(axis=-1)
    assert (gain > 0.05).mean() > 0.99, (gain > 0.05).mean()
    # Turned half a turn, the studio lights the scene from elsewhere.
    turned = chiaro.Renderer(settings={"render": {"ambient": [0, 0, 0], "msaa": 1},
                                       "environment": {"source": "neutral", "rotation_deg": 180}})
    other = turned.render(scene, camera=camera, width=W, height=H, outputs=("hdr",))
    assert np.abs(other["hdr"] - lit["hdr"]).max() > 0.1


def test_a_files_image_based_light_lights_it_unless_the_settings_say_ambient(scene, tmp_path):
    own = chiaro.load(scenes.write_scene(str(tmp_path / "studio.gltf"), environment=(2.0, 2.0, 2.0)))
    assert own.environment == "EXT_lights_image_based light 0 (grey studio)"
    assert scene.environment is None
    camera = overview()
    settings = {"render": {"ambient": [0, 0, 0], "msaa": 1}}
    lit = chiaro.Renderer(settings=settings).render(own, camera=camera, width=W, height=H, outputs=("hdr", "depth"))
    sky = ~np.isfinite(lit["depth"])
    assert sky.any()
    # The background is the file's environment: 2 nits through 8-bit RGBD.
    np.testing.assert_allclose(lit["hdr"][sky], 2.0, rtol=0.02)
    plain = chiaro.Renderer(settings={**settings, "environment": {"source": "ambient"}})
    dark = plain.render(own, camera=camera, width=W, height=H, outputs=("hdr",))
    assert dark["hdr"][sky].max() == 0.0
    # The environment lights the surfaces too.
    assert (lit["hdr"][~sky].sum(axis=-1) > dark["hdr"][~sky].sum(axis=-1) + 0.05).mean() > 0.99


def test_a_bad_environment_is_an_error_naming_it(scene, tmp_path):
    with pytest.raises(chiaro.SettingsError, match="environment.source"):
        chiaro.Renderer(settings={"environment": {"source": "studio.png"}})
    missing = tmp_path / "missing.hdr"
    r = chiaro.Renderer(settings={"environment": {"source": str(missing)}})
    with pytest.raises(chiaro.RenderError) as e:
        r.render(scene, camera=overview(), width=W, height=H)
    assert str(missing) in str(e.value) and "cannot read environment image" in str(e.value)


def test_area_lights_have_a_type_a_size_and_an_aspect(renderer, scene_path, tmp_path):
    with open(scene_path) as f:
        doc = json.load(f)
    doc["extensionsUsed"].append("EXT_lights_area")
    doc["extensions"]["EXT_lights_area"] = {"lights": [
        {"name": "panel", "type": "rect", "intensity": 400.0, "size": 0.5, "rect": {"aspect": 2.0}},
        {"name": "lamp", "type": "disk", "intensity": 400.0, "size": 0.4}]}
    down = scenes.quat_from_to([0, 0, -1], [0, -1, 0]).tolist()
    doc["nodes"] += [{"name": "panel", "translation": [-1.0, 2.0, 0.0], "rotation": down,
                      "extensions": {"EXT_lights_area": {"light": 0}}},
                     {"name": "lamp", "translation": [1.0, 2.0, 0.0], "rotation": down,
                      "extensions": {"EXT_lights_area": {"light": 1}}}]
    doc["scenes"][0]["nodes"] += [len(doc["nodes"]) - 2, len(doc["nodes"]) - 1]
    path = tmp_path / "area.gltf"
    path.write_text(json.dumps(doc))
    scene = chiaro.load(str(path))
    sun, panel, lamp = scene.lights
    assert (sun.type, panel.type, lamp.type) == ("directional", "rect", "disk")
    assert panel.kind == "rect" and sun.size is None and sun.aspect is None and lamp.aspect is None
    assert panel.size == pytest.approx(0.5) and panel.aspect == pytest.approx(2.0)
    assert lamp.size == pytest.approx(0.4)
    sun.intensity = 0.0
    before = renderer.render(scene, camera=overview(), width=W, height=H, outputs=("hdr",))["hdr"]
    assert before.max() > 0.0
    # Four times the area at the same luminance: more light on the floor.
    panel.size = 1.0
    assert panel.size == pytest.approx(1.0) and panel.aspect == pytest.approx(2.0)
    after = renderer.render(scene, camera=overview(), width=W, height=H, outputs=("hdr",))["hdr"]
    assert after.sum() > 1.5 * before.sum()
    panel.aspect = 1.0
    assert scene.lights[1].aspect == pytest.approx(1.0) and scene.lights[1].size == pytest.approx(1.0)
    with pytest.raises(ValueError, match="not a rect or disk"):
        sun.size = 1.0
    with pytest.raises(ValueError, match="not a rect"):
        lamp.aspect = 2.0
    with pytest.raises(ValueError, match="must be a positive"):
        panel.size = -1.0
