//! Animation, skins and morph targets: files written here are posed at chosen times and the
//! results checked against the glTF formulas and against hand-posed static copies.

use super::{TempDir, data_uri, invalid_message, load_doc};
use crate::animation::sample::hermite;
use glam::{Mat4, Quat, Vec3};
use serde_json::{Value, json};

/// A document under construction: one buffer that accessors are appended to.
struct Doc {
    json: Value,
    bytes: Vec<u8>,
}

impl Doc {
    fn new(nodes: Value, roots: Value) -> Doc {
        Doc {
            json: json!({
                "asset": { "version": "2.0" },
                "scene": 0,
                "scenes": [{ "nodes": roots }],
                "nodes": nodes,
                "meshes": [],
                "accessors": [],
                "bufferViews": [],
            }),
            bytes: Vec::new(),
        }
    }

    /// Appends `values` as a float accessor of `ty` and returns its index.
    fn floats(&mut self, values: &[f32], ty: &str) -> usize {
        let width = match ty {
            "SCALAR" => 1,
            "VEC3" => 3,
            "VEC4" => 4,
            "MAT4" => 16,
            _ => unreachable!(),
        };
        let data: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
        self.view_and_accessor(data, 5126, values.len() / width, ty)
    }

    /// Appends unsigned-short JOINTS.
    fn joints(&mut self, joints: &[[u16; 4]]) -> usize {
        let data: Vec<u8> = joints.iter().flatten().flat_map(|j| j.to_le_bytes()).collect();
        self.view_and_accessor(data, 5123, joints.len(), "VEC4")
    }

    fn view_and_accessor(&mut self, data: Vec<u8>, component: u32, count: usize, ty: &str) -> usize {
        let offset = self.bytes.len();
        let length = data.len();
        self.bytes.extend(data);
        while !self.bytes.len().is_multiple_of(4) {
            self.bytes.push(0);
        }
        let views = self.json["bufferViews"].as_array_mut().unwrap();
        views.push(json!({ "buffer": 0, "byteOffset": offset, "byteLength": length }));
        let view = views.len() - 1;
        let accessors = self.json["accessors"].as_array_mut().unwrap();
        let mut accessor = json!({ "bufferView": view, "componentType": component, "count": count, "type": ty });
        if ty == "VEC3" && component == 5126 {
            // POSITION accessors need bounds; every VEC3 gets them, harmlessly.
            accessor["min"] = json!([-100.0, -100.0, -100.0]);
            accessor["max"] = json!([100.0, 100.0, 100.0]);
        }
        accessors.push(accessor);
        accessors.len() - 1
    }

    fn mesh(&mut self, primitive: Value) -> usize {
        let meshes = self.json["meshes"].as_array_mut().unwrap();
        meshes.push(json!({ "primitives": [primitive] }));
        meshes.len() - 1
    }

    fn finish(mut self) -> Value {
        self.json["buffers"] = json!([{ "byteLength": self.bytes.len(), "uri": data_uri(&self.bytes) }]);
        self.json
    }
}

fn channel(sampler: usize, node: usize, path: &str) -> Value {
    json!({ "sampler": sampler, "target": { "node": node, "path": path } })
}

fn sampler(input: usize, output: usize, interpolation: &str) -> Value {
    json!({ "input": input, "output": output, "interpolation": interpolation })
}

/// A unit triangle mesh (no normals: they are generated flat).
fn triangle(doc: &mut Doc) -> usize {
    let positions = doc.floats(&[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0], "VEC3");
    doc.mesh(json!({ "attributes": { "POSITION": positions } }))
}

#[test]
fn linear_translation_and_rotation_channels_move_meshes_and_lights() {
    let dir = TempDir::new("anim-linear");
    let mut doc = Doc::new(
        json!([
            { "mesh": 0, "name": "box", "translation": [5.0, 0.0, 0.0] },
            { "name": "sun", "extensions": { "KHR_lights_punctual": { "light": 0 } } }
        ]),
        json!([0, 1]),
    );
    triangle(&mut doc);
    let times = doc.floats(&[1.0, 3.0], "SCALAR");
    let moves = doc.floats(&[0.0, 0.0, 0.0, 2.0, 4.0, -6.0], "VEC3");
    let (q0, q1) = (Quat::from_rotation_x(-0.2), Quat::from_rotation_x(-1.4));
    let turns = doc.floats(&[q0.to_array(), q1.to_array()].concat(), "VEC4");
    doc.json["extensionsUsed"] = json!(["KHR_lights_punctual"]);
    doc.json["extensions"] = json!({ "KHR_lights_punctual": { "lights": [{ "type": "directional" }] } });
    doc.json["animations"] = json!([{
        "channels": [channel(0, 0, "translation"), channel(1, 1, "rotation")],
        "samplers": [sampler(times, moves, "LINEAR"), sampler(times, turns, "LINEAR")]
    }]);
    let mut scene = load_doc(&dir, &doc.finish()).unwrap();
    // At rest the file's own transforms hold.
    assert_eq!(scene.instances[0].world_from_local, Mat4::from_translation(Vec3::new(5.0, 0.0, 0.0)));
    assert_eq!(scene.animation_duration(), Some(3.0));

    scene.pose(Some(1.5)).unwrap();
    let translation = scene.instances[0].world_from_local.w_axis.truncate();
    assert!(translation.abs_diff_eq(Vec3::new(0.5, 1.0, -1.5), 1e-6), "{translation}");
    let light = Quat::from_mat4(&scene.lights[0].world_from_light);
    assert!(light.angle_between(q0.slerp(q1, 0.25)) < 1e-5);
    assert_eq!(scene.nodes[0].world_from_node, scene.instances[0].world_from_local);

    // Before the first key the first holds, after the last the last; no time is the rest.
    scene.pose(Some(-4.0)).unwrap();
    assert_eq!(scene.instances[0].world_from_local, Mat4::IDENTITY);
    scene.pose(Some(99.0)).unwrap();
    assert!(scene.instances[0].world_from_local.w_axis.truncate().abs_diff_eq(Vec3::new(2.0, 4.0, -6.0), 1e-6));
    scene.pose(None).unwrap();
    assert_eq!(scene.instances[0].world_from_local, Mat4::from_translation(Vec3::new(5.0, 0.0, 0.0)));
    assert!(scene.pose(Some(f32::NAN)).is_err());
}

#[test]
fn step_and_cubic_spline_channels_follow_their_formulas() {
    let dir = TempDir::new("anim-spline");
    let mut doc = Doc::new(json!([{ "mesh": 0 }, { "mesh": 0 }]), json!([0, 1]));
    triangle(&mut doc);
    let times = doc.floats(&[0.0, 2.0, 5.0], "SCALAR");
    let steps = doc.floats(&[1.0, 1.0, 1.0, 2.0, 2.0, 2.0, 3.0, 3.0, 3.0], "VEC3");
    // (in-tangent, value, out-tangent) per key, moving along x only.
    let spline_keys = [[0.0, 0.0, 1.5], [-2.0, 4.0, 0.5], [3.0, 1.0, 0.0]];
    let spline: Vec<f32> = spline_keys.iter().flat_map(|k| k.iter().flat_map(|&x| [x, 0.0, 0.0])).collect();
    let spline = doc.floats(&spline, "VEC3");
    doc.json["animations"] = json!([{
        "channels": [channel(0, 0, "scale"), channel(1, 1, "translation")],
        "samplers": [sampler(times, steps, "STEP"), sampler(times, spline, "CUBICSPLINE")]
    }]);
    let mut scene = load_doc(&dir, &doc.finish()).unwrap();
    // Between keys k and k + 1 (at t0 and t1) the spline is the Hermite blend of value k,
    // out-tangent k, value k + 1 and in-tangent k + 1, tangents scaled by the span.
    let spline_at = |t: f32| -> f32 {
        let (k, t0, t1) = if t < 2.0 { (0, 0.0, 2.0) } else { (1, 2.0, 5.0) };
        let (dt, h) = (t1 - t0, hermite((t - t0) / (t1 - t0)));
        h[0] * spline_keys[k][1]
            + h[1] * dt * spline_keys[k][2]
            + h[2] * spline_keys[k + 1][1]
            + h[3] * dt * spline_keys[k + 1][0]
    };
    for (t, scale, x) in [
        (0.5f32, 1.0, spline_at(0.5)),
        (2.0, 2.0, spline_keys[1][1]),
        (3.2, 2.0, spline_at(3.2)),
        (4.99, 2.0, spline_at(4.99)),
        (6.0, 3.0, spline_keys[2][1]),
    ] {
        scene.pose(Some(t)).unwrap();
        let (got_scale, _, _) = scene.instances[0].world_from_local.to_scale_rotation_translation();
        assert!(got_scale.abs_diff_eq(Vec3::splat(scale), 1e-6), "t = {t}: scale {got_scale}");
        let got_x = scene.instances[1].world_from_local.w_axis.x;
        assert!((got_x - x).abs() < 1e-5, "t = {t}: {got_x} != {x}");
    }
}

/// The strip's triangles. It has no normals, so the loader unwelds its vertices in this
/// order and gives them flat normals.
const STRIP_INDICES: [u16; 12] = [0, 1, 3, 0, 3, 2, 2, 3, 5, 2, 5, 4];

/// A strip two metres tall along +Y at x = 3, two triangles per metre, skinned to a root
/// joint at its foot and a bone joint one metre up: the bottom row follows the root, the top row
/// the bone, the middle row half each. With `posed`, the same strip as a static mesh with
/// those positions instead.
fn two_bone_doc(bone_rotation: Quat, posed: Option<&[Vec3]>) -> Value {
    let rows = [0.0f32, 1.0, 2.0];
    let rest: Vec<Vec3> = rows.iter().flat_map(|&y| [Vec3::new(3.0, y, 0.0), Vec3::new(3.5, y, 0.0)]).collect();
    let indices = STRIP_INDICES;
    let mut doc = Doc::new(
        json!([
            { "mesh": 0, "name": "strip" },
            { "name": "root", "children": [2], "translation": [3.0, 0.0, 0.0] },
            { "name": "bone", "translation": [0.0, 1.0, 0.0] }
        ]),
        json!([0, 1]),
    );
    let positions = posed.unwrap_or(&rest);
    let position_accessor = doc.floats(&positions.iter().flat_map(|p| p.to_array()).collect::<Vec<_>>(), "VEC3");
    let index_bytes: Vec<u8> = indices.iter().flat_map(|i| i.to_le_bytes()).collect();
    let index_accessor = doc.view_and_accessor(index_bytes, 5123, indices.len(), "SCALAR");
    let mut primitive = json!({ "attributes": { "POSITION": position_accessor }, "indices": index_accessor });
    if posed.is_none() {
        let joints = doc.joints(&[[0, 1, 0, 0]; 6]);
        let weights: Vec<f32> = [[1.0, 0.0], [1.0, 0.0], [0.5, 0.5], [0.5, 0.5], [0.0, 1.0], [0.0, 1.0]]
            .iter()
            .flat_map(|[a, b]| [*a, *b, 0.0, 0.0])
            .collect();
        let weights = doc.floats(&weights, "VEC4");
        primitive["attributes"]["JOINTS_0"] = json!(joints);
        primitive["attributes"]["WEIGHTS_0"] = json!(weights);
        // Bind pose: the root at x = 3, the bone one metre above it.
        let inverse_bind: Vec<f32> = [Vec3::new(3.0, 0.0, 0.0), Vec3::new(3.0, 1.0, 0.0)]
            .iter()
            .flat_map(|t| Mat4::from_translation(-*t).to_cols_array())
            .collect();
        let inverse_bind = doc.floats(&inverse_bind, "MAT4");
        doc.json["skins"] = json!([{ "joints": [1, 2], "inverseBindMatrices": inverse_bind }]);
        doc.json["nodes"][0]["skin"] = json!(0);
        let times = doc.floats(&[0.0, 1.0], "SCALAR");
        let turns = doc.floats(&[Quat::IDENTITY.to_array(), bone_rotation.to_array()].concat(), "VEC4");
        doc.json["animations"] =
            json!([{ "channels": [channel(0, 2, "rotation")], "samplers": [sampler(times, turns, "LINEAR")] }]);
    }
    doc.mesh(primitive);
    doc.finish()
}

#[test]
fn a_skinned_two_bone_mesh_at_a_time_equals_its_hand_posed_copy() {
    let dir = TempDir::new("anim-skin");
    let bend = Quat::from_rotation_z(std::f32::consts::FRAC_PI_2);
    let mut scene = load_doc(&dir, &two_bone_doc(bend, None)).unwrap();
    // At rest the joints are where they were bound: the strip stays as authored.
    assert_eq!(scene.instances[0].world_from_local, Mat4::IDENTITY);
    // (Vertex 8 of the unwelded strip is vertex 5 of the file, at the top.)
    assert!(
        scene.meshes[scene.instances[0].mesh].primitives[0].positions[8].abs_diff_eq(Vec3::new(3.5, 2.0, 0.0), 1e-6)
    );
    assert!(!scene.instances[0].is_static, "a mesh moved by animated joints is dynamic");

    // Half-way, the bone has turned 45 degrees about z around its pivot (3, 1, 0).
    scene.pose(Some(0.5)).unwrap();
    let turn = Quat::from_rotation_z(std::f32::consts::FRAC_PI_4);
    let pivot = Vec3::new(3.0, 1.0, 0.0);
    let by_bone = |p: Vec3| pivot + turn * (p - pivot);
    let by_root = |p: Vec3| p;
    let rest: Vec<Vec3> =
        [0.0f32, 1.0, 2.0].iter().flat_map(|&y| [Vec3::new(3.0, y, 0.0), Vec3::new(3.5, y, 0.0)]).collect();
    let by_hand: Vec<Vec3> = rest
        .iter()
        .enumerate()
        .map(|(i, &p)| match i / 2 {
            0 => by_root(p),
            1 => (by_root(p) + by_bone(p)) * 0.5,
            _ => by_bone(p),
        })
        .collect();
    let posed = &scene.meshes[scene.instances[0].mesh].primitives[0];
    let unwelded: Vec<Vec3> = STRIP_INDICES.iter().map(|&i| by_hand[usize::from(i)]).collect();
    assert_eq!(posed.positions.len(), unwelded.len());
    for (got, want) in posed.positions.iter().zip(&unwelded) {
        assert!(got.abs_diff_eq(*want, 1e-5), "{got} != {want}");
    }
    // The hand-posed copy as a static file loads to the same vertices and normals.
    let copy = load_doc(&dir, &two_bone_doc(bend, Some(&by_hand))).unwrap();
    let still = &copy.meshes[0].primitives[0];
    for (a, b) in posed.positions.iter().zip(&still.positions) {
        assert!(a.abs_diff_eq(*b, 1e-5));
    }
    for (a, b) in posed.normals.iter().zip(&still.normals) {
        assert!(a.abs_diff_eq(*b, 1e-5), "{a} != {b}");
    }
    assert!(posed.bounds.max.abs_diff_eq(still.bounds.max, 1e-5));
}

#[test]
fn morph_weights_from_the_mesh_the_node_and_a_channel_blend_targets() {
    let dir = TempDir::new("anim-morph");
    let mut doc = Doc::new(json!([{ "mesh": 0, "weights": [0.5] }, { "mesh": 0 }]), json!([0, 1]));
    let positions = doc.floats(&[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0], "VEC3");
    let lift = doc.floats(&[0.0, 0.0, 2.0, 0.0, 0.0, 2.0, 0.0, 0.0, 2.0], "VEC3");
    doc.mesh(json!({ "attributes": { "POSITION": positions }, "targets": [{ "POSITION": lift }] }));
    doc.json["meshes"][0]["weights"] = json!([0.25]);
    let times = doc.floats(&[0.0, 1.0], "SCALAR");
    let weights = doc.floats(&[0.0, 1.0], "SCALAR");
    doc.json["animations"] =
        json!([{ "channels": [channel(0, 1, "weights")], "samplers": [sampler(times, weights, "LINEAR")] }]);
    let mut scene = load_doc(&dir, &doc.finish()).unwrap();
    let z = |scene: &crate::types::Scene, i: usize| scene.meshes[scene.instances[i].mesh].primitives[0].positions[2].z;
    // At rest: the node's weights, else the mesh's.
    assert_eq!((z(&scene, 0), z(&scene, 1)), (1.0, 0.5));
    scene.pose(Some(0.75)).unwrap();
    assert_eq!((z(&scene, 0), z(&scene, 1)), (1.0, 1.5));
    assert_ne!(scene.instances[0].mesh, scene.instances[1].mesh, "each morphed instance poses its own copy");
}

#[test]
fn broken_samplers_are_refused_naming_the_channel() {
    let dir = TempDir::new("anim-bad");
    let mut doc = Doc::new(json!([{ "mesh": 0 }]), json!([0]));
    triangle(&mut doc);
    let times = doc.floats(&[0.0, 2.0, 1.0], "SCALAR");
    let moves = doc.floats(&[0.0; 9], "VEC3");
    let short = doc.floats(&[0.0; 6], "VEC3");
    let good_times = doc.floats(&[0.0, 1.0, 2.0], "SCALAR");
    doc.json["animations"] = json!([{ "name": "walk", "channels": [channel(0, 0, "translation")], "samplers": [sampler(times, moves, "LINEAR")] }]);
    let mut broken = doc.json.clone();
    let bytes_doc = |mut json: Value, doc: &Doc| {
        json["buffers"] = json!([{ "byteLength": doc.bytes.len(), "uri": data_uri(&doc.bytes) }]);
        json
    };
    let message = invalid_message(load_doc(&dir, &bytes_doc(broken.clone(), &doc)));
    assert!(message.starts_with("animations[0] (walk).channels[0]: key times must increase"), "{message}");
    broken["animations"][0]["samplers"][0] = sampler(good_times, short, "CUBICSPLINE");
    let message = invalid_message(load_doc(&dir, &bytes_doc(broken, &doc)));
    assert!(message.contains("which is not 3 keys of 3 value(s) each"), "{message}");
}

fn pointer_channel(sampler: usize, pointer: &str) -> Value {
    json!({ "sampler": sampler, "target": { "path": "pointer", "extensions": { "KHR_animation_pointer": { "pointer": pointer } } } })
}

#[test]
fn animation_pointers_move_light_and_material_properties_and_nodes() {
    let dir = TempDir::new("anim-pointer");
    let lamp = |n: usize| json!({ "name": format!("lamp {n}"), "translation": [n as f32, 2.0, 0.0], "extensions": { "KHR_lights_punctual": { "light": 0 } } });
    let mut doc = Doc::new(json!([{ "mesh": 0, "name": "tri" }, lamp(1), lamp(2)]), json!([0, 1, 2]));
    let mesh = triangle(&mut doc);
    doc.json["meshes"][mesh]["primitives"][0]["material"] = json!(0);
    doc.json["materials"] = json!([{
        "pbrMetallicRoughness": { "baseColorFactor": [1.0, 1.0, 1.0, 1.0], "roughnessFactor": 0.8 },
        "emissiveFactor": [1.0, 0.5, 0.0],
        "extensions": { "KHR_materials_emissive_strength": { "emissiveStrength": 2.0 } }
    }]);
    doc.json["extensionsUsed"] =
        json!(["KHR_lights_punctual", "KHR_animation_pointer", "KHR_materials_emissive_strength"]);
    doc.json["extensionsRequired"] = json!(["KHR_animation_pointer"]);
    doc.json["extensions"] = json!({ "KHR_lights_punctual": { "lights": [{
        "type": "spot", "color": [1.0, 1.0, 1.0], "intensity": 10.0, "range": 8.0,
        "spot": { "innerConeAngle": 0.2, "outerConeAngle": 0.6 }
    }] } });
    let times = doc.floats(&[0.0, 2.0], "SCALAR");
    let colors = doc.floats(&[1.0, 0.0, 0.0, 0.0, 0.0, 1.0], "VEC3");
    let intensities = doc.floats(&[0.0, 40.0], "SCALAR");
    let cones = doc.floats(&[0.1, 0.9], "SCALAR");
    let base = doc.floats(&[0.2, 0.4, 0.6, 1.0, 0.6, 0.4, 0.2, 0.5], "VEC4");
    let roughness = doc.floats(&[0.1, 0.5], "SCALAR");
    let strength = doc.floats(&[0.0, 4.0], "SCALAR");
    let moves = doc.floats(&[0.0, 0.0, 0.0, 0.0, 6.0, 0.0], "VEC3");
    doc.json["animations"] = json!([{
        "name": "pulse",
        "channels": [
            pointer_channel(0, "/extensions/KHR_lights_punctual/lights/0/color"),
            pointer_channel(1, "/extensions/KHR_lights_punctual/lights/0/intensity"),
            pointer_channel(2, "/extensions/KHR_lights_punctual/lights/0/spot/outerConeAngle"),
            pointer_channel(3, "/materials/0/pbrMetallicRoughness/baseColorFactor"),
            pointer_channel(4, "/materials/0/pbrMetallicRoughness/roughnessFactor"),
            pointer_channel(5, "/materials/0/extensions/KHR_materials_emissive_strength/emissiveStrength"),
            pointer_channel(6, "/nodes/0/translation"),
            pointer_channel(4, "/cameras/0/perspective/yfov"),
            pointer_channel(4, "/materials/9/alphaCutoff"),
        ],
        "samplers": [
            sampler(times, colors, "LINEAR"), sampler(times, intensities, "LINEAR"), sampler(times, cones, "STEP"),
            sampler(times, base, "LINEAR"), sampler(times, roughness, "LINEAR"), sampler(times, strength, "LINEAR"),
            sampler(times, moves, "LINEAR")
        ]
    }]);
    let mut scene = load_doc(&dir, &doc.finish()).unwrap();
    assert_eq!(scene.lights.len(), 2, "two nodes place the light");
    assert_eq!(scene.animation_duration(), Some(2.0));
    let ignored =
        |what: &str| scene.ignored.iter().any(|s| s.contains("animations[0] (pulse).channels[") && s.contains(what));
    assert!(ignored("\"/cameras/0/perspective/yfov\" is not a property Chiaro animates"), "{:?}", scene.ignored);
    assert!(ignored("\"/materials/9/alphaCutoff\" names something the file does not have"), "{:?}", scene.ignored);

    scene.pose(Some(0.5)).unwrap();
    for light in &scene.lights {
        assert!(light.color.abs_diff_eq(Vec3::new(0.75, 0.0, 0.25), 1e-6), "{}", light.color);
        assert!((light.intensity - 10.0).abs() < 1e-5);
        let crate::types::LightKind::Spot { inner_cone_rad, outer_cone_rad } = light.kind else { panic!("spot") };
        assert_eq!(outer_cone_rad, 0.1, "STEP holds the first key");
        // An outer cone below the file's inner one pulls the inner one in, for this pose.
        assert!(inner_cone_rad < 0.1 && inner_cone_rad > 0.099, "{inner_cone_rad}");
    }
    let m = &scene.materials[0];
    assert!(m.base_color.abs_diff_eq(glam::Vec4::new(0.3, 0.4, 0.5, 0.875), 1e-6), "{}", m.base_color);
    assert!((m.roughness - 0.2).abs() < 1e-6);
    // Emissive strength 1 (a quarter of the way to 4) times the file's factor.
    assert!(m.emissive.abs_diff_eq(Vec3::new(1.0, 0.5, 0.0), 1e-6), "{}", m.emissive);
    assert!(scene.instances[0].world_from_local.w_axis.truncate().abs_diff_eq(Vec3::new(0.0, 1.5, 0.0), 1e-6));

    scene.pose(Some(2.0)).unwrap();
    let crate::types::LightKind::Spot { inner_cone_rad, outer_cone_rad } = scene.lights[1].kind else { panic!("spot") };
    assert_eq!((inner_cone_rad, outer_cone_rad), (0.2, 0.9), "the file's inner cone again");
    scene.pose(None).unwrap();
    let light = &scene.lights[0];
    assert_eq!((light.color, light.intensity, light.range), (Vec3::ONE, 10.0, Some(8.0)));
    let crate::types::LightKind::Spot { inner_cone_rad, outer_cone_rad } = light.kind else { panic!("spot") };
    assert_eq!((inner_cone_rad, outer_cone_rad), (0.2, 0.6));
    let m = &scene.materials[0];
    assert_eq!((m.base_color, m.roughness), (glam::Vec4::ONE, 0.8));
    assert!(m.emissive.abs_diff_eq(Vec3::new(2.0, 1.0, 0.0), 1e-6), "{}", m.emissive);
}

#[test]
fn a_pointer_channel_without_its_sampler_is_refused_naming_it() {
    let dir = TempDir::new("anim-pointer-bad");
    let mut doc = Doc::new(json!([{ "mesh": 0 }]), json!([0]));
    triangle(&mut doc);
    doc.json["materials"] = json!([{}]);
    doc.json["animations"] = json!([{ "channels": [pointer_channel(3, "/materials/0/alphaCutoff")], "samplers": [] }]);
    let message = invalid_message(load_doc(&dir, &doc.finish()));
    assert!(message.contains("animations[0].channels[0]: its sampler does not exist"), "{message}");
}
