//! `--time`: a scene made here, animated, rendered at a time equals the same scene with the
//! sampled transforms written as static nodes, in HDR (EXR within 1e-5); a skinned strip
//! equals its hand-posed copy.

mod common;

use base64::Engine as _;
use common::{chiaro, read_exr_channels};
use glam::{Quat, Vec3};
use serde_json::{Value, json};
use std::path::Path;

/// A glTF document with one embedded buffer that accessors are appended to.
struct Doc {
    json: Value,
    bytes: Vec<u8>,
}

impl Doc {
    fn new() -> Doc {
        let json = json!({
            "asset": { "version": "2.0" }, "scene": 0, "scenes": [{ "nodes": [] }], "nodes": [],
            "meshes": [], "accessors": [], "bufferViews": [],
            "cameras": [{ "type": "perspective", "perspective": { "yfov": 0.9, "znear": 0.1 } }],
            "extensionsUsed": ["KHR_lights_punctual"],
            "extensions": { "KHR_lights_punctual": { "lights": [
                { "type": "spot", "intensity": 400.0, "spot": { "outerConeAngle": 0.9 }, "extras": { "shadows": "soft" } },
                { "type": "directional", "intensity": 2.0, "extras": { "shadows": "soft" } }
            ] } }
        });
        Doc { json, bytes: Vec::new() }
    }

    fn accessor(
        &mut self,
        data: Vec<u8>,
        component: u32,
        count: usize,
        ty: &str,
        bounds: Option<(Vec3, Vec3)>,
    ) -> usize {
        let offset = self.bytes.len();
        self.bytes.extend(&data);
        while !self.bytes.len().is_multiple_of(4) {
            self.bytes.push(0);
        }
        let views = self.json["bufferViews"].as_array_mut().unwrap();
        views.push(json!({ "buffer": 0, "byteOffset": offset, "byteLength": data.len() }));
        let mut accessor =
            json!({ "bufferView": views.len() - 1, "componentType": component, "count": count, "type": ty });
        if let Some((min, max)) = bounds {
            accessor["min"] = json!(min.to_array());
            accessor["max"] = json!(max.to_array());
        }
        let accessors = self.json["accessors"].as_array_mut().unwrap();
        accessors.push(accessor);
        accessors.len() - 1
    }

    fn floats(&mut self, values: &[f32], ty: &str) -> usize {
        let width = match ty {
            "SCALAR" => 1,
            "VEC3" => 3,
            "VEC4" => 4,
            _ => 16,
        };
        let bytes = values.iter().flat_map(|v| v.to_le_bytes()).collect();
        self.accessor(bytes, 5126, values.len() / width, ty, None)
    }

    fn positions(&mut self, points: &[Vec3]) -> usize {
        let min = points.iter().copied().fold(Vec3::splat(f32::MAX), Vec3::min);
        let max = points.iter().copied().fold(Vec3::splat(f32::MIN), Vec3::max);
        let bytes = points.iter().flat_map(|p| p.to_array()).flat_map(f32::to_le_bytes).collect();
        self.accessor(bytes, 5126, points.len(), "VEC3", Some((min, max)))
    }

    fn indices(&mut self, indices: &[u16]) -> usize {
        let bytes = indices.iter().flat_map(|i| i.to_le_bytes()).collect();
        self.accessor(bytes, 5123, indices.len(), "SCALAR", None)
    }

    fn mesh(&mut self, primitive: Value) -> usize {
        let meshes = self.json["meshes"].as_array_mut().unwrap();
        meshes.push(json!({ "primitives": [primitive] }));
        meshes.len() - 1
    }

    /// Adds a node (a root unless `root` is false) and returns its index.
    fn node(&mut self, node: Value, root: bool) -> usize {
        let nodes = self.json["nodes"].as_array_mut().unwrap();
        nodes.push(node);
        let index = nodes.len() - 1;
        if root {
            self.json["scenes"][0]["nodes"].as_array_mut().unwrap().push(json!(index));
        }
        index
    }

    /// The floor (8 m square at y = 0) and a camera looking down at it from the front.
    fn stage(&mut self) {
        let floor = self.positions(&[
            Vec3::new(-4.0, 0.0, -4.0),
            Vec3::new(-4.0, 0.0, 4.0),
            Vec3::new(4.0, 0.0, 4.0),
            Vec3::new(4.0, 0.0, -4.0),
        ]);
        let floor_indices = self.indices(&[0, 1, 2, 0, 2, 3]);
        let floor = self.mesh(json!({ "attributes": { "POSITION": floor }, "indices": floor_indices }));
        self.node(json!({ "name": "floor", "mesh": floor }), true);
        let look = look_at_rotation(Vec3::new(0.0, 5.0, 7.0), Vec3::ZERO);
        self.node(
            json!({ "name": "eye", "camera": 0, "translation": [0.0, 5.0, 7.0], "rotation": look.to_array() }),
            true,
        );
    }

    fn write(mut self, path: &Path) {
        let uri = format!(
            "data:application/octet-stream;base64,{}",
            base64::engine::general_purpose::STANDARD.encode(&self.bytes)
        );
        self.json["buffers"] = json!([{ "byteLength": self.bytes.len(), "uri": uri }]);
        std::fs::write(path, self.json.to_string()).unwrap();
    }
}

/// A glTF node rotation that points its -Z axis from `eye` at `target` (+Y up).
fn look_at_rotation(eye: Vec3, target: Vec3) -> Quat {
    let forward = (target - eye).normalize();
    let right = forward.cross(Vec3::Y).normalize();
    let up = right.cross(forward);
    Quat::from_mat3(&glam::Mat3::from_cols(right, up, -forward))
}

/// A cube of side 1 centred on its node, with flat faces (normals generated).
fn cube(doc: &mut Doc) -> usize {
    let corners: Vec<Vec3> = (0..8)
        .map(|i| Vec3::new((i & 1) as f32 - 0.5, ((i >> 1) & 1) as f32 - 0.5, ((i >> 2) & 1) as f32 - 0.5))
        .collect();
    let positions = doc.positions(&corners);
    let faces: [u16; 36] =
        [0, 2, 3, 0, 3, 1, 4, 5, 7, 4, 7, 6, 0, 1, 5, 0, 5, 4, 2, 6, 7, 2, 7, 3, 0, 4, 6, 0, 6, 2, 1, 3, 7, 1, 7, 5];
    let indices = doc.indices(&faces);
    doc.mesh(json!({ "attributes": { "POSITION": positions }, "indices": indices }))
}

fn channel(sampler: usize, node: usize, path: &str) -> Value {
    json!({ "sampler": sampler, "target": { "node": node, "path": path } })
}

fn render_exr(dir: &Path, scene: &str, time: Option<&str>, out: &str) -> Vec<(String, Vec<f32>)> {
    let mut args = vec!["render", scene, "-o", out, "--width", "96", "--height", "72"];
    if let Some(t) = time {
        args.extend(["--time", t]);
    }
    let run = chiaro(&args, &[], dir);
    assert_eq!(run.code, 0, "{}", run.stderr);
    read_exr_channels(&dir.join(out))
}

fn assert_same_image(a: &[(String, Vec<f32>)], b: &[(String, Vec<f32>)], what: &str) {
    assert_eq!(a.len(), b.len());
    let mut lit = 0;
    for ((name, x), (_, y)) in a.iter().zip(b) {
        assert_eq!(x.len(), y.len());
        for (i, (p, q)) in x.iter().zip(y).enumerate() {
            assert!((p - q).abs() <= 1e-5, "{what}: channel {name} pixel {i}: {p} != {q}");
        }
        lit += x.iter().filter(|v| **v > 1e-3).count();
    }
    assert!(lit > 0, "{what}: the image is black");
}

#[test]
fn a_render_at_a_time_equals_the_scene_with_its_sampled_transforms_written_static() {
    let dir = tempfile::tempdir().unwrap();
    let (t0, t1, t) = (0.5f32, 2.5f32, 1.25f32);
    let (from, to) = (Vec3::new(-1.5, 0.5, 0.0), Vec3::new(1.5, 0.5, 0.5));
    let down = Quat::from_rotation_x(-std::f32::consts::FRAC_PI_2);
    let (turn_from, turn_to) = (down * Quat::from_rotation_x(0.3), down * Quat::from_rotation_y(-0.4));

    let scene = |animated: bool| {
        let mut doc = Doc::new();
        doc.stage();
        let mesh = cube(&mut doc);
        let s = (t - t0) / (t1 - t0);
        let (box_at, lamp_turn) = if animated {
            (from, turn_from)
        } else {
            (from + (to - from) * s, turn_from.normalize().slerp(turn_to.normalize(), s))
        };
        let cube_node = doc.node(json!({ "name": "box", "mesh": mesh, "translation": box_at.to_array() }), true);
        let lamp = doc.node(
            json!({ "name": "lamp", "translation": [0.0, 4.0, 0.0], "rotation": lamp_turn.to_array(),
                    "extensions": { "KHR_lights_punctual": { "light": 0 } } }),
            true,
        );
        let sun = look_at_rotation(Vec3::new(2.0, 4.0, 1.0), Vec3::ZERO);
        doc.node(
            json!({ "name": "sun", "rotation": sun.to_array(), "extensions": { "KHR_lights_punctual": { "light": 1 } } }),
            true,
        );
        if animated {
            let times = doc.floats(&[t0, t1], "SCALAR");
            let moves = doc.floats(&[from.to_array(), to.to_array()].concat(), "VEC3");
            let turns = doc.floats(&[turn_from.to_array(), turn_to.to_array()].concat(), "VEC4");
            doc.json["animations"] = json!([
                { "channels": [channel(0, cube_node, "translation")],
                  "samplers": [{ "input": times, "output": moves }] },
                { "channels": [channel(0, lamp, "rotation")],
                  "samplers": [{ "input": times, "output": turns, "interpolation": "LINEAR" }] }
            ]);
        }
        doc
    };
    scene(true).write(&dir.path().join("animated.gltf"));
    scene(false).write(&dir.path().join("static.gltf"));
    let posed = render_exr(dir.path(), "animated.gltf", Some("1.25"), "posed.exr");
    let written = render_exr(dir.path(), "static.gltf", None, "written.exr");
    assert_same_image(&posed, &written, "--time 1.25 against the sampled scene");
    // The time matters: the rest pose differs from it.
    let rest = render_exr(dir.path(), "animated.gltf", None, "rest.exr");
    let differing = rest[0].1.iter().zip(&posed[0].1).filter(|(a, b)| (*a - *b).abs() > 1e-3).count();
    assert!(differing > 50, "only {differing} pixels changed between the rest pose and t = 1.25");
}

#[test]
fn animation_pointers_render_as_their_sampled_values_written_static() {
    // KHR_animation_pointer: the spot's colour, intensity and outer cone and the floor's
    // base colour and roughness, sampled at t = 1 (a quarter of the way) and written into
    // a static copy, render the same.
    let dir = tempfile::tempdir().unwrap();
    let pointer = |sampler: usize, p: &str| {
        json!({ "sampler": sampler, "target": { "path": "pointer",
                "extensions": { "KHR_animation_pointer": { "pointer": p } } } })
    };
    let scene = |animated: bool| {
        let mut doc = Doc::new();
        doc.stage();
        let (color, intensity, cone, base, roughness) = if animated {
            ([1.0, 0.25, 0.0], 100.0, 0.5, [1.0, 1.0, 1.0, 1.0], 1.0)
        } else {
            // Dyadic keys, so that a quarter of the way is exact in f32.
            ([0.75, 0.25, 0.25], 200.0, 0.59375, [0.8125, 0.90625, 0.75, 1.0], 0.875)
        };
        let light = &mut doc.json["extensions"]["KHR_lights_punctual"]["lights"][0];
        light["color"] = json!(color);
        light["intensity"] = json!(intensity);
        light["spot"]["outerConeAngle"] = json!(cone);
        doc.json["materials"] = json!([{ "pbrMetallicRoughness": {
            "baseColorFactor": base, "metallicFactor": 0.0, "roughnessFactor": roughness } }]);
        doc.json["meshes"][0]["primitives"][0]["material"] = json!(0);
        let down = Quat::from_rotation_x(-std::f32::consts::FRAC_PI_2);
        doc.node(
            json!({ "name": "lamp", "translation": [0.5, 3.0, 0.0], "rotation": down.to_array(),
                    "extensions": { "KHR_lights_punctual": { "light": 0 } } }),
            true,
        );
        if animated {
            let times = doc.floats(&[0.0, 4.0], "SCALAR");
            let colors = doc.floats(&[1.0, 0.25, 0.0, 0.0, 0.25, 1.0], "VEC3");
            let intensities = doc.floats(&[100.0, 500.0], "SCALAR");
            let cones = doc.floats(&[0.5, 0.875], "SCALAR");
            let bases = doc.floats(&[1.0, 1.0, 1.0, 1.0, 0.25, 0.625, 0.0, 1.0], "VEC4");
            let rough = doc.floats(&[1.0, 0.5], "SCALAR");
            doc.json["extensionsUsed"] = json!(["KHR_lights_punctual", "KHR_animation_pointer"]);
            doc.json["animations"] = json!([{
                "channels": [
                    pointer(0, "/extensions/KHR_lights_punctual/lights/0/color"),
                    pointer(1, "/extensions/KHR_lights_punctual/lights/0/intensity"),
                    pointer(2, "/extensions/KHR_lights_punctual/lights/0/spot/outerConeAngle"),
                    pointer(3, "/materials/0/pbrMetallicRoughness/baseColorFactor"),
                    pointer(4, "/materials/0/pbrMetallicRoughness/roughnessFactor"),
                ],
                "samplers": [
                    { "input": times, "output": colors }, { "input": times, "output": intensities },
                    { "input": times, "output": cones }, { "input": times, "output": bases },
                    { "input": times, "output": rough }
                ]
            }]);
        }
        doc
    };
    scene(true).write(&dir.path().join("animated.gltf"));
    scene(false).write(&dir.path().join("static.gltf"));
    let posed = render_exr(dir.path(), "animated.gltf", Some("1"), "posed.exr");
    let written = render_exr(dir.path(), "static.gltf", None, "written.exr");
    assert_same_image(&posed, &written, "--time 1 against the sampled light and material");
    let rest = render_exr(dir.path(), "animated.gltf", None, "rest.exr");
    let differing = rest[0].1.iter().zip(&posed[0].1).filter(|(a, b)| (*a - *b).abs() > 1e-3).count();
    assert!(differing > 50, "only {differing} pixels changed between the rest values and t = 1");
}

#[test]
fn a_skinned_strip_at_a_time_renders_as_its_hand_posed_copy() {
    let dir = tempfile::tempdir().unwrap();
    let angle = 0.8f32;
    // A strip 2 m tall at x in [0, 0.6], bound to a root joint at its foot and a bone joint
    // 1 m up; the bone's rotation about z turns the upper half (the middle row half-way).
    let rest: Vec<Vec3> =
        [0.0f32, 1.0, 2.0].iter().flat_map(|&y| [Vec3::new(0.0, y, 0.0), Vec3::new(0.6, y, 0.0)]).collect();
    let pivot = Vec3::new(0.0, 1.0, 0.0);
    let turn = Quat::from_rotation_z(angle * 0.5);
    let by_bone = |p: Vec3| pivot + turn * (p - pivot);
    let by_hand: Vec<Vec3> = rest
        .iter()
        .enumerate()
        .map(|(i, &p)| match i / 2 {
            0 => p,
            1 => (p + by_bone(p)) * 0.5,
            _ => by_bone(p),
        })
        .collect();
    let strip_indices = [0u16, 1, 3, 0, 3, 2, 2, 3, 5, 2, 5, 4];
    let scene = |skinned: bool| {
        let mut doc = Doc::new();
        doc.stage();
        let positions = doc.positions(if skinned { &rest } else { &by_hand });
        let indices = doc.indices(&strip_indices);
        let mut primitive = json!({ "attributes": { "POSITION": positions }, "indices": indices });
        if skinned {
            let joints: Vec<u8> = [[0u16, 1, 0, 0]; 6].iter().flatten().flat_map(|j| j.to_le_bytes()).collect();
            primitive["attributes"]["JOINTS_0"] = json!(doc.accessor(joints, 5123, 6, "VEC4", None));
            let weights: Vec<f32> =
                [1.0, 1.0, 0.5, 0.5, 0.0, 0.0].iter().flat_map(|&w: &f32| [w, 1.0 - w, 0.0, 0.0]).collect();
            primitive["attributes"]["WEIGHTS_0"] = json!(doc.floats(&weights, "VEC4"));
        }
        let mesh = doc.mesh(primitive);
        let strip = doc.node(json!({ "name": "strip", "mesh": mesh }), true);
        let lamp = look_at_rotation(Vec3::new(1.0, 4.0, 3.0), Vec3::new(0.0, 0.5, 0.0));
        doc.node(
            json!({ "name": "lamp", "translation": [1.0, 4.0, 3.0], "rotation": lamp.to_array(),
                    "extensions": { "KHR_lights_punctual": { "light": 0 } } }),
            true,
        );
        if skinned {
            let bone = doc.node(json!({ "name": "bone", "translation": [0.0, 1.0, 0.0] }), false);
            let root = doc.node(json!({ "name": "root", "children": [bone] }), true);
            let inverse_bind: Vec<f32> =
                [Vec3::ZERO, pivot].iter().flat_map(|t| glam::Mat4::from_translation(-*t).to_cols_array()).collect();
            let inverse_bind = doc.floats(&inverse_bind, "MAT4");
            doc.json["skins"] = json!([{ "joints": [root, bone], "inverseBindMatrices": inverse_bind }]);
            doc.json["nodes"][strip]["skin"] = json!(0);
            let times = doc.floats(&[0.0, 1.0], "SCALAR");
            let turns =
                doc.floats(&[Quat::IDENTITY.to_array(), Quat::from_rotation_z(angle).to_array()].concat(), "VEC4");
            doc.json["animations"] = json!([{ "channels": [channel(0, bone, "rotation")],
                                              "samplers": [{ "input": times, "output": turns }] }]);
        }
        doc
    };
    scene(true).write(&dir.path().join("skinned.gltf"));
    scene(false).write(&dir.path().join("by-hand.gltf"));
    let posed = render_exr(dir.path(), "skinned.gltf", Some("0.5"), "posed.exr");
    let by_hand = render_exr(dir.path(), "by-hand.gltf", None, "by-hand.exr");
    assert_same_image(&posed, &by_hand, "the skinned strip at 0.5 s against its hand-posed copy");
}

#[test]
fn a_time_that_is_not_a_number_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let mut doc = Doc::new();
    doc.stage();
    doc.write(&dir.path().join("still.gltf"));
    let run = chiaro(&["render", "still.gltf", "--time", "nan", "-o", "x.png"], &[], dir.path());
    assert_eq!(run.code, 1, "{}", run.stderr);
    assert!(run.stderr.contains("--time: time NaN is not a finite number of seconds"), "{}", run.stderr);
    assert!(!dir.path().join("x.png").exists());
}
