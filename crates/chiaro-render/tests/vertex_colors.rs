//! Vertex colours (COLOR_0) multiply the base colour and its alpha as a material's factor
//! does: a floor coloured by its vertices and a cut-out plank whose vertices carry its
//! alpha render, in both paths, as the same scene with those values in the materials,
//! shadow of the alpha-tested plank included.

mod common;

use chiaro_render::{FrameOptions, View};
use chiaro_scene::{AlphaMode, Light, LightKind, Material, Mesh, MeshInstance, RenderPath, Scene, shapes};
use common::*;
use glam::{Mat4, Vec3, Vec4};

const FLOOR_COLOR: Vec4 = Vec4::new(0.8, 0.3, 0.1, 1.0);

/// A sunlit floor and, 1 m above it, a plank of the MASK material 1; `by_vertex` puts the
/// floor's colour and the plank's alpha (`plank_alpha`) in vertex colours, else in the
/// materials' factors.
fn scene(by_vertex: bool, plank_alpha: f32) -> Scene {
    let sun = Light { intensity: 3.0, ..Light::new(LightKind::Directional, Vec3::ZERO, Vec3::new(-0.2, -1.0, -0.1)) };
    let mut scene = floor_scene(6.0, Vec3::new(0.0, 5.0, 0.0), vec![sun]);
    let mut plank = shapes::plane(1.5, 2);
    plank.material = Some(1);
    let factor = |by: Vec4| if by_vertex { Vec4::ONE } else { by };
    scene.materials[0].base_color = factor(FLOOR_COLOR);
    scene.materials.push(Material {
        name: "plank".into(),
        base_color: factor(Vec4::new(1.0, 1.0, 1.0, plank_alpha)),
        alpha_mode: AlphaMode::Mask,
        alpha_cutoff: 0.5,
        double_sided: true,
        shadow_casting: chiaro_scene::ShadowCasting::Clip,
        ..Material::default()
    });
    if by_vertex {
        let floor = &mut scene.meshes[0].primitives[0];
        floor.colors = vec![FLOOR_COLOR; floor.positions.len()];
        plank.colors = vec![Vec4::new(1.0, 1.0, 1.0, plank_alpha); plank.positions.len()];
    }
    scene.meshes.push(Mesh::of_triangles("plank".into(), vec![plank]));
    let mut instance: MeshInstance = scene.instances[0].clone();
    instance.mesh = 1;
    instance.node = 5;
    instance.world_from_local = Mat4::from_translation(Vec3::new(0.0, 1.0, 0.0));
    scene.instances.push(instance);
    scene
}

fn hdr(scene: &Scene, path: RenderPath) -> Vec<[f32; 4]> {
    let mut settings = unlit_settings();
    settings.render.path = path;
    let mut renderer = renderer();
    let prepared = renderer.prepare(scene).unwrap();
    let view = View::from_camera(scene, 0, 64, 64);
    let options = FrameOptions { readback: true, ..Default::default() };
    renderer.render(scene, &prepared, &view, &settings, options).unwrap().hdr
}

/// The largest difference between two images, relative to the brightest channel.
fn worst_difference(a: &[[f32; 4]], b: &[[f32; 4]]) -> f32 {
    let peak = a.iter().flat_map(|p| &p[..3]).fold(0.0f32, |m, &c| m.max(c));
    a.iter().zip(b).flat_map(|(p, q)| (0..3).map(move |c| (p[c] - q[c]).abs())).fold(0.0, f32::max) / peak
}

#[test]
fn vertex_colours_shade_and_cast_as_material_factors_do() {
    for path in [RenderPath::Forward, RenderPath::Deferred] {
        for plank_alpha in [0.2, 1.0] {
            let by_material = hdr(&scene(false, plank_alpha), path);
            let by_vertex = hdr(&scene(true, plank_alpha), path);
            let worst = worst_difference(&by_material, &by_vertex);
            println!("{path:?}, plank alpha {plank_alpha}: worst difference {worst:.2e}");
            assert!(worst < 1e-3, "{path:?}, plank alpha {plank_alpha}: vertex colours differ by {worst}");
        }
        // The plank is there to be cut: opaque, it hides and shadows the floor's middle.
        let cut = hdr(&scene(true, 0.2), path);
        let opaque = hdr(&scene(true, 1.0), path);
        assert!(worst_difference(&cut, &opaque) > 0.5, "{path:?}: the plank changes nothing");
        // The floor, beside the plank, takes the vertices' orange.
        let corner = cut[64 * 32 + 8];
        assert!(corner[0] > 2.0 * corner[1] && corner[1] > 2.0 * corner[2], "{path:?}: {corner:?}");
    }
}
