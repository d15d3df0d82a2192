//! The BVH's alpha: clipped casters block only where alpha passes the cutoff, dithered
//! casters let `1 - alpha` through, and materials that cast nothing block nothing.

use super::*;
use chiaro_scene::{ColorSpace, Image, Material, Mesh, SamplerDesc, TextureRef, shapes};
use glam::Mat4;

/// A 2 m plane at y = 0 (UVs 0..1 across it) with one material, seen from above.
fn plane_scene(material: Material, images: Vec<Image>) -> Scene {
    let mut plane = shapes::plane(2.0, 1);
    plane.material = Some(0);
    Scene {
        meshes: vec![Mesh::of_triangles("plane".into(), vec![plane])],
        materials: vec![material],
        images,
        instances: vec![MeshInstance {
            mesh: 0,
            node: 0,
            name: "plane".into(),
            world_from_local: Mat4::IDENTITY,
            cast_shadows: CastShadows::On,
            receive_shadows: true,
            is_static: true,
            lightmap: None,
            gpu_instance: None,
            label: 0,
        }],
        ..Scene::default()
    }
}

/// 2x2 alpha: opaque where x == y (nearest sampling).
fn checker_material(alpha_mode: AlphaMode, casting: ShadowCasting) -> (Material, Vec<Image>) {
    let texel = |a: u8| [255u8, 255, 255, a];
    let image = Image {
        name: "checker".into(),
        width: 2,
        height: 2,
        rgba8: [texel(255), texel(0), texel(0), texel(255)].concat(),
        file_mips: Vec::new(),
        basis_source: None,
        color_space: ColorSpace::Srgb,
    };
    let material = Material {
        alpha_mode,
        shadow_casting: casting,
        base_color_texture: Some(TextureRef {
            image: 0,
            sampler: SamplerDesc { mag_linear: false, ..SamplerDesc::default() },
            tex_coord: 0,
            transform: Default::default(),
        }),
        ..Material::default()
    };
    (material, vec![image])
}

/// Where (x, z) on the plane falls in the checker: the plane's UVs are (x + 1, z + 1),
/// so the 2x2 texture repeats every metre.
fn opaque_at(x: f32, z: f32) -> bool {
    let (u, v) = ((x + 1.0).fract(), (z + 1.0).fract());
    (u < 0.5) == (v < 0.5)
}

#[test]
fn clipped_casters_block_only_where_alpha_passes() {
    let (material, images) = checker_material(AlphaMode::Mask, ShadowCasting::Clip);
    let bvh = SceneBvh::build(&plane_scene(material, images));
    let mut checked = 0;
    for (x, z) in [(-0.75, -0.75), (-0.25, -0.75), (0.25, 0.25), (0.75, 0.25), (-0.8, 0.3), (0.2, 0.9)] {
        let origin = Vec3::new(x, 1.0, z);
        let blocked = bvh.occluded(origin, Vec3::NEG_Y, f32::INFINITY);
        assert_eq!(blocked, opaque_at(x, z), "({x}, {z})");
        // The camera sees the same holes.
        assert_eq!(bvh.closest_hit(origin, Vec3::NEG_Y, f32::INFINITY).is_some(), opaque_at(x, z));
        checked += 1;
    }
    assert_eq!(checked, 6);
}

#[test]
fn dithered_casters_let_one_minus_alpha_through_each_time() {
    let material = Material {
        alpha_mode: AlphaMode::Blend,
        base_color: glam::Vec4::new(1.0, 1.0, 1.0, 0.3),
        shadow_casting: ShadowCasting::Dither,
        ..Material::default()
    };
    let mut scene = plane_scene(material, Vec::new());
    // A second pane 0.5 m above the first.
    let mut second = scene.instances[0].clone();
    second.world_from_local = Mat4::from_translation(Vec3::new(0.0, 0.5, 0.0));
    scene.instances.push(second);
    let bvh = SceneBvh::build(&scene);
    let through = bvh.transmittance(Vec3::new(0.1, 2.0, 0.2), Vec3::NEG_Y, f32::INFINITY);
    assert!((through - 0.7 * 0.7).abs() < 1e-6, "{through}");
    // Blended glass is still seen by the camera.
    assert!(bvh.closest_hit(Vec3::new(0.1, 2.0, 0.2), Vec3::NEG_Y, f32::INFINITY).is_some());
    // Between the panes, one is crossed.
    let through = bvh.transmittance(Vec3::new(0.1, 0.25, 0.2), Vec3::Y, f32::INFINITY);
    assert!((through - 0.7).abs() < 1e-6, "{through}");
}

#[test]
fn transmissive_casters_let_their_colour_through_each_time() {
    let red = Vec3::new(0.9, 0.3, 0.1);
    // Double-sided, as a pane: either face tints.
    let mut material =
        Material { base_color: red.extend(1.0), metallic: 0.0, double_sided: true, ..Material::default() };
    material.layers.transmission = 1.0;
    let per_crossing = material.shadow_transmittance().expect("transmissive");
    assert!((per_crossing - red * 0.96).abs().max_element() < 1e-6, "{per_crossing}");
    let mut scene = plane_scene(material, Vec::new());
    let mut second = scene.instances[0].clone();
    second.world_from_local = Mat4::from_translation(Vec3::new(0.0, 0.5, 0.0));
    scene.instances.push(second);
    let bvh = SceneBvh::build(&scene);
    let through = bvh.transmittance_rgb(Vec3::new(0.1, 2.0, 0.2), Vec3::NEG_Y, f32::INFINITY);
    assert!((through - per_crossing * per_crossing).abs().max_element() < 1e-6, "{through}");
    let mean = bvh.transmittance(Vec3::new(0.1, 2.0, 0.2), Vec3::NEG_Y, f32::INFINITY);
    assert!((mean - (through.x + through.y + through.z) / 3.0).abs() < 1e-6);
    // The camera sees the glass.
    assert!(bvh.closest_hit(Vec3::new(0.1, 2.0, 0.2), Vec3::NEG_Y, f32::INFINITY).is_some());
    // A transmissive surface that is also metal lets nothing through.
    let mut metal = Material { metallic: 1.0, double_sided: true, ..Material::default() };
    metal.layers.transmission = 1.0;
    let bvh = SceneBvh::build(&plane_scene(metal, Vec::new()));
    assert_eq!(bvh.transmittance_rgb(Vec3::new(0.1, 2.0, 0.2), Vec3::NEG_Y, f32::INFINITY), Vec3::ZERO);
}

#[test]
fn materials_that_cast_off_are_seen_but_block_nothing() {
    let material = Material { shadow_casting: ShadowCasting::Off, ..Material::default() };
    let bvh = SceneBvh::build(&plane_scene(material, Vec::new()));
    let origin = Vec3::new(0.1, 1.0, 0.2);
    assert!(bvh.closest_hit(origin, Vec3::NEG_Y, f32::INFINITY).is_some());
    assert_eq!(bvh.transmittance(origin, Vec3::NEG_Y, f32::INFINITY), 1.0);
}

#[test]
fn barycentrics_rebuild_the_point() {
    let (a, b, c) = (Vec3::ZERO, Vec3::X, Vec3::new(0.0, 0.0, 2.0));
    let p = a * 0.2 + b * 0.3 + c * 0.5;
    let w = barycentrics(a, b, c, p);
    assert!((w[0] - 0.2).abs() < 1e-6 && (w[1] - 0.3).abs() < 1e-6 && (w[2] - 0.5).abs() < 1e-6, "{w:?}");
}

#[test]
fn vertex_colour_alpha_multiplies_the_materials() {
    // Plane corners: x = -1 at alpha 0, x = +1 at alpha 1; alpha rises linearly across.
    let material = Material {
        alpha_mode: AlphaMode::Mask,
        alpha_cutoff: 0.5,
        base_color: glam::Vec4::new(1.0, 1.0, 1.0, 0.8),
        shadow_casting: ShadowCasting::Clip,
        ..Material::default()
    };
    let mut scene = plane_scene(material, Vec::new());
    let plane = &mut scene.meshes[0].primitives[0];
    plane.colors = plane.positions.iter().map(|p| glam::Vec4::new(1.0, 1.0, 1.0, 0.5 * (p.x + 1.0))).collect();
    let bvh = SceneBvh::build(&scene);
    // 0.8 * alpha passes 0.5 where alpha > 0.625, x > 0.25.
    for (x, blocked) in [(-0.5, false), (0.2, false), (0.3, true), (0.9, true)] {
        assert_eq!(bvh.occluded(Vec3::new(x, 1.0, 0.1), Vec3::NEG_Y, f32::INFINITY), blocked, "x = {x}");
    }
}

#[test]
fn a_single_sided_transmissive_solid_tints_once_a_double_sided_one_twice() {
    let red = Vec3::new(0.9, 0.3, 0.1);
    for (double_sided, mirrored, crossings) in [(false, false, 1), (true, false, 2), (false, true, 1)] {
        let mut material = Material { base_color: red.extend(1.0), metallic: 0.0, double_sided, ..Material::default() };
        material.layers.transmission = 1.0;
        let per_crossing = material.shadow_transmittance().unwrap();
        let mut cube = shapes::cuboid(Vec3::ONE);
        cube.material = Some(0);
        let mirror = if mirrored { Mat4::from_scale(Vec3::new(-1.0, 1.0, 1.0)) } else { Mat4::IDENTITY };
        let scene = Scene {
            meshes: vec![Mesh::of_triangles("cube".into(), vec![cube])],
            materials: vec![material],
            instances: vec![MeshInstance {
                mesh: 0,
                node: 0,
                name: "cube".into(),
                world_from_local: Mat4::from_translation(Vec3::new(0.0, 1.0, 0.0)) * mirror,
                cast_shadows: CastShadows::On,
                receive_shadows: true,
                is_static: true,
                lightmap: None,
                gpu_instance: None,
                label: 0,
            }],
            ..Scene::default()
        };
        let bvh = SceneBvh::build(&scene);
        // From under the cube up to a light above it, and from above down through it.
        for (origin, direction) in [(Vec3::new(0.1, 0.0, 0.2), Vec3::Y), (Vec3::new(0.1, 2.0, 0.2), Vec3::NEG_Y)] {
            let through = bvh.transmittance_rgb(origin, direction, f32::INFINITY);
            let expected = per_crossing.powf(crossings as f32);
            assert!(
                (through - expected).abs().max_element() < 1e-5,
                "double-sided {double_sided}, mirrored {mirrored}: {through}, expected {expected}"
            );
        }
    }
}
