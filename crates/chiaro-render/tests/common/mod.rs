//! Shared set-up for the GPU tests: a renderer on whatever adapter is present (the
//! software Vulkan device in CI) and small lit scenes whose radiance the tests predict.
//! No adapter is a failure, never a skip.

#![allow(dead_code)]

use chiaro_render::renderer::FrameOutput;
use chiaro_render::{FrameOptions, GpuContext, Renderer, View};
use chiaro_scene::{
    Camera, CastShadows, Light, LightKind, LightShadow, Material, Mesh, MeshInstance, Scene, Settings, shapes,
};
use glam::{Mat4, Vec3};

pub fn renderer() -> Renderer {
    let ctx = GpuContext::new().unwrap_or_else(|e| panic!("GPU tests need an adapter: {e}"));
    Renderer::new(ctx).expect("renderer")
}

/// Settings with no ambient term, so only the punctual lights contribute.
pub fn unlit_settings() -> Settings {
    let mut s = Settings::default();
    s.render.ambient = [0.0; 3];
    s
}

/// A white, fully rough dielectric floor of `size` metres, seen from `eye`.
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

pub fn point_light(position: Vec3, intensity: f32, range: Option<f32>) -> Light {
    Light {
        name: "point".into(),
        node: 10,
        kind: LightKind::Point,
        color: Vec3::ONE,
        intensity,
        range,
        position,
        direction: Vec3::NEG_Z,
        shadow: LightShadow::default(),
    }
}

pub fn render(renderer: &mut Renderer, scene: &Scene, settings: &Settings, size: u32) -> FrameOutput {
    let view = View::from_camera(scene, 0, size, size);
    let prepared = renderer.prepare(scene).expect("prepare");
    renderer
        .render(scene, &prepared, &view, settings, FrameOptions { aovs: true, readback: true, ..Default::default() })
        .expect("render")
}

/// Covered pixels: (index, world position, normal, rendered radiance).
pub fn surface_pixels(frame: &FrameOutput) -> Vec<(usize, Vec3, Vec3, Vec3)> {
    let aovs = frame.aovs.as_ref().expect("aovs");
    (0..frame.hdr.len())
        .filter(|&i| aovs.position_ws[i][0].is_finite())
        .map(|i| {
            let h = frame.hdr[i];
            (i, Vec3::from(aovs.position_ws[i]), Vec3::from(aovs.normal_ws[i]), Vec3::new(h[0], h[1], h[2]))
        })
        .collect()
}

/// Adds an axis-aligned box (white, like the floor) turned by `yaw_rad` about Y.
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
    });
}

/// Points the scene's camera from `eye` at `target`.
pub fn look_from(scene: &mut Scene, eye: Vec3, target: Vec3) {
    scene.cameras[0].world_from_view = Mat4::look_at_rh(eye, target, Vec3::Y).inverse();
}

pub fn compare(scene: &Scene, settings: &Settings, size: u32) -> chiaro_render::shadow_compare::ShadowComparison {
    let mut renderer = renderer();
    let prepared = renderer.prepare(scene).unwrap();
    let view = View::from_camera(scene, 0, size, size);
    chiaro_render::shadow_compare::compare_shadows(&mut renderer, scene, &prepared, &view, settings).unwrap()
}
