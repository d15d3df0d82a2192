//! KHR_materials_unlit on both paths: an unlit floor shows its base colour, exposed and
//! tone mapped by chiaro_math::tonemap, whether the lights reach it, a caster shadows it,
//! or only ambient light would; and an unlit caster still casts its shadow on a lit
//! floor. Which floor pixels lie in shadow is read from the shadow AOVs of the same scene
//! with the floor lit, so the test measures where the shadows are rather than assuming it.

mod common;

use chiaro_math::tonemap::{exposure_scale, pbr_neutral};
use chiaro_render::{FrameOptions, FrameOutput, Renderer, View};
use chiaro_scene::{CastShadows, Light, LightKind, Material, RenderPath, Scene, Settings};
use common::*;
use glam::Vec3;

const SIZE: u32 = 128;

/// A shadow AOV below this is in shadow, above `LIT` out of it; between is penumbra.
const SHADOWED: f32 = 0.05;
const LIT: f32 = 0.95;

/// Fewest pixels each class must hold for the comparison to mean something (the floor
/// covers most of the 16384).
const MIN_PIXELS: usize = 100;

/// The HDR target holds pre-exposed half floats: 11 bits of mantissa, so 2^-11 relative,
/// doubled for the exposure's division on read-back.
const HDR_TOLERANCE: f32 = 1.0e-3;

fn sun() -> Light {
    Light { intensity: 3.0, ..Light::new(LightKind::Directional, Vec3::ZERO, Vec3::new(0.9, -1.0, 1.0)) }
}

fn spot() -> Light {
    Light {
        intensity: 40.0,
        range: Some(10.0),
        ..Light::new(
            LightKind::Spot { inner_cone_rad: 0.4, outer_cone_rad: 0.7 },
            Vec3::new(-1.5, 3.0, -1.0),
            Vec3::new(0.4, -1.0, 0.3),
        )
    }
}

/// A floor (material 0) under a unit box on material 1, seen from above and in front.
fn floor_and_box(floor: Material, caster: Material, lights: Vec<Light>) -> Scene {
    let mut scene = floor_scene(10.0, Vec3::ZERO, lights);
    look_from(&mut scene, Vec3::new(0.0, 6.0, 5.0), Vec3::new(0.3, 0.0, 0.5));
    scene.materials = vec![floor, caster];
    add_box(&mut scene, Vec3::new(0.0, 0.5, 0.0), Vec3::ONE, 0.3, CastShadows::On);
    let cube = scene.instances.last().unwrap().mesh;
    scene.meshes[cube].primitives[0].material = Some(1);
    scene
}

fn lit(name: &str, color: Vec3) -> Material {
    Material { name: name.into(), base_color: color.extend(1.0), metallic: 0.0, roughness: 0.6, ..Material::default() }
}

fn unlit(name: &str, color: Vec3) -> Material {
    Material { unlit: true, ..lit(name, color) }
}

fn render(renderer: &mut Renderer, scene: &Scene, settings: &Settings, path: RenderPath) -> FrameOutput {
    let mut settings = settings.clone();
    settings.render.path = path;
    // One sample a pixel: no pixel mixes the floor with the box's edge.
    settings.render.msaa = 1;
    let view = View::from_camera(scene, 0, SIZE, SIZE);
    let prepared = renderer.prepare(scene).expect("prepare");
    let options = FrameOptions { aovs: true, shadow_aovs: true, readback: true, ..Default::default() };
    let frame = renderer.render(scene, &prepared, &view, &settings, options).expect("render");
    let deferred = frame.graph.passes.contains(&"deferred lights");
    assert_eq!(deferred, path == RenderPath::Deferred, "{path:?} ran {:?}", frame.graph.passes);
    frame
}

/// Floor pixels (y = 0 in the position AOV), split by the shadow AOVs of every light:
/// (in shadow of some light, lit by all).
fn floor_pixels_by_shadow(frame: &FrameOutput) -> (Vec<usize>, Vec<usize>) {
    let aovs = frame.aovs.as_ref().expect("aovs");
    let (mut shadowed, mut lit) = (Vec::new(), Vec::new());
    for i in 0..frame.hdr.len() {
        let y = aovs.position_ws[i][1];
        if !(y.is_finite() && y.abs() < 1e-3) {
            continue;
        }
        let terms = frame.shadow_aovs.iter().map(|aov| aov[i]);
        if terms.clone().any(|t| t < SHADOWED) {
            shadowed.push(i);
        } else if terms.clone().all(|t| t > LIT) {
            lit.push(i);
        }
    }
    (shadowed, lit)
}

fn mean_radiance(frame: &FrameOutput, pixels: &[usize]) -> Vec3 {
    pixels.iter().map(|&i| Vec3::from_slice(&frame.hdr[i][..3])).sum::<Vec3>() / pixels.len() as f32
}

#[test]
fn an_unlit_floor_shows_its_tone_mapped_base_colour_in_and_out_of_shadow() {
    let base = Vec3::new(0.55, 0.3, 0.1);
    let mut settings = Settings::default();
    // Brighter than the default, so the red channel reaches the tone mapper's roll-off;
    // the default ambient stays on, and must not reach the floor either.
    settings.render.exposure_ev100 = -1.0;
    assert!(settings.render.ambient.iter().any(|&a| a > 0.0));
    let exposed = base * exposure_scale(settings.render.exposure_ev100);
    assert!(exposed.max_element() > 0.8, "{exposed}: tone mapping is tested in its roll-off");
    let display = pbr_neutral(exposed.max(Vec3::ZERO));
    let expected_ldr = [0, 1, 2].map(|c| srgb_encode(display[c]) * 255.0);

    let mut renderer = renderer();
    let caster = lit("white", Vec3::ONE);
    for path in [RenderPath::Forward, RenderPath::Deferred] {
        // Where the shadows fall: the same scene with the floor lit.
        let control = floor_and_box(lit("floor", base), caster.clone(), vec![sun(), spot()]);
        let control = render(&mut renderer, &control, &settings, path);
        let (shadowed, lit_pixels) = floor_pixels_by_shadow(&control);
        assert!(
            shadowed.len() >= MIN_PIXELS && lit_pixels.len() >= MIN_PIXELS,
            "{path:?}: {} shadowed, {} lit",
            shadowed.len(),
            lit_pixels.len()
        );
        let (control_shadowed, control_lit) =
            (mean_radiance(&control, &shadowed), mean_radiance(&control, &lit_pixels));
        // Shadowed pixels still get the other light and ambient: darker, not dark.
        assert!(
            control_shadowed.max_element() < 0.9 * control_lit.max_element(),
            "{path:?}: the lit floor's shadow ({control_shadowed}) is not darker than its light ({control_lit})"
        );

        let scene = floor_and_box(unlit("floor", base), caster.clone(), vec![sun(), spot()]);
        let frame = render(&mut renderer, &scene, &settings, path);
        let (mut worst_hdr, mut worst_ldr) = (0.0f32, 0.0f32);
        for &i in shadowed.iter().chain(&lit_pixels) {
            let radiance = Vec3::from_slice(&frame.hdr[i][..3]);
            worst_hdr = worst_hdr.max(((radiance - base).abs() / base).max_element());
            for (c, expected) in expected_ldr.iter().enumerate() {
                worst_ldr = worst_ldr.max((frame.ldr[4 * i + c] as f32 - expected).abs());
            }
            // Its shading used no shadow, as the AOV says.
            assert!(frame.shadow_aovs.iter().all(|aov| aov[i] == 1.0), "{path:?}: pixel {i} reports a shadow");
        }
        let (in_shadow, in_light) = (mean_radiance(&frame, &shadowed), mean_radiance(&frame, &lit_pixels));
        println!(
            "{path:?}: {} shadowed and {} lit floor pixels (lit floor: {control_shadowed} vs {control_lit}); \
             unlit floor: {in_shadow} vs {in_light}, base {base}; worst {:.5} relative, {worst_ldr:.2}/255 \
             from sRGB {expected_ldr:?}",
            shadowed.len(),
            lit_pixels.len(),
            worst_hdr,
        );
        assert!(worst_hdr <= HDR_TOLERANCE, "{path:?}: an unlit floor pixel differs from base colour by {worst_hdr}");
        assert!(
            worst_ldr <= 1.0,
            "{path:?}: an unlit floor pixel differs from the tone-mapped base by {worst_ldr}/255"
        );
        assert!(
            ((in_shadow - in_light).abs() / base).max_element() <= HDR_TOLERANCE,
            "{path:?}: in shadow {in_shadow}, out of it {in_light}"
        );
    }
}

#[test]
fn an_unlit_caster_casts_the_shadow_a_lit_one_does() {
    let mut settings = Settings::default();
    settings.render.ambient = [0.0; 3];
    let floor = lit("floor", Vec3::splat(0.8));
    let box_color = Vec3::new(0.2, 0.5, 0.9);
    let mut renderer = renderer();
    for path in [RenderPath::Forward, RenderPath::Deferred] {
        let lit_box = floor_and_box(floor.clone(), lit("box", box_color), vec![sun()]);
        let (lit_shadowed, _) = floor_pixels_by_shadow(&render(&mut renderer, &lit_box, &settings, path));
        let unlit_box = floor_and_box(floor.clone(), unlit("box", box_color), vec![sun()]);
        let frame = render(&mut renderer, &unlit_box, &settings, path);
        let (shadowed, lit_pixels) = floor_pixels_by_shadow(&frame);
        let (dark, bright) = (mean_radiance(&frame, &shadowed), mean_radiance(&frame, &lit_pixels));
        println!(
            "{path:?}: unlit box shadows {} floor pixels, lit box {}; floor radiance {dark} in shadow, {bright} lit",
            shadowed.len(),
            lit_shadowed.len()
        );
        assert!(shadowed.len() >= MIN_PIXELS, "{path:?}: the unlit box shadows only {} pixels", shadowed.len());
        assert_eq!(shadowed, lit_shadowed, "{path:?}: the unlit box's shadow differs from the lit box's");
        assert!(
            dark.max_element() < 0.05 * bright.max_element(),
            "{path:?}: the floor in the unlit box's shadow ({dark}) is not dark beside its lit part ({bright})"
        );
    }
}
