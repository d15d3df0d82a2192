//! Shadows of alpha-tested and transparent surfaces against the ray-traced reference on
//! the software device: a checkerboard MASK quad above a floor throws a checkerboard
//! shadow for a sun, a spot and a point light, and a uniformly transparent pane darkens
//! its dithered, filtered shadow in proportion to its opacity.

mod common;

use chiaro_compare::{ShadowComparison, assert_agrees_with_reference};
use chiaro_render::ShadowStatus;
use chiaro_scene::{
    AlphaMode, CastShadows, ColorSpace, Image, Light, LightKind, Material, SamplerDesc, Scene, ShadowCasting,
    TextureRef, shapes,
};
use common::*;
use glam::{Mat4, Vec3, Vec4};

/// A 2x2 alpha checker, opaque where x == y; nearest sampling keeps its edges crisp.
fn checker_image() -> Image {
    let texel = |a: u8| [255u8, 255, 255, a];
    Image {
        name: "checker".into(),
        width: 2,
        height: 2,
        rgba8: [texel(255), texel(0), texel(0), texel(255)].concat(),
        file_mips: Vec::new(),
        basis_source: None,
        color_space: ColorSpace::Srgb,
    }
}

/// Adds a horizontal 2 m quad at `height` with `material` (UVs 0..2: the texture repeats
/// every metre), casting with both faces.
fn add_quad(scene: &mut Scene, height: f32, material: Material) {
    let at = Mat4::from_translation(Vec3::new(0.0, height, 0.0));
    add_mesh(scene, "quad", shapes::plane(2.0, 1), material, at, CastShadows::TwoSided);
}

fn checker_scene(light: Light) -> Scene {
    let mut scene = floor_scene(12.0, Vec3::ZERO, vec![light]);
    look_from(&mut scene, Vec3::new(0.5, 7.0, 4.0), Vec3::new(0.0, 0.0, 0.0));
    scene.images.push(checker_image());
    add_quad(
        &mut scene,
        1.5,
        Material {
            name: "checker".into(),
            alpha_mode: AlphaMode::Mask,
            alpha_cutoff: 0.5,
            shadow_casting: ShadowCasting::Clip,
            base_color_texture: Some(TextureRef {
                image: 0,
                sampler: SamplerDesc { mag_linear: false, min_linear: false, ..SamplerDesc::default() },
                tex_coord: 0,
                transform: Default::default(),
            }),
            double_sided: true,
            ..Material::default()
        },
    );
    scene
}

/// Floor pixels (y = 0) the quad's shadow could fall on: the reference has both lit and
/// shadowed pixels there, and so must the render. Returns (lit, shadowed) counts of the
/// rendered shadow AOV over the pixels where the reference sees floor under the quad.
fn checker_counts(result: &ShadowComparison, under: impl Fn(Vec3) -> bool) -> (usize, usize) {
    let (mut lit, mut shadowed) = (0, 0);
    for (i, p) in result.reference.position.iter().enumerate() {
        if let Some(p) = p
            && p.y.abs() < 1e-3
            && under(*p)
        {
            if result.rendered[0][i] > 0.5 {
                lit += 1;
            } else {
                shadowed += 1;
            }
        }
    }
    (lit, shadowed)
}

fn assert_checker_shadow(label: &str, light: Light, under: impl Fn(Vec3) -> bool) {
    let scene = checker_scene(light);
    let result = compare(&scene, &unlit_settings(), 192);
    assert_eq!(result.status[0], ShadowStatus::Mapped, "{label}");
    let c = &result.reports[0].comparison;
    assert!(c.compared > 4000, "{label}: only {} compared", c.compared);
    assert_agrees_with_reference(label, c);
    // A checkerboard, not a solid rectangle: about half of the footprint is lit.
    let (lit, shadowed) = checker_counts(&result, under);
    println!(
        "{label}: {:.3}% of {} compared pixels disagree; {shadowed} of {} pixels under the quad shadowed",
        100.0 * c.disagreement(),
        c.compared,
        lit + shadowed
    );
    let share = shadowed as f32 / (lit + shadowed) as f32;
    assert!((0.3..0.7).contains(&share), "{label}: {shadowed} shadowed of {} under the quad", lit + shadowed);
}

#[test]
fn a_masked_checker_casts_a_checker_shadow_from_the_sun() {
    let sun = Light { intensity: 3.0, ..Light::new(LightKind::Directional, Vec3::ZERO, Vec3::new(0.1, -1.0, 0.05)) };
    // The footprint moves by 0.15 m in x for 1.5 m of height; keep clear of its rim.
    assert_checker_shadow("sun", sun, |p| p.x.abs() < 0.8 && p.z.abs() < 0.8);
}

#[test]
fn a_masked_checker_casts_a_checker_shadow_from_a_spot() {
    let kind = LightKind::Spot { inner_cone_rad: 0.6, outer_cone_rad: 0.8 };
    let spot = Light { intensity: 40.0, range: Some(20.0), ..Light::new(kind, Vec3::new(0.0, 4.0, 0.0), Vec3::NEG_Y) };
    // From 4 m up, the 2 m quad at 1.5 m throws a 3.2 m shadow.
    assert_checker_shadow("spot", spot, |p| p.x.abs() < 1.4 && p.z.abs() < 1.4);
}

#[test]
fn a_masked_checker_casts_a_checker_shadow_from_a_point_light() {
    let point = Light { intensity: 40.0, range: Some(20.0), ..point_light(Vec3::new(0.0, 4.0, 0.0), 40.0, Some(20.0)) };
    assert_checker_shadow("point", point, |p| p.x.abs() < 1.4 && p.z.abs() < 1.4);
}

#[test]
fn a_transparent_pane_darkens_its_shadow_in_proportion_to_opacity() {
    // The hard 2x2 filter averages too few texels of the 4x4 pattern to hide it; the tents
    // average it out. Spreads measured: 0.23 (2x2), 0.003 (3x3, alpha 0.5), 0.01 (5x5).
    for (alpha, filter, max_spread) in [
        (0.25f32, "tent5x5", 0.05),
        (0.5, "tent5x5", 0.05),
        (0.75, "tent5x5", 0.05),
        (0.25, "pcf2x2", 0.3),
        (0.5, "tent3x3", 0.15),
    ] {
        let sun = Light { intensity: 3.0, ..Light::new(LightKind::Directional, Vec3::ZERO, Vec3::NEG_Y) };
        let mut scene = floor_scene(12.0, Vec3::ZERO, vec![sun]);
        // Low, so the camera sees the floor under the pane rather than the pane.
        look_from(&mut scene, Vec3::new(0.0, 0.6, 3.0), Vec3::new(0.0, 0.0, -0.3));
        add_quad(
            &mut scene,
            1.0,
            Material {
                name: "glass".into(),
                alpha_mode: AlphaMode::Blend,
                base_color: Vec4::new(1.0, 1.0, 1.0, alpha),
                shadow_casting: ShadowCasting::Dither,
                double_sided: true,
                ..Material::default()
            },
        );
        let mut settings = unlit_settings();
        settings.shadows.directional.filter = filter.into();
        let result = compare(&scene, &settings, 256);
        // Pixels the reference sees through exactly one pane's worth of light.
        let behind: Vec<f32> = (0..result.rendered[0].len())
            .filter(|&i| {
                result.reference.position[i].is_some_and(|p| p.y.abs() < 1e-3 && p.x.abs() < 0.8 && p.z.abs() < 0.8)
            })
            .map(|i| result.rendered[0][i])
            .collect();
        assert!(behind.len() > 1000, "alpha {alpha}: {} pixels behind the pane", behind.len());
        let mean = behind.iter().sum::<f32>() / behind.len() as f32;
        let spread = (behind.iter().map(|v| (v - mean).powi(2)).sum::<f32>() / behind.len() as f32).sqrt();
        println!(
            "alpha {alpha}, {filter}: shadow term mean {mean:.4}, standard deviation {spread:.4} over {} pixels",
            behind.len()
        );
        assert!((mean - (1.0 - alpha)).abs() < 0.05, "alpha {alpha}, {filter}: mean shadow term {mean}");
        assert!(spread < max_spread, "alpha {alpha}, {filter}: the dither leaves a spread of {spread}");
        assert_agrees_with_reference(&format!("alpha {alpha}, {filter}"), &result.reports[0].comparison);
    }
}
