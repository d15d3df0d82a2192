//! The built-in demo scene, made in code: a floor, boxes and spheres, one sun, a ring of
//! coloured point and spot lights, and a camera. `chiaro render` with no scene draws it in
//! a studio environment (`demo_scene_in_studio`), and the benchmarks vary its number of
//! local lights.

use crate::environment::{SceneEnvironment, neutral, scene_sun};
use crate::shapes;
use crate::types::*;
use chiaro_math::rigid::looking_along;
use glam::{Mat4, Quat, Vec3};

/// Default number of point and spot lights in the demo.
pub const DEMO_LOCAL_LIGHTS: usize = 8;

const PALETTE: [Vec3; 6] = [
    Vec3::new(1.0, 0.45, 0.25),
    Vec3::new(0.3, 0.6, 1.0),
    Vec3::new(0.4, 1.0, 0.45),
    Vec3::new(1.0, 0.85, 0.3),
    Vec3::new(0.85, 0.35, 1.0),
    Vec3::new(1.0, 1.0, 1.0),
];

fn material(name: &str, color: Vec3, metallic: f32, roughness: f32) -> Material {
    Material { name: name.into(), base_color: color.extend(1.0), metallic, roughness, ..Material::default() }
}

/// Default shadowed lights of the demo: four spots and two points fill the local-light
/// atlas's 16 tiles, as in chiaro-bench.
pub const DEMO_SHADOWED_SPOTS: usize = 4;
/// Default number of the demo's point lights that cast shadows.
pub const DEMO_SHADOWED_POINTS: usize = 2;

/// The demo scene with `local_lights` point and spot lights (alternating, spots first),
/// spread over a ring around the centre so that every count lights the floor; the first
/// four spots and two points cast shadows.
pub fn demo_scene(local_lights: usize) -> Scene {
    demo_scene_with_shadows(local_lights, DEMO_SHADOWED_SPOTS, DEMO_SHADOWED_POINTS)
}

/// The demo as the front ends show it when no scene file is given (`chiaro render`, the
/// viewer, `chiaro.Scene.demo()`): `demo_scene_with_shadows` with an environment of its
/// own, as a glTF file's EXT_lights_image_based would give it: the neutral studio at a
/// fifth of its sun's illuminance, so that the metals reflect something and the shadows
/// are filled yet read. `environment.source = "ambient"` takes it off; the tests use the
/// plain `demo_scene`, whose light is the lights' alone.
pub fn demo_scene_in_studio(local_lights: usize, shadowed_spots: usize, shadowed_points: usize) -> Scene {
    let mut scene = demo_scene_with_shadows(local_lights, shadowed_spots, shadowed_points);
    let sun_lux = scene_sun(&scene).map(|(_, lux)| lux);
    scene.environment = Some(SceneEnvironment::new("the demo's studio".into(), neutral(sun_lux)));
    scene
}

/// The demo scene where the first `shadowed_spots` spots and `shadowed_points` points cast
/// realtime shadows and the rest do not.
pub fn demo_scene_with_shadows(local_lights: usize, shadowed_spots: usize, shadowed_points: usize) -> Scene {
    let mut scene = demo_materials_and_meshes();
    place_demo_objects(&mut scene);
    // Lights and the camera take the node indices after the objects'.
    let light_node_base = scene.instances.len();
    scene.lights.push(demo_sun(light_node_base));
    for i in 0..local_lights {
        let shadowed = if i.is_multiple_of(2) { i / 2 < shadowed_spots } else { i / 2 < shadowed_points };
        scene.lights.push(demo_local_light(i, local_lights, light_node_base + 1 + i, shadowed));
    }
    scene.cameras.push(demo_camera(light_node_base + 1 + local_lights));
    scene.ensure_nodes();
    scene
}

/// The demo's materials and meshes, each mesh with its material (the gold sphere and the
/// chalk box share the plain ones' geometry).
fn demo_materials_and_meshes() -> Scene {
    let mut scene = Scene {
        materials: vec![
            material("floor", Vec3::splat(0.6), 0.0, 0.85),
            material("clay", Vec3::new(0.8, 0.3, 0.2), 0.0, 0.6),
            material("teal", Vec3::new(0.15, 0.55, 0.55), 0.0, 0.4),
            material("gold", Vec3::new(1.0, 0.78, 0.34), 1.0, 0.3),
            material("chalk", Vec3::splat(0.85), 0.0, 0.9),
        ],
        meshes: vec![
            Mesh::of_triangles("floor".into(), vec![shapes::plane(24.0, 8)]),
            Mesh::of_triangles("box".into(), vec![shapes::cuboid(Vec3::ONE)]),
            Mesh::of_triangles("sphere".into(), vec![shapes::sphere(0.5, 48, 24)]),
        ],
        ..Scene::default()
    };
    for (mesh, material) in [(0, 0), (1, 1), (2, 2)] {
        scene.meshes[mesh].primitives[0].material = Some(material);
    }
    // Second materials for the same shapes come as extra meshes sharing geometry.
    let mut gold_sphere = scene.meshes[2].clone();
    gold_sphere.name = "gold sphere".into();
    gold_sphere.primitives[0].material = Some(3);
    scene.meshes.push(gold_sphere);
    let mut chalk_box = scene.meshes[1].clone();
    chalk_box.name = "chalk box".into();
    chalk_box.primitives[0].material = Some(4);
    scene.meshes.push(chalk_box);
    scene
}

/// The floor, boxes and spheres, one instance (and node) each.
fn place_demo_objects(scene: &mut Scene) {
    let mut place = |mesh: usize, name: &str, transform: Mat4| {
        let node = scene.instances.len();
        scene.instances.push(MeshInstance {
            mesh,
            node,
            name: name.into(),
            world_from_local: transform,
            cast_shadows: CastShadows::On,
            receive_shadows: true,
            is_static: true,
            lightmap: None,
            gpu_instance: None,
            label: 0,
        });
    };
    place(0, "floor", Mat4::IDENTITY);
    let boxes = [
        (Vec3::new(-2.5, 0.75, -1.0), Vec3::new(1.5, 1.5, 1.5), 0.5, 1),
        (Vec3::new(2.0, 1.0, -2.5), Vec3::new(1.0, 2.0, 1.0), -0.3, 4),
        (Vec3::new(0.5, 0.4, 2.0), Vec3::new(2.0, 0.8, 0.8), 0.9, 1),
        (Vec3::new(-4.5, 1.5, -4.5), Vec3::new(1.0, 3.0, 1.0), 0.0, 4),
    ];
    for (i, (pos, size, yaw, mesh)) in boxes.into_iter().enumerate() {
        let t = Mat4::from_scale_rotation_translation(size, Quat::from_rotation_y(yaw), pos);
        place(mesh, &format!("box {i}"), t);
    }
    let spheres = [
        (Vec3::new(0.0, 1.0, 0.0), 2.0, 2),
        (Vec3::new(-1.0, 0.5, 3.5), 1.0, 3),
        (Vec3::new(3.5, 0.75, 1.0), 1.5, 3),
        (Vec3::new(4.0, 0.5, -5.0), 1.0, 2),
    ];
    for (i, (pos, scale, mesh)) in spheres.into_iter().enumerate() {
        place(
            mesh,
            &format!("sphere {i}"),
            Mat4::from_scale_rotation_translation(Vec3::splat(scale), Quat::IDENTITY, pos),
        );
    }
}

/// The demo's sun, at node `node`.
fn demo_sun(node: usize) -> Light {
    let sun_direction = Vec3::new(-0.4, -1.0, -0.55).normalize();
    Light {
        name: "sun".into(),
        node,
        kind: LightKind::Directional,
        color: Vec3::new(1.0, 0.96, 0.9),
        intensity: 3.0,
        range: None,
        world_from_light: looking_along(Vec3::ZERO, sun_direction),
        shadow: LightShadow::default(),
        cookie: None,
        mode: LightMode::Realtime,
    }
}

/// Point or spot light `i` of `count` (spots at even `i`), at node `node`, on a
/// golden-angle spiral that keeps any count evenly spread.
fn demo_local_light(i: usize, count: usize, node: usize, shadowed: bool) -> Light {
    let t = (i as f32 + 0.5) / count.max(1) as f32;
    let angle = i as f32 * 2.399_963;
    let radius = 2.0 + 7.0 * t.sqrt();
    let position = Vec3::new(radius * angle.cos(), 1.2 + 1.8 * ((i % 3) as f32 / 2.0), radius * angle.sin());
    let color = PALETTE[i % PALETTE.len()];
    let is_spot = i.is_multiple_of(2);
    let (kind, direction, intensity, range) = if is_spot {
        let target = Vec3::new(position.x * 0.6, 0.0, position.z * 0.6);
        (
            LightKind::Spot {
                inner_cone_rad: (18.0 + 4.0 * (i % 3) as f32).to_radians(),
                outer_cone_rad: (28.0 + 6.0 * (i % 3) as f32).to_radians(),
            },
            (target - position).normalize(),
            40.0,
            Some(9.0),
        )
    } else {
        (LightKind::Point, Vec3::NEG_Y, 8.0, Some(5.0 + (i % 4) as f32))
    };
    let kind_name = if is_spot { "spot" } else { "point" };
    Light {
        name: format!("{kind_name} {i}"),
        node,
        kind,
        color,
        intensity,
        range,
        world_from_light: looking_along(position, direction),
        shadow: if shadowed {
            LightShadow::default()
        } else {
            LightShadow { mode: ShadowMode::None, ..LightShadow::default() }
        },
        cookie: None,
        mode: LightMode::Realtime,
    }
}

/// The demo's camera, at node `node`, looking down at the centre from the front.
fn demo_camera(node: usize) -> Camera {
    let eye = Vec3::new(0.0, 7.5, 13.0);
    let view_from_world = Mat4::look_at_rh(eye, Vec3::new(0.0, 0.5, 0.0), Vec3::Y);
    Camera {
        name: "demo camera".into(),
        node,
        projection: chiaro_math::camera::Projection::Perspective { yfov_rad: 50f32.to_radians() },
        znear: 0.1,
        zfar: None,
        aspect_ratio: None,
        world_from_view: view_from_world.inverse(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn demo_has_the_requested_lights() {
        for n in [0, 4, 16, 64] {
            let s = demo_scene(n);
            assert_eq!(s.lights.len(), n + 1);
            assert_eq!(s.lights.iter().filter(|l| l.kind == LightKind::Directional).count(), 1);
            if n >= 2 {
                assert!(s.lights.iter().any(|l| matches!(l.kind, LightKind::Spot { .. })));
                assert!(s.lights.iter().any(|l| l.kind == LightKind::Point));
            }
        }
    }

    #[test]
    fn demo_shadows_the_requested_lights() {
        let casting = |s: &Scene, kind: fn(&LightKind) -> bool| {
            s.lights.iter().filter(|l| kind(&l.kind) && l.shadow.casts()).count()
        };
        let s = demo_scene(64);
        assert_eq!(casting(&s, |k| matches!(k, LightKind::Spot { .. })), 4);
        assert_eq!(casting(&s, |k| *k == LightKind::Point), 2);
        let s = demo_scene_with_shadows(32, 16, 0);
        assert_eq!(casting(&s, |k| matches!(k, LightKind::Spot { .. })), 16);
        assert_eq!(casting(&s, |k| *k == LightKind::Point), 0);
    }

    #[test]
    fn demo_spots_point_down_at_the_floor() {
        let s = demo_scene(DEMO_LOCAL_LIGHTS);
        for l in &s.lights {
            if matches!(l.kind, LightKind::Spot { .. }) {
                assert!(l.direction().y < -0.3, "{}", l.name);
                assert!((l.direction().length() - 1.0).abs() < 1e-5);
            }
        }
        assert!(s.triangle_count() > 1000);
        assert!(!s.bounds().is_empty());
    }
}
