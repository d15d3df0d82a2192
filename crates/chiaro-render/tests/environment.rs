//! Image-based environment light, measured: a white sphere in a uniform environment (the
//! furnace) sends back exactly the environment's radiance; rough and smooth metals reflect
//! what the split sum with energy compensation predicts; a mirror reflects, and a rough
//! sphere is lit from, the side of the environment the image puts there (and turned by
//! `rotation_deg`); the background is the environment; forward and deferred agree.
//! Environments are written as Radiance .hdr files, read back as users' files are.

mod common;

use chiaro_math::environment::{environment_direction, ibl_weights, split_sum};
use chiaro_render::{FrameOutput, Renderer};
use chiaro_scene::settings::EnvironmentSource;
use chiaro_scene::{RenderPath, Scene, Settings};
use common::*;
use glam::Vec3;
use std::path::PathBuf;

const SIZE: u32 = 256;

/// This test run's folder for the files it writes.
fn scratch_dir() -> PathBuf {
    let dir = std::env::temp_dir().join(format!("chiaro-environment-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Writes a `width` x `width / 2` equirectangular .hdr with radiance `f(direction)`.
fn write_hdr(name: &str, width: u32, f: impl Fn(Vec3) -> Vec3) -> PathBuf {
    let map = chiaro_scene::environment::EnvironmentMap::from_fn(width, f);
    let path = scratch_dir().join(name);
    map.write_hdr(&path).unwrap();
    path
}

/// Settings lit by the environment image at `path` alone, no ambient term, no MSAA.
fn environment_settings(path: PathBuf, path_kind: RenderPath) -> Settings {
    let mut s = unlit_settings();
    s.environment.source = EnvironmentSource::File(path);
    s.render.path = path_kind;
    s.render.msaa = 1;
    s
}

fn sphere(base_color: Vec3, metallic: f32, roughness: f32) -> SphereMaterial {
    SphereMaterial { base_color, metallic, roughness }
}

/// Covered pixels with their view direction: (index, normal, towards the eye, radiance).
fn shaded_pixels(scene: &Scene, frame: &FrameOutput) -> Vec<(usize, Vec3, Vec3, Vec3)> {
    let eye = scene.cameras[0].world_from_view.w_axis.truncate();
    surface_pixels(frame).into_iter().map(|(i, p, n, radiance)| (i, n, (eye - p).normalize(), radiance)).collect()
}

fn render_environment(renderer: &mut Renderer, scene: &Scene, settings: &Settings) -> FrameOutput {
    render(renderer, scene, settings, SIZE)
}

/// Radiance 0.5 everywhere (exact in the .hdr's shared-exponent encoding).
const FURNACE: f32 = 0.5;

#[test]
fn a_white_sphere_in_a_uniform_environment_returns_its_radiance() {
    let path = write_hdr("furnace.hdr", 64, |_| Vec3::splat(FURNACE));
    let mut renderer = renderer();
    for roughness in [1.0, 0.5, 0.1] {
        let scene = spheres_scene(&[sphere(Vec3::ONE, 0.0, roughness)]);
        for path_kind in [RenderPath::Forward, RenderPath::Deferred] {
            let frame = render_environment(&mut renderer, &scene, &environment_settings(path.clone(), path_kind));
            let pixels = shaded_pixels(&scene, &frame);
            assert!(pixels.len() > 5_000, "{}", pixels.len());
            let worst = pixels.iter().map(|(.., r)| (*r / FURNACE - Vec3::ONE).abs().max_element()).fold(0.0, f32::max);
            println!("furnace, roughness {roughness}, {path_kind:?}: worst |radiance / L - 1| {worst:.4}");
            assert!(worst < 0.01, "roughness {roughness} {path_kind:?}: {worst}");
            // The background is the environment too.
            let positions = &frame.aovs.as_ref().expect("aovs").position_ws;
            let background: Vec<&[f32; 4]> =
                frame.hdr.iter().zip(positions).filter(|(_, p)| !p[0].is_finite()).map(|(h, _)| h).collect();
            assert!(background.len() > 10_000, "{}", background.len());
            assert!(background.iter().all(|h| (h[0] / FURNACE - 1.0).abs() < 0.01), "background");
        }
    }
}

#[test]
fn the_ldr_light_buffer_and_msaa_draw_the_environment_too() {
    // The deferred path's 8-bit exp2(-light) buffer and the forward path's multisampled
    // target take the environment and its background through their own pipelines.
    let path = write_hdr("furnace-ldr.hdr", 64, |_| Vec3::splat(FURNACE));
    let scene = spheres_scene(&[sphere(Vec3::ONE, 0.0, 0.5)]);
    let mut renderer = renderer();
    let mut ldr = environment_settings(path.clone(), RenderPath::Deferred);
    ldr.render.light_buffer = chiaro_scene::LightBuffer::LdrExp2;
    let mut msaa = environment_settings(path, RenderPath::Forward);
    msaa.render.msaa = 4;
    for (name, settings, tolerance) in [("ldr-exp2", ldr, 0.02), ("4x msaa", msaa, 0.01)] {
        let view = chiaro_render::View::from_camera(&scene, 0, 128, 128);
        let prepared = renderer.prepare(&scene).unwrap();
        let options = chiaro_render::FrameOptions { readback: true, ..Default::default() };
        let frame = renderer.render(&scene, &prepared, &view, &settings, options).unwrap();
        // Sphere and background alike: the furnace's radiance everywhere.
        let worst = frame.hdr.iter().map(|h| (h[0] / FURNACE - 1.0).abs()).fold(0.0, f32::max);
        println!("{name}: worst |radiance / L - 1| over the whole image {worst:.4}");
        assert!(worst < tolerance, "{name}: {worst}");
    }
}

#[test]
fn metals_reflect_what_the_split_sum_predicts() {
    let path = write_hdr("furnace-metal.hdr", 64, |_| Vec3::splat(FURNACE));
    let gold = Vec3::new(1.0, 0.78, 0.34);
    let mut renderer = renderer();
    for roughness in [0.85, 0.15] {
        let scene = spheres_scene(&[sphere(gold, 1.0, roughness)]);
        let frame = render_environment(&mut renderer, &scene, &environment_settings(path.clone(), RenderPath::Forward));
        let (mut worst, mut compared, mut without_compensation) = (0.0f32, 0, 0.0f32);
        for (_, n, v, radiance) in shaded_pixels(&scene, &frame) {
            let n_dot_v = n.dot(v);
            if n_dot_v < 0.2 {
                continue;
            }
            let terms = split_sum(n_dot_v, roughness, 2048);
            let w = ibl_weights(gold, 1.0, terms);
            let predicted = (w.specular + w.diffuse) * FURNACE;
            worst = worst.max((radiance / predicted - Vec3::ONE).abs().max_element());
            without_compensation = without_compensation.max((w.specular * FURNACE / predicted - Vec3::ONE).abs().x);
            compared += 1;
        }
        println!(
            "metal, roughness {roughness}: {compared} pixels, worst |rendered / predicted - 1| {worst:.4} \
             (single scattering alone would be off by up to {without_compensation:.3})"
        );
        assert!(compared > 5_000);
        assert!(worst < 0.02, "roughness {roughness}: {worst}");
    }
}

/// Radiance 1 in the red channel towards +X, green towards +Y, blue towards +Z; 0 else.
fn octant_radiance(d: Vec3) -> Vec3 {
    Vec3::new((d.x > 0.0) as u8 as f32, (d.y > 0.0) as u8 as f32, (d.z > 0.0) as u8 as f32)
}

#[test]
fn a_mirror_reflects_the_side_of_the_environment_the_image_puts_there() {
    let path = write_hdr("octants.hdr", 512, octant_radiance);
    let scene = spheres_scene(&[sphere(Vec3::ONE, 1.0, 0.0)]);
    let mut renderer = renderer();
    for rotation_deg in [0.0, 90.0] {
        let mut settings = environment_settings(path.clone(), RenderPath::Forward);
        settings.environment.rotation_deg = rotation_deg;
        let frame = render_environment(&mut renderer, &scene, &settings);
        let (mut agree, mut judged) = (0, 0);
        for (_, n, v, radiance) in shaded_pixels(&scene, &frame) {
            let r = environment_direction(2.0 * n.dot(v) * n - v, rotation_deg);
            for c in 0..3 {
                // Away from the image's edges between bright and dark.
                if r[c].abs() > 0.25 {
                    judged += 1;
                    agree += usize::from((radiance[c] > 0.5) == (r[c] > 0.0));
                }
            }
        }
        let share = agree as f32 / judged as f32;
        println!("mirror, rotation {rotation_deg}: {agree} of {judged} channel samples on the predicted side");
        assert!(judged > 10_000 && share > 0.98, "rotation {rotation_deg}: {share}");
    }
}

#[test]
fn a_rough_sphere_is_lit_from_the_bright_side() {
    let path = write_hdr("bright-x.hdr", 128, |d| if d.x > 0.0 { Vec3::ONE } else { Vec3::ZERO });
    let scene = spheres_scene(&[sphere(Vec3::ONE, 0.0, 1.0)]);
    let mut renderer = renderer();
    for (rotation_deg, bright) in [(0.0, Vec3::X), (180.0, Vec3::NEG_X)] {
        let mut settings = environment_settings(path.clone(), RenderPath::Forward);
        settings.environment.rotation_deg = rotation_deg;
        let frame = render_environment(&mut renderer, &scene, &settings);
        // A white surface facing n sees the bright half over (1 + n.bright) / 2 of its
        // cosine lobe, so it sends back that much radiance; mean over each side's cap.
        let mean = |facing: Vec3| {
            let cap: Vec<(f32, f32)> = shaded_pixels(&scene, &frame)
                .into_iter()
                .filter(|(_, n, ..)| n.dot(facing) > 0.7)
                .map(|(_, n, _, r)| (r.x, (1.0 + n.dot(bright)) / 2.0))
                .collect();
            let count = cap.len() as f32;
            (cap.iter().map(|c| c.0).sum::<f32>() / count, cap.iter().map(|c| c.1).sum::<f32>() / count)
        };
        let (towards, away) = (mean(bright), mean(-bright));
        println!(
            "rough sphere, rotation {rotation_deg}: facing the bright side {:.3} (exact {:.3}), away {:.3} (exact {:.3})",
            towards.0, towards.1, away.0, away.1
        );
        // Nine harmonics smooth the step between the halves by a few hundredths.
        assert!((towards.0 - towards.1).abs() < 0.02 && (away.0 - away.1).abs() < 0.02, "{towards:?} {away:?}");
    }
}

#[test]
fn forward_and_deferred_agree_under_an_environment() {
    let path = write_hdr("octants-fd.hdr", 256, |d| octant_radiance(d) * 2.0 + Vec3::splat(0.2));
    let scene = spheres_scene(&[
        sphere(Vec3::new(0.8, 0.2, 0.2), 0.0, 0.9),
        sphere(Vec3::new(0.9, 0.9, 0.9), 1.0, 0.3),
        sphere(Vec3::new(0.2, 0.5, 0.9), 0.0, 0.15),
    ]);
    let mut renderer = renderer();
    let frames: Vec<FrameOutput> = [RenderPath::Forward, RenderPath::Deferred]
        .into_iter()
        .map(|kind| {
            let mut settings = environment_settings(path.clone(), kind);
            settings.render.deferred_antialiasing = chiaro_scene::DeferredAntialiasing::None;
            render_environment(&mut renderer, &scene, &settings)
        })
        .collect();
    let within = frames[0]
        .hdr
        .iter()
        .zip(&frames[1].hdr)
        .filter(|(f, d)| (0..3).all(|c| (f[c] - d[c]).abs() <= 0.02 * f[c].max(d[c]) + 1e-3))
        .count();
    let share = within as f32 / frames[0].hdr.len() as f32;
    println!("forward against deferred: {:.3}% of pixels within 2%", share * 100.0);
    assert!(share >= 0.995, "{share}");
}

/// The environment of a glTF file with EXT_lights_image_based whose faces are all
/// `FURNACE` (stored as RGBD PNGs) times `intensity`, read by the importer.
fn file_environment(intensity: f32) -> chiaro_scene::environment::SceneEnvironment {
    let doc = chiaro_testkit::image_based_light_gltf(
        16,
        |_, _| Vec3::splat(FURNACE),
        serde_json::json!({ "intensity": intensity }),
    );
    let path = scratch_dir().join(format!("image-based-{intensity}.gltf"));
    std::fs::write(&path, doc.to_string()).unwrap();
    chiaro_scene::load_gltf(&path).unwrap().environment.expect("the file's environment")
}

#[test]
fn a_files_image_based_light_lights_it_unless_the_settings_name_another() {
    let mut renderer = renderer();
    let mut scene = spheres_scene(&[sphere(Vec3::ONE, 0.0, 0.5)]);
    let settings = unlit_settings();
    // Twice as bright second: the renderer makes its maps again when the file's changes.
    for intensity in [1.0, 2.0] {
        let own = file_environment(intensity);
        // 0.5 through 8-bit RGBD comes back within 0.1%.
        let stored = own.map.texels[0];
        assert!((stored / (FURNACE * intensity) - Vec3::ONE).abs().max_element() < 1e-3, "{stored}");
        scene.environment = Some(own);
        let frame = render_environment(&mut renderer, &scene, &settings);
        let worst = frame.hdr.iter().map(|h| (Vec3::new(h[0], h[1], h[2]) / stored - Vec3::ONE).abs().max_element());
        let worst = worst.fold(0.0, f32::max);
        println!("EXT_lights_image_based furnace, intensity {intensity}: worst |radiance / L - 1| {worst:.4}");
        assert!(worst < 0.01, "intensity {intensity}: {worst}");
    }
    // `ambient` keeps the constant term (zero here): the sphere is black, the background
    // is render.background.
    let mut ambient = settings.clone();
    ambient.environment.source = EnvironmentSource::Ambient;
    let frame = render_environment(&mut renderer, &scene, &ambient);
    let brightest = surface_pixels(&frame).iter().map(|(.., r)| r.max_element()).fold(0.0, f32::max);
    assert!(brightest < 1e-4, "{brightest}");
}

#[test]
fn a_sunlit_floors_shadows_read_under_the_studio() {
    // A box on a floor under a sun 45 degrees up, at a few lux and at daylight's
    // 100,000 lux (exposed for it): under the studio, which scales with the sun, the box's
    // shadow keeps about a fifth of the lit floor's light, whatever the sun's strength.
    for (lux, ev100) in [(3.0, 0.0), (100_000.0, 15.0)] {
        let mut sun = chiaro_scene::Light::new(
            chiaro_scene::LightKind::Directional,
            Vec3::ZERO,
            Vec3::new(0.0, -1.0, -1.0).normalize(),
        );
        sun.intensity = lux;
        sun.node = 5;
        // Steep enough to see the floor behind the box.
        let mut scene = floor_scene(8.0, Vec3::new(0.0, 9.0, 3.0), vec![sun]);
        add_box(&mut scene, Vec3::new(0.0, 0.5, 0.0), Vec3::ONE, 0.0, chiaro_scene::CastShadows::On);
        let mut settings = Settings::default();
        settings.environment.source = EnvironmentSource::Neutral;
        settings.render.exposure_ev100 = ev100;
        settings.render.msaa = 1;
        let mut renderer = renderer();
        let frame = render(&mut renderer, &scene, &settings, 128);
        let aovs = frame.aovs.as_ref().unwrap();
        let floor = |i: usize| aovs.position_ws[i][1].abs() < 0.02 && aovs.normal_ws[i][1] > 0.99;
        let luminance = |i: usize| chiaro_math::tonemap::luminance(Vec3::from_slice(&frame.hdr[i][..3]));
        // The shadow falls towards -z behind the box (the sun shines along -z), to 1.5 m
        // back: floor 0.9 to 1.4 m back is in it, floor as far in front of the box is lit.
        let mean = |pick: &dyn Fn(Vec3) -> bool| {
            let values: Vec<f32> = (0..frame.hdr.len())
                .filter(|&i| floor(i) && pick(Vec3::from(aovs.position_ws[i])))
                .map(luminance)
                .collect();
            assert!(values.len() > 20, "{} pixels", values.len());
            values.iter().sum::<f32>() / values.len() as f32
        };
        let shadowed = mean(&|p| p.x.abs() < 0.4 && (-1.4..-0.9).contains(&p.z));
        let lit = mean(&|p| p.x.abs() < 0.4 && (0.9..1.4).contains(&p.z));
        println!("sun {lux} lux under the studio: shadowed floor {shadowed}, lit floor {lit}, {:.3}", shadowed / lit);
        assert!((0.08..0.3).contains(&(shadowed / lit)), "shadowed {shadowed} against lit {lit}");
    }
}
