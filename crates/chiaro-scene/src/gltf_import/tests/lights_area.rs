//! EXT_lights_area: rect and disk lights in, sized by their node's scale, with their
//! defaults and extras; a clear error naming the light and the key for bad values.

use super::{TempDir, invalid_message, load_doc, triangle_doc};
use crate::light::ShadowMode;
use crate::types::{LightKind, LightMode};
use glam::Vec3;
use serde_json::{Value, json};

/// The triangle with `lights` in the extension's root list and one node per entry of
/// `placed` (its light index and its node's extra fields).
fn area_doc(lights: Value, placed: &[(usize, Value)]) -> Value {
    let mut doc = triangle_doc();
    doc["extensionsUsed"] = json!(["EXT_lights_area"]);
    doc["extensionsRequired"] = json!(["EXT_lights_area"]);
    doc["extensions"] = json!({ "EXT_lights_area": { "lights": lights } });
    let mut nodes = vec![json!({ "mesh": 0 })];
    for (light, extra) in placed {
        let mut node = json!({ "extensions": { "EXT_lights_area": { "light": light } } });
        for (key, value) in extra.as_object().unwrap() {
            node[key] = value.clone();
        }
        nodes.push(node);
    }
    doc["scenes"] = json!([{ "nodes": (0..nodes.len()).collect::<Vec<_>>() }]);
    doc["nodes"] = Value::Array(nodes);
    doc
}

#[test]
fn rect_and_disk_lights_load_with_their_sizes_and_defaults() {
    let dir = TempDir::new("area-lights");
    let doc = area_doc(
        json!([
            { "type": "rect", "name": "panel", "intensity": 250.0, "color": [1.0, 0.5, 0.25], "size": 0.5,
              "rect": { "aspect": 4.0 }, "extras": { "shadows": "soft", "mode": "mixed" } },
            { "type": "disk", "size": 0.3 },
            { "type": "rect" }
        ]),
        &[
            (0, json!({ "translation": [0.0, 3.0, 0.0] })),
            (1, json!({ "scale": [1.0, 2.0, 0.5] })),
            (2, json!({ "name": "default rect" })),
        ],
    );
    let scene = load_doc(&dir, &doc).unwrap();
    assert_eq!(scene.lights.len(), 3);
    let panel = &scene.lights[0];
    assert_eq!(panel.name, "panel");
    assert_eq!(panel.kind, LightKind::Rect { width: 2.0, height: 0.5 });
    assert_eq!(panel.intensity, 250.0);
    assert_eq!(panel.color, Vec3::new(1.0, 0.5, 0.25));
    assert_eq!(panel.position(), Vec3::new(0.0, 3.0, 0.0));
    assert_eq!(panel.direction(), Vec3::NEG_Z);
    assert_eq!(panel.shadow.mode, ShadowMode::Soft);
    assert_eq!(panel.mode, LightMode::Mixed);
    assert_eq!(panel.range, None);
    // The node's largest scale sizes the disk; the frame keeps unit axes.
    let disk = &scene.lights[1];
    assert_eq!(disk.kind, LightKind::Disk { diameter: 0.6 });
    assert!((disk.world_from_light.y_axis.truncate().length() - 1.0).abs() < 1e-6);
    assert_eq!(disk.intensity, 1000.0, "nits where the file gives none");
    assert_eq!(disk.shadow.mode, ShadowMode::Pcss, "area lights' shadows are contact-hardening by default");
    let default = &scene.lights[2];
    assert_eq!(default.kind, LightKind::Rect { width: 1.0, height: 1.0 });
    assert_eq!(default.name, "default rect");
    assert_eq!(default.kind.name(), "rect");
    // Far away it is a point of luminance times area.
    assert!((panel.peak_intensity_cd() - 250.0).abs() < 1e-3);
    assert!((disk.peak_intensity_cd() - 1000.0 * std::f32::consts::PI * 0.09).abs() < 1e-2);
}

#[test]
fn bad_area_lights_are_refused_naming_the_light_and_key() {
    let cases: [(Value, &[&str]); 8] = [
        (json!({ "size": 1.0 }), &["EXT_lights_area light 0", "type is missing"]),
        (json!({ "type": "sphere" }), &["EXT_lights_area light 0", "'sphere' is not rect or disk"]),
        (json!({ "type": "rect", "size": 0.0 }), &["size 0 must be positive"]),
        (json!({ "type": "rect", "rect": { "aspect": -2.0 } }), &["rect.aspect -2 must be positive"]),
        (json!({ "type": "disk", "intensity": -5.0 }), &["intensity -5"]),
        (json!({ "type": "disk", "intensity": "bright" }), &["intensity must be a finite number"]),
        (json!({ "type": "rect", "color": [1.0, 2.0] }), &["color must be three numbers"]),
        (json!({ "type": "rect", "extras": { "cookie": { "image": 0 } } }), &["area lights take no cookie"]),
    ];
    for (k, (light, expected)) in cases.into_iter().enumerate() {
        let dir = TempDir::new(&format!("bad-area-{k}"));
        let message = invalid_message(load_doc(&dir, &area_doc(json!([light]), &[(0, json!({}))])));
        for part in expected {
            assert!(message.contains(part), "case {k}: '{message}' lacks '{part}'");
        }
    }
    let dir = TempDir::new("bad-area-index");
    let message = invalid_message(load_doc(&dir, &area_doc(json!([{ "type": "rect" }]), &[(3, json!({}))])));
    assert!(message.contains("light 3 is out of range"), "{message}");
    let dir = TempDir::new("bad-area-scale");
    let doc = area_doc(json!([{ "type": "rect" }]), &[(0, json!({ "scale": [0.0, 0.0, 0.0] }))]);
    assert!(invalid_message(load_doc(&dir, &doc)).contains("no scale"));
}
