"""KHR_materials_variants from Python: load(variant=), Scene.variants, variant and
select_variant, the renderer picking up a switch, and a name the file lacks refused with
the list."""

import json

import numpy as np
import pytest

import chiaro
import scenes

W, H = 96, 72


def write_variant_scene(path):
    """The floor-box-sun scene whose box variant "Blue" paints blue and "Green" green."""
    scenes.write_scene(str(path))
    doc = json.loads(path.read_text())
    materials = doc["materials"]
    for name, color in (("blue", [0.1, 0.2, 0.9, 1.0]), ("green", [0.1, 0.8, 0.1, 1.0])):
        materials.append({"name": name, "pbrMetallicRoughness": {"baseColorFactor": color}})
    box_mesh = doc["nodes"][scenes.BOX_NODE]["mesh"]
    doc["meshes"][box_mesh]["primitives"][0]["extensions"] = {"KHR_materials_variants": {"mappings": [
        {"material": len(materials) - 2, "variants": [0]}, {"material": len(materials) - 1, "variants": [1]}]}}
    doc.setdefault("extensions", {})["KHR_materials_variants"] = {"variants": [{"name": "Blue"}, {"name": "Green"}]}
    doc.setdefault("extensionsUsed", []).append("KHR_materials_variants")
    path.write_text(json.dumps(doc))
    return path


def box_color(renderer, scene):
    camera = chiaro.Camera.look_at(scenes.CAMERA_EYE, scenes.CAMERA_TARGET, yfov_deg=scenes.CAMERA_YFOV_DEG)
    out = renderer.render(scene, camera=camera, width=W, height=H, outputs=("hdr", "instance"))
    box = out["instance"] == scenes.BOX_NODE
    assert box.sum() > 50
    return out["hdr"][box].mean(axis=0)


def test_variants_are_listed_selected_and_rendered(renderer, tmp_path):
    path = write_variant_scene(tmp_path / "variants.gltf")
    scene = chiaro.load(path)
    assert scene.variants == ["Blue", "Green"]
    assert scene.variant is None
    grey = box_color(renderer, scene)
    assert grey.max() < 1.2 * grey.min(), f"the default box is grey: {grey}"
    scene.select_variant("Blue")
    assert scene.variant == "Blue"
    r, g, b = box_color(renderer, scene)
    assert b > 2 * r and b > 2 * g
    blue = chiaro.load(path, variant="Blue")
    np.testing.assert_array_equal(box_color(renderer, blue), box_color(renderer, scene))
    scene.select_variant("Green")
    r, g, b = box_color(renderer, scene)
    assert g > 2 * r and g > 2 * b
    scene.select_variant(None)
    assert scene.variant is None


def test_an_unknown_variant_is_a_value_error_listing_them(tmp_path):
    path = write_variant_scene(tmp_path / "variants.gltf")
    with pytest.raises(ValueError, match="no material variant 'Red'; the scene has: Blue, Green"):
        chiaro.load(path, variant="Red")
    scene = chiaro.load(path)
    with pytest.raises(ValueError, match="the scene has: Blue, Green"):
        scene.select_variant("Red")
    assert scene.variant is None
