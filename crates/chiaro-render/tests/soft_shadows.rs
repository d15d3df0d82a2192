//! Contact-hardening (PCSS) shadows: a plank 1 m above a floor under a point light of
//! radius 0.2 m at 3 m casts a penumbra as wide as similar triangles say (2 x 0.2 x 1 / 2
//! = 0.2 m), with the visibility profile of a disc light across a straight edge; so does
//! a sun of 5 degrees (2 tan 2.5 x 1 = 0.087 m); and the forward and deferred paths shade
//! the same penumbra.

mod common;

use chiaro_math::shadow::pcss::{disc_edge_visibility, penumbra_width};
use chiaro_render::{FrameOptions, FrameOutput, Renderer, View};
use chiaro_scene::{RenderPath, Scene, Settings, ShadowMode};
use common::*;

const SIZE: u32 = 256;
const LIGHT_RADIUS: f32 = 0.2;
const SUN_DIAMETER_DEG: f32 = 5.0;

/// The plank under a point or spot light of radius LIGHT_RADIUS (or a sun of
/// SUN_DIAMETER_DEG) with `mode` shadows, the camera straight above the shadow's edge:
/// close enough that the penumbra spans tens of pixels (the sun's is 9 cm).
fn plank(mode: ShadowMode, kind: PlankLight) -> Scene {
    let sun = kind == PlankLight::Sun;
    let size = if sun { SUN_DIAMETER_DEG } else { LIGHT_RADIUS };
    let mut scene = plank_scene(kind, size, if sun { 0.6 } else { 2.0 }, shadow_edge_x(sun));
    scene.lights[0].shadow.mode = mode;
    scene
}

/// Where the plank's edge casts the middle of the penumbra on the floor.
fn shadow_edge_x(sun: bool) -> f32 {
    if sun { PLANK_EDGE_X } else { PLANK_EDGE_X * PLANK_LIGHT_HEIGHT / (PLANK_LIGHT_HEIGHT - PLANK_HEIGHT) }
}

fn render_shadow(renderer: &mut Renderer, scene: &Scene, settings: &Settings) -> FrameOutput {
    let view = View::from_camera(scene, 0, SIZE, SIZE);
    let prepared = renderer.prepare(scene).expect("prepare");
    let options = FrameOptions { aovs: true, shadow_aovs: true, readback: true, ..Default::default() };
    renderer.render(scene, &prepared, &view, settings, options).expect("render")
}

/// Mean visibility of floor pixels near z = 0 in bins of `bin` metres along x, from
/// `x0` to `x1`: (bin centre, mean visibility).
fn profile(frame: &FrameOutput, x0: f32, x1: f32, bin: f32) -> Vec<(f32, f32)> {
    profile_between(frame, (-0.3, 0.3), x0, x1, bin)
}

/// `profile` over the floor pixels with z in `z`.
fn profile_between(frame: &FrameOutput, z: (f32, f32), x0: f32, x1: f32, bin: f32) -> Vec<(f32, f32)> {
    let aovs = frame.aovs.as_ref().expect("aovs");
    let bins = ((x1 - x0) / bin).round() as usize;
    let mut sums = vec![(0.0f32, 0u32); bins];
    for (i, p) in aovs.position_ws.iter().enumerate() {
        let visibility = frame.shadow_aovs[0][i];
        let on_strip = p[1].abs() < 1e-3 && p[2] >= z.0 && p[2] < z.1;
        if !(on_strip && visibility.is_finite() && p[0] >= x0 && p[0] < x1) {
            continue;
        }
        let k = (((p[0] - x0) / bin) as usize).min(bins - 1);
        sums[k].0 += visibility;
        sums[k].1 += 1;
    }
    sums.iter()
        .enumerate()
        .filter(|(_, s)| s.1 > 0)
        .map(|(k, s)| (x0 + (k as f32 + 0.5) * bin, s.0 / s.1 as f32))
        .collect()
}

/// Where a falling profile first drops below `level`, interpolated between bins.
fn crossing(profile: &[(f32, f32)], level: f32) -> f32 {
    let k = profile.iter().position(|&(_, v)| v < level).expect("the profile falls below the level");
    let ((xa, va), (xb, vb)) = (profile[k - 1], profile[k]);
    xa + (va - level) / (va - vb) * (xb - xa)
}

/// x of the disc light's profile at `level`, in half-widths from the penumbra's middle.
fn disc_offset(level: f32) -> f32 {
    // disc_edge_visibility rises with its argument; visibility falls with x here.
    let (mut lo, mut hi) = (-1.0f32, 1.0f32);
    for _ in 0..40 {
        let mid = 0.5 * (lo + hi);
        if disc_edge_visibility(mid) < level { lo = mid } else { hi = mid }
    }
    -0.5 * (lo + hi)
}

/// Renders the plank with `mode` and checks the penumbra's 10-90% width against the disc
/// light's and the whole profile against it; returns the measured width.
fn check_penumbra(kind: PlankLight, mode: ShadowMode) -> f32 {
    let sun = kind == PlankLight::Sun;
    let mut renderer = renderer();
    let mut settings = unlit_settings();
    settings.render.msaa = 1;
    let frame = render_shadow(&mut renderer, &plank(mode, kind), &settings);
    let width = if sun {
        penumbra_width(false, (SUN_DIAMETER_DEG.to_radians() * 0.5).tan(), 1.0, 0.0)
    } else {
        penumbra_width(true, LIGHT_RADIUS, PLANK_LIGHT_HEIGHT, PLANK_LIGHT_HEIGHT - PLANK_HEIGHT)
    };
    let middle = shadow_edge_x(sun);
    let measured = profile(&frame, middle - 1.5 * width, middle + 1.5 * width, width / 20.0);
    let (x90, x10) = (crossing(&measured, 0.9), crossing(&measured, 0.1));
    let predicted = 0.5 * width * (disc_offset(0.1) - disc_offset(0.9));
    let error = ((x10 - x90) - predicted).abs() / predicted;
    let disc = |x: f32| disc_edge_visibility(-(x - middle) / (0.5 * width));
    let errors: Vec<f32> = measured.iter().map(|&(x, v)| (v - disc(x)).abs()).collect();
    let mean = errors.iter().sum::<f32>() / errors.len() as f32;
    let worst = errors.iter().copied().fold(0.0f32, f32::max);
    eprintln!(
        "{kind:?}, {mode:?}: 10-90% width {:.4} m against {predicted:.4} m ({:.1}%); profile against the disc \
         light's: mean {mean:.4}, worst {worst:.4}",
        x10 - x90,
        100.0 * error
    );
    if mode == ShadowMode::Pcss {
        assert!(error < 0.15, "penumbra 10-90% width {:.4} m against {predicted:.4} m", x10 - x90);
        assert!(mean < 0.03 && worst < 0.1, "profile off the disc light's: mean {mean}, worst {worst}");
    }
    x10 - x90
}

#[test]
fn a_plank_under_a_sphere_light_casts_the_penumbra_similar_triangles_predict() {
    let pcss = check_penumbra(PlankLight::Point, ShadowMode::Pcss);
    // The same light with its filtered hard shadow: a penumbra of a few texels.
    assert!(check_penumbra(PlankLight::Point, ShadowMode::Hard) < 0.25 * pcss);
    check_penumbra(PlankLight::Spot, ShadowMode::Pcss);
}

#[test]
fn a_plank_under_a_wide_sun_casts_the_penumbra_similar_triangles_predict() {
    let pcss = check_penumbra(PlankLight::Sun, ShadowMode::Pcss);
    assert!(check_penumbra(PlankLight::Sun, ShadowMode::Hard) < 0.5 * pcss);
}

/// Forward and deferred shade the same soft shadows: the shadow functions are shared,
/// and the sample discs turn with the pixel, so the penumbra's pixels agree closely.
#[test]
fn forward_and_deferred_shade_the_same_penumbra() {
    let mut renderer = renderer();
    for kind in [PlankLight::Point, PlankLight::Sun] {
        let scene = plank(ShadowMode::Pcss, kind);
        let mut settings = unlit_settings();
        settings.render.msaa = 1;
        let forward = render_shadow(&mut renderer, &scene, &settings);
        settings.render.path = RenderPath::Deferred;
        let deferred = render_shadow(&mut renderer, &scene, &settings);
        assert!(deferred.graph.passes.contains(&"deferred lights"), "{:?}", deferred.graph.passes);
        let luminance = |p: &[f32; 4]| 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
        let brightest = forward.hdr.iter().map(luminance).fold(0.0f32, f32::max);
        // Pixels of the penumbra: neither fully lit nor dark.
        let penumbra: Vec<usize> =
            (0..forward.hdr.len()).filter(|&i| (0.1..0.9).contains(&forward.shadow_aovs[0][i])).collect();
        assert!(penumbra.len() > 500, "{kind:?}: {} penumbra pixels", penumbra.len());
        let close = penumbra
            .iter()
            .filter(|&&i| (luminance(&forward.hdr[i]) - luminance(&deferred.hdr[i])).abs() <= 0.02 * brightest)
            .count();
        let share = close as f32 / penumbra.len() as f32;
        eprintln!("{kind:?}: {:.2}% of {} penumbra pixels within 2% of the brightest", 100.0 * share, penumbra.len());
        assert!(share > 0.995, "{kind:?}: forward and deferred differ in the penumbra ({share})");
    }
}

/// A sun's penumbra is as wide in every cascade: widths are worked out in metres, not
/// texels. Seen from one end of the plank, the shadow's edge runs through three cascades
/// (max distance 6 m: cascades end at 0.6, 1.5, 3 and 6 m).
#[test]
fn a_suns_penumbra_keeps_its_width_across_cascades() {
    let mut scene = plank_scene(PlankLight::Sun, 10.0, 1.0, PLANK_EDGE_X);
    // Low over the floor (the plank is seen by the light alone), looking along the edge.
    let eye = glam::Vec3::new(PLANK_EDGE_X, 0.6, 1.8);
    scene.cameras[0].world_from_view =
        glam::Mat4::look_at_rh(eye, glam::Vec3::new(PLANK_EDGE_X, 0.0, -1.5), glam::Vec3::Y).inverse();
    let mut settings = unlit_settings();
    settings.render.msaa = 1;
    settings.shadows.max_distance = 6.0;
    let mut renderer = renderer();
    let view = View::from_camera(&scene, 0, 384, 384);
    let prepared = renderer.prepare(&scene).expect("prepare");
    let options = FrameOptions { aovs: true, shadow_aovs: true, readback: true, ..Default::default() };
    let frame = renderer.render(&scene, &prepared, &view, &settings, options).expect("render");
    let width = penumbra_width(false, 5f32.to_radians().tan(), 1.0, 0.0);
    let predicted = 0.5 * width * (disc_offset(0.1) - disc_offset(0.9));
    // The cascade a point of the edge falls in: the first culling sphere that holds it.
    let spheres = &frame.plan.shadows.cascade_spheres;
    let cascade_of = |z: f32| {
        let p = glam::Vec3::new(PLANK_EDGE_X, 0.0, z);
        spheres.iter().position(|s| s.center.distance(p) < s.radius).expect("inside the cascades")
    };
    let mut cascades = Vec::new();
    for z in [(1.05, 1.45), (-0.6, 0.5), (-1.42, -1.27)] {
        let cascade = (cascade_of(z.0), cascade_of(z.1));
        assert_eq!(cascade.0, cascade.1, "z {z:?} lies in one cascade");
        cascades.push(cascade.0);
        let measured = profile_between(&frame, z, PLANK_EDGE_X - width, PLANK_EDGE_X + width, width / 12.0);
        let measured_width = crossing(&measured, 0.1) - crossing(&measured, 0.9);
        let error = (measured_width - predicted).abs() / predicted;
        eprintln!(
            "z {z:?} (cascade {}): 10-90% width {measured_width:.4} m against {predicted:.4} m ({:.1}%)",
            cascade.0,
            100.0 * error
        );
        assert!(error < 0.15, "z {z:?}: {measured_width} m against {predicted} m");
    }
    assert!(cascades[0] < cascades[1] && cascades[1] < cascades[2], "three cascades: {cascades:?}");
}
