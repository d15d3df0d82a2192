//! Small scenes made in code for tests and examples: a white floor with a camera, boxes
//! to stand on it, point lights, and settings with no ambient term, so that measured
//! radiance comes from the lights alone.

use crate::settings::Settings;
use crate::shapes;
use crate::types::{Camera, CastShadows, Light, LightKind, Material, Mesh, MeshInstance, Scene};
use glam::{Mat4, Vec3};

/// Settings with no ambient term, so only the punctual lights contribute.
pub fn unlit_settings() -> Settings {
    let mut s = Settings::default();
    s.render.ambient = [0.0; 3];
    s
}

/// A white, fully rough dielectric floor of `size` metres in the XZ plane, seen from
/// `eye` looking at the origin (+Z up in the view, so a camera straight above works).
pub fn floor_scene(size: f32, eye: Vec3, lights: Vec<Light>) -> Scene {
    let mut floor = shapes::plane(size, 4);
    floor.material = Some(0);
    Scene {
        meshes: vec![Mesh { name: "floor".into(), primitives: vec![floor] }],
        instances: vec![MeshInstance {
            mesh: 0,
            node: 0,
            name: "floor".into(),
            world_from_local: Mat4::IDENTITY,
            cast_shadows: CastShadows::On,
            receive_shadows: true,
            is_static: true,
            lightmap: None,
            label: 0,
        }],
        materials: vec![Material {
            name: "white".into(),
            base_color: glam::Vec4::ONE,
            metallic: 0.0,
            roughness: 1.0,
            ..Material::default()
        }],
        lights,
        cameras: vec![Camera {
            name: "test".into(),
            node: 1,
            yfov_rad: 70f32.to_radians(),
            znear: 0.05,
            zfar: None,
            aspect_ratio: None,
            world_from_view: Mat4::look_at_rh(eye, Vec3::ZERO, Vec3::Z).inverse(),
        }],
        ..Scene::default()
    }
}

/// A white point light named "point" on node 10.
pub fn point_light(position: Vec3, intensity: f32, range: Option<f32>) -> Light {
    Light { name: "point".into(), node: 10, intensity, range, ..Light::new(LightKind::Point, position, Vec3::NEG_Z) }
}

/// Adds a box (white, like the floor) of `size` at `position`, turned by `yaw_rad` about Y.
pub fn add_box(scene: &mut Scene, position: Vec3, size: Vec3, yaw_rad: f32, cast: CastShadows) {
    let mesh = match scene.meshes.iter().position(|m| m.name == "unit box") {
        Some(m) => m,
        None => {
            let mut cube = shapes::cuboid(Vec3::ONE);
            cube.material = Some(0);
            scene.meshes.push(Mesh { name: "unit box".into(), primitives: vec![cube] });
            scene.meshes.len() - 1
        }
    };
    let node = 100 + scene.instances.len();
    scene.instances.push(MeshInstance {
        mesh,
        node,
        name: format!("box {node}"),
        world_from_local: Mat4::from_scale_rotation_translation(size, glam::Quat::from_rotation_y(yaw_rad), position),
        cast_shadows: cast,
        receive_shadows: true,
        is_static: true,
        lightmap: None,
        label: 0,
    });
}

/// Points the scene's first camera from `eye` at `target`.
pub fn look_from(scene: &mut Scene, eye: Vec3, target: Vec3) {
    scene.cameras[0].world_from_view = Mat4::look_at_rh(eye, target, Vec3::Y).inverse();
}
