//! Punctual lights and cameras: KHR_lights_punctual lights, their node transforms, their
//! cookies and `extras.mode`, and perspective cameras in; `Light` and `Camera` values, or
//! an error naming the light, out.

use super::{TempDir, data_uri, invalid_message, load_doc, png_bytes, triangle_doc};
use crate::error::SceneError;
use crate::types::{ColorSpace, LightKind, LightMode};
use chiaro_math::camera::Projection;
use glam::{Mat4, Vec2, Vec3};
use serde_json::{Value, json};

#[test]
fn a_scaled_light_node_keeps_its_roll_and_loses_its_scale() {
    let dir = TempDir::new("light-scale");
    let mut doc = triangle_doc();
    doc["extensionsUsed"] = json!(["KHR_lights_punctual"]);
    doc["extensions"] = json!({ "KHR_lights_punctual": { "lights": [{ "type": "spot", "spot": {} }] } });
    doc["scenes"] = json!([{ "nodes": [0, 1, 2] }]);
    // A quarter turn about Z (roll only), scaled unevenly.
    let half = std::f32::consts::FRAC_1_SQRT_2;
    doc["nodes"] = json!([
        { "mesh": 0 },
        { "translation": [0.0, 1.0, 0.0], "rotation": [0.0, 0.0, half, half], "scale": [2.0, 3.0, 4.0],
          "extensions": { "KHR_lights_punctual": { "light": 0 } } },
        { "scale": [0.0, 0.0, 0.0], "extensions": { "KHR_lights_punctual": { "light": 0 } } }
    ]);
    let scene = load_doc(&dir, &doc).unwrap();
    let m = scene.lights[0].world_from_light;
    assert!(m.x_axis.truncate().distance(Vec3::Y) < 1e-6, "{m}");
    assert!(m.y_axis.truncate().distance(Vec3::NEG_X) < 1e-6, "{m}");
    assert!(m.z_axis.truncate().distance(Vec3::Z) < 1e-6, "{m}");
    assert_eq!(scene.lights[0].position(), Vec3::Y);
    // A node scaled to nothing still gives a light with a unit direction.
    let collapsed = &scene.lights[1];
    assert!((collapsed.direction().length() - 1.0).abs() < 1e-6);
    assert!(collapsed.world_from_light.is_finite());
}

#[test]
fn punctual_lights_take_their_node_transforms() {
    let dir = TempDir::new("lights");
    let mut doc = triangle_doc();
    let half = std::f32::consts::FRAC_1_SQRT_2;
    doc["extensionsUsed"] = json!(["KHR_lights_punctual"]);
    doc["extensions"] = json!({ "KHR_lights_punctual": { "lights": [
        { "type": "point", "name": "bulb", "color": [1.0, 0.5, 0.25], "intensity": 10.0 },
        { "type": "spot", "intensity": 20.0, "range": 8.0,
          "spot": { "innerConeAngle": 0.2, "outerConeAngle": 0.5 } },
        { "type": "directional", "intensity": 3.0 },
        { "type": "spot", "spot": {} }
    ] } });
    doc["scenes"] = json!([{ "nodes": [0, 1, 2, 3, 4] }]);
    doc["nodes"] = json!([
        { "mesh": 0 },
        { "translation": [1.0, 2.0, 3.0], "extensions": { "KHR_lights_punctual": { "light": 0 } } },
        { "name": "spot node", "rotation": [half, 0.0, 0.0, half],
          "extensions": { "KHR_lights_punctual": { "light": 1 } } },
        { "extensions": { "KHR_lights_punctual": { "light": 2 } } },
        { "extensions": { "KHR_lights_punctual": { "light": 3 } } }
    ]);
    let scene = load_doc(&dir, &doc).unwrap();
    assert_eq!(scene.lights.len(), 4);

    let point = &scene.lights[0];
    assert_eq!(point.name, "bulb");
    assert_eq!(point.node, 1);
    assert_eq!(point.kind, LightKind::Point);
    assert_eq!(point.color, Vec3::new(1.0, 0.5, 0.25));
    assert_eq!(point.intensity, 10.0);
    assert_eq!(point.range, None);
    assert_eq!(point.position(), Vec3::new(1.0, 2.0, 3.0));

    let spot = &scene.lights[1];
    assert_eq!(spot.name, "spot node");
    assert_eq!(spot.kind, LightKind::Spot { inner_cone_rad: 0.2, outer_cone_rad: 0.5 });
    assert_eq!(spot.range, Some(8.0));
    // +90 degrees about X turns -Z into +Y.
    assert!(spot.direction().distance(Vec3::Y) < 1e-6, "{}", spot.direction());
    // The roll comes along: the node's +Y turns into +Z.
    assert!(spot.world_from_light.y_axis.truncate().distance(Vec3::Z) < 1e-6, "{}", spot.world_from_light);

    let sun = &scene.lights[2];
    assert_eq!(sun.kind, LightKind::Directional);
    assert_eq!(sun.direction(), Vec3::NEG_Z);
    assert_eq!(sun.color, Vec3::ONE);
    assert_eq!(sun.name, "light 2");

    let default_spot = &scene.lights[3];
    assert_eq!(default_spot.intensity, 1.0);
    assert_eq!(default_spot.kind, LightKind::Spot { inner_cone_rad: 0.0, outer_cone_rad: std::f32::consts::FRAC_PI_4 });
}

#[test]
fn bad_lights_are_invalid() {
    let dir = TempDir::new("bad-lights");
    for (light, needle) in [
        (json!({ "type": "point", "intensity": -1.0 }), "intensity"),
        (json!({ "type": "point", "range": 0.0 }), "range"),
        (json!({ "type": "spot", "spot": { "innerConeAngle": 0.6, "outerConeAngle": 0.5 } }), "cone"),
        (json!({ "type": "spot", "spot": { "outerConeAngle": 2.0 } }), "cone"),
        (json!({ "type": "point", "range": 2.0, "extras": { "shadows": "pcss", "lightRadius": 3.0 } }), "lightRadius"),
        (json!({ "type": "point", "extras": { "lightRadius": -0.5 } }), "lightRadius"),
        (json!({ "type": "directional", "extras": { "angularDiameter": 200.0 } }), "angularDiameter"),
    ] {
        let mut doc = triangle_doc();
        doc["extensions"] = json!({ "KHR_lights_punctual": { "lights": [light] } });
        doc["nodes"][0]["extensions"] = json!({ "KHR_lights_punctual": { "light": 0 } });
        let message = invalid_message(load_doc(&dir, &doc));
        assert!(message.contains("light 0") && message.contains(needle), "{message}");
    }

    // A hard-edged cone (inner == outer) is tolerated.
    let mut doc = triangle_doc();
    doc["extensions"] = json!({ "KHR_lights_punctual": { "lights": [
        { "type": "spot", "spot": { "innerConeAngle": 0.5, "outerConeAngle": 0.5 } }
    ] } });
    doc["nodes"][0]["extensions"] = json!({ "KHR_lights_punctual": { "light": 0 } });
    let scene = load_doc(&dir, &doc).unwrap();
    let LightKind::Spot { inner_cone_rad, outer_cone_rad } = scene.lights[0].kind else {
        panic!("not a spot light");
    };
    assert_eq!(outer_cone_rad, 0.5);
    assert!(inner_cone_rad < outer_cone_rad && inner_cone_rad > 0.49);
}

#[test]
fn cameras_of_both_kinds_drop_node_scale() {
    let dir = TempDir::new("camera");
    let mut doc = triangle_doc();
    doc["cameras"] = json!([
        { "type": "perspective", "perspective": { "yfov": 0.8, "znear": 0.1, "aspectRatio": 1.5 } },
        { "type": "orthographic", "name": "ortho",
          "orthographic": { "xmag": 1.0, "ymag": 1.0, "znear": 0.1, "zfar": 10.0 } }
    ]);
    doc["scenes"] = json!([{ "nodes": [0, 1, 2] }]);
    doc["nodes"] = json!([
        { "mesh": 0 },
        { "name": "eye", "camera": 0, "translation": [0.0, 1.0, 4.0], "scale": [3.0, 3.0, 3.0] },
        { "camera": 1 }
    ]);
    doc["cameras"][1]["orthographic"]["xmag"] = json!(2.0);
    doc["nodes"][2]["scale"] = json!([2.0, 2.0, 2.0]);
    let scene = load_doc(&dir, &doc).unwrap();
    assert_eq!(scene.cameras.len(), 2);
    let camera = &scene.cameras[0];
    assert_eq!(camera.name, "eye");
    assert_eq!(camera.node, 1);
    assert_eq!(camera.projection, Projection::Perspective { yfov_rad: 0.8 });
    assert_eq!(camera.zfar, None);
    assert_eq!(camera.aspect_ratio, Some(1.5));
    let expected = Mat4::from_translation(Vec3::new(0.0, 1.0, 4.0));
    assert!(camera.world_from_view.abs_diff_eq(expected, 1e-6));
    let ortho = &scene.cameras[1];
    assert_eq!((ortho.name.as_str(), ortho.node), ("ortho", 2));
    assert_eq!(ortho.projection, Projection::Orthographic { ymag: 1.0 });
    assert_eq!((ortho.znear, ortho.zfar, ortho.aspect_ratio), (0.1, Some(10.0), Some(2.0)));
    assert!(ortho.world_from_view.abs_diff_eq(Mat4::IDENTITY, 1e-6), "the node's scale is not the view's");
    assert!(scene.ignored.is_empty(), "{:?}", scene.ignored);
}

#[test]
fn orthographic_cameras_refuse_what_projects_nothing() {
    let dir = TempDir::new("ortho-camera");
    let load = |orthographic: Value| {
        let mut doc = triangle_doc();
        doc["cameras"] = json!([{ "type": "orthographic", "name": "plan", "orthographic": orthographic }]);
        doc["nodes"].as_array_mut().unwrap().push(json!({ "camera": 0 }));
        doc["scenes"][0]["nodes"] = json!([0, 1]);
        load_doc(&dir, &doc)
    };
    let message = |o: Value| load(o).unwrap_err().to_string();
    assert!(
        message(json!({ "xmag": 0.0, "ymag": 1.0, "znear": 0.1, "zfar": 10.0 }))
            .contains("camera 0 (plan): xmag 0 is not a non-zero distance")
    );
    assert!(
        message(json!({ "xmag": 1.0, "ymag": 1.0, "znear": 0.1, "zfar": 0.1 }))
            .contains("camera 0 (plan): zfar 0.1 is not beyond znear 0.1")
    );
    assert!(message(json!({ "xmag": 1.0, "ymag": 1.0, "znear": -1.0, "zfar": 5.0 })).contains("znear -1 is negative"));
    // znear 0 is allowed: it moves out by a millionth of the far plane.
    let scene = load(json!({ "xmag": -2.0, "ymag": 1.0, "znear": 0.0, "zfar": 10.0 })).unwrap();
    assert_eq!((scene.cameras[0].znear, scene.cameras[0].aspect_ratio), (1.0e-5, Some(2.0)));
    assert!(scene.ignored.iter().any(|s| s.contains("xmag -2 is negative")), "{:?}", scene.ignored);
}

/// The triangle lit by one light of `light` (JSON) on a second node, with `images`.
fn cookie_doc(light: Value, images: Value) -> Value {
    let mut doc = triangle_doc();
    doc["extensions"] = json!({ "KHR_lights_punctual": { "lights": [light] } });
    doc["nodes"].as_array_mut().unwrap().push(json!({
        "name": "lamp",
        "translation": [1.0, 2.0, 3.0],
        "extensions": { "KHR_lights_punctual": { "light": 0 } }
    }));
    doc["scenes"][0]["nodes"] = json!([0, 1]);
    doc["images"] = images;
    doc
}

fn png_uri(width: u32, height: u32) -> Value {
    let image = image::RgbaImage::from_fn(width, height, |x, y| image::Rgba([x as u8 * 10, y as u8 * 10, 7, 255]));
    json!({ "uri": data_uri(&png_bytes(image.into())), "mimeType": "image/png" })
}

#[test]
fn cookies_load_for_every_light_type_with_their_images_as_stored() {
    let dir = TempDir::new("cookies");
    let cases = [
        (
            json!({ "type": "directional", "extras": { "cookie": { "image": 1, "size": [2.0, 0.5] } } }),
            Vec2::new(2.0, 0.5),
        ),
        (
            json!({ "type": "spot", "spot": { "outerConeAngle": 0.5 }, "extras": { "cookie": { "image": 1 } } }),
            Vec2::ONE,
        ),
        (json!({ "type": "point", "extras": { "cookie": { "image": 0 } } }), Vec2::ONE),
    ];
    for (light, size) in cases {
        let image = light["extras"]["cookie"]["image"].as_u64().unwrap() as usize;
        let scene = load_doc(&dir, &cookie_doc(light, json!([png_uri(12, 2), png_uri(4, 3)]))).unwrap();
        let cookie = scene.lights[0].cookie.expect("a cookie");
        assert_eq!(cookie.size_m, size);
        // Only the image the cookie uses is decoded, linear, with its texels as stored.
        assert_eq!(scene.images.len(), 1);
        let decoded = &scene.images[cookie.image];
        assert_eq!(decoded.color_space, ColorSpace::Linear);
        let (width, height) = if image == 0 { (12, 2) } else { (4, 3) };
        assert_eq!((decoded.width, decoded.height), (width, height));
        let texel = 4 * (width as usize + 3);
        assert_eq!(&decoded.rgba8[texel..texel + 4], &[30, 10, 7, 255], "texel (3, 1)");
    }
}

#[test]
fn bad_cookies_are_errors_naming_the_light() {
    let dir = TempDir::new("bad-cookies");
    dir.write("broken.png", b"not a png");
    let images = json!([png_uri(12, 2), png_uri(4, 4), { "uri": "broken.png" }, { "uri": "missing.png" }]);
    for (cookie_light, needle) in [
        (
            json!({ "type": "spot", "spot": { "outerConeAngle": 0.5 }, "extras": { "cookie": { "image": 9 } } }),
            "extras.cookie.image: 9 is not an image",
        ),
        (json!({ "type": "point", "extras": { "cookie": { "image": 1 } } }), "six square faces side by side (6:1)"),
        (json!({ "type": "directional", "extras": { "cookie": { "image": 1 } } }), "needs [width, height]"),
        (json!({ "type": "directional", "extras": { "cookie": { "image": 1, "size": [1.0, 0.0] } } }), "both positive"),
        (
            json!({ "type": "spot", "spot": { "outerConeAngle": 0.5 }, "extras": { "cookie": { "image": 2 } } }),
            "broken.png",
        ),
        (
            json!({ "type": "spot", "spot": { "outerConeAngle": 0.5 }, "extras": { "cookie": { "image": 3 } } }),
            "missing.png",
        ),
        (
            json!({ "type": "spot", "spot": { "outerConeAngle": 0.5 }, "extras": { "cookie": { "image": 0, "tiles": 2 } } }),
            "tiles",
        ),
        (json!({ "type": "spot", "spot": { "outerConeAngle": 0.5 }, "extras": { "cookie": 3 } }), "cookie"),
    ] {
        let mut light = cookie_light;
        light["name"] = json!("gobo");
        let message = match load_doc(&dir, &cookie_doc(light, images.clone())) {
            Err(SceneError::Invalid { message, .. }) => message,
            Err(SceneError::Io { .. }) => panic!("a missing cookie image is an invalid scene naming the light"),
            other => panic!("expected an error, got {other:?}"),
        };
        assert!(message.contains("gobo") && message.contains(needle), "{needle}: {message}");
    }
}

#[test]
fn light_mode_comes_from_extras() {
    let dir = TempDir::new("light mode");
    let mut doc = triangle_doc();
    doc["extensionsUsed"] = json!(["KHR_lights_punctual"]);
    doc["extensions"] = json!({ "KHR_lights_punctual": { "lights": [
        { "type": "point", "extras": { "mode": "baked" } },
        { "type": "point" }
    ] } });
    doc["scenes"] = json!([{ "nodes": [0, 1, 2] }]);
    doc["nodes"] = json!([
        { "mesh": 0 },
        { "extensions": { "KHR_lights_punctual": { "light": 0 } } },
        { "extensions": { "KHR_lights_punctual": { "light": 1 } } }
    ]);
    let scene = load_doc(&dir, &doc).unwrap();
    assert_eq!(scene.lights.iter().map(|l| l.mode).collect::<Vec<_>>(), vec![LightMode::Baked, LightMode::Realtime]);
    doc["extensions"]["KHR_lights_punctual"]["lights"][1]["extras"] = json!({ "mode": "never" });
    assert!(invalid_message(load_doc(&dir, &doc)).contains("extras.mode"));
}

#[test]
fn the_node_table_keeps_names_parents_and_places_and_a_parent_moves_what_hangs_below() {
    let dir = TempDir::new("node-table");
    let mut doc = triangle_doc();
    doc["extensionsUsed"] = json!(["KHR_lights_punctual"]);
    doc["extensions"] = json!({ "KHR_lights_punctual": { "lights": [{ "type": "point", "intensity": 5.0 }] } });
    doc["scenes"] = json!([{ "nodes": [1] }]);
    doc["nodes"] = json!([
        { "mesh": 0, "name": "tri", "translation": [0.0, 1.0, 0.0] },
        { "name": "rig", "translation": [2.0, 0.0, 0.0], "children": [0, 2] },
        { "extensions": { "KHR_lights_punctual": { "light": 0 } }, "translation": [0.0, 3.0, 0.0] },
        { "name": "unused", "translation": [9.0, 0.0, 0.0] }
    ]);
    let mut scene = load_doc(&dir, &doc).unwrap();
    let names: Vec<&str> = scene.nodes.iter().map(|n| n.name.as_str()).collect();
    assert_eq!(names, ["tri", "rig", "node 2", "unused"]);
    let parents: Vec<Option<usize>> = scene.nodes.iter().map(|n| n.parent).collect();
    assert_eq!(parents, [Some(1), None, Some(1), None]);
    assert_eq!(scene.nodes[0].world_from_node, Mat4::from_translation(Vec3::new(2.0, 1.0, 0.0)));
    assert_eq!(scene.nodes[3].world_from_node, Mat4::from_translation(Vec3::new(9.0, 0.0, 0.0)));
    let moved = scene.set_node_transform(1, Mat4::from_translation(Vec3::new(2.0, 0.0, 5.0))).unwrap();
    assert_eq!((moved.instances, moved.lights), (1, 1));
    assert!(scene.instances[0].world_from_local.w_axis.truncate().abs_diff_eq(Vec3::new(2.0, 1.0, 5.0), 1e-6));
    assert!(scene.lights[0].position().abs_diff_eq(Vec3::new(2.0, 3.0, 5.0), 1e-6));
}
