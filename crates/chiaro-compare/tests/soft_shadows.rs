//! Contact-hardening (PCSS) shadows against the traced reference, which sees the share of
//! each light's disc (64 stratified rays a pixel): a plank 1 m above a floor under a
//! 0.2 m point and spot light 3 m up and under a 5 degree sun. Per light, the mean and
//! 95th percentile of |rendered - traced| visibility and the share off by more than 0.1,
//! with the default sample counts (16 blocker, 16 filter) and with twice them; and the
//! traced penumbra itself against the disc light's analytic profile.

mod common;

use chiaro_compare::{VisibilityError, compare_rendered, render_shadows};
use chiaro_math::shadow::pcss::{disc_edge_visibility, penumbra_width};
use chiaro_render::View;
use chiaro_scene::{Settings, ShadowMode, ShadowTechnique};
use chiaro_testkit::{PLANK_EDGE_X, PLANK_HEIGHT, PLANK_LIGHT_HEIGHT, PlankLight, plank_scene, pole_and_plank_scene};
use common::*;

const SIZE: u32 = 192;

fn scene(kind: PlankLight) -> (chiaro_scene::Scene, f32) {
    let sun = kind == PlankLight::Sun;
    let edge = if sun { PLANK_EDGE_X } else { PLANK_EDGE_X * PLANK_LIGHT_HEIGHT / (PLANK_LIGHT_HEIGHT - PLANK_HEIGHT) };
    let size = if sun { 5.0 } else { 0.2 };
    (plank_scene(kind, size, if sun { 0.6 } else { 2.0 }, edge), edge)
}

/// The visibility error of the plank's shadow rendered with `mode` against the traced
/// area light, and the traced penumbra's mean distance from the disc light's profile.
fn measure(kind: PlankLight, mode: ShadowMode, samples: u32) -> (VisibilityError, f32) {
    measure_with(kind, mode, samples, ShadowTechnique::Atlas)
}

/// As `measure`, with the shadow maps of `technique`.
fn measure_with(
    kind: PlankLight,
    mode: ShadowMode,
    samples: u32,
    technique: ShadowTechnique,
) -> (VisibilityError, f32) {
    let (scene, edge) = scene(kind);
    let mut settings = Settings::default();
    settings.shadows.technique = technique;
    settings.shadows.pcss_blocker_samples = samples;
    settings.shadows.pcss_filter_samples = samples;
    let mut renderer = renderer();
    let mut rendered_scene = scene.clone();
    rendered_scene.lights[0].shadow.mode = mode;
    let prepared = renderer.prepare(&rendered_scene).expect("prepare");
    let view = View::from_camera(&scene, 0, SIZE, SIZE);
    let rendered = render_shadows(&mut renderer, &rendered_scene, &prepared, &view, &settings).expect("render");
    // Judged as the pcss light it is, whatever it was rendered with.
    let result = compare_rendered(&scene, &view, &settings, rendered);
    let error = result.reports[0].visibility.expect("a pcss light has a visibility error");
    // The traced penumbra against the disc light's profile, pixel by pixel near z = 0.
    let sun = kind == PlankLight::Sun;
    let width = match sun {
        true => penumbra_width(false, (2.5f32).to_radians().tan(), 1.0, 0.0),
        false => penumbra_width(true, 0.2, PLANK_LIGHT_HEIGHT, PLANK_LIGHT_HEIGHT - PLANK_HEIGHT),
    };
    let reference = &result.reference;
    let traced: Vec<f32> = (0..reference.pixel_count())
        .filter_map(|i| {
            let p = reference.position[i]?;
            (p.z.abs() < 0.3 && (p.x - edge).abs() < width)
                .then(|| (reference.visibility[0][i] - disc_edge_visibility(-(p.x - edge) / (0.5 * width))).abs())
        })
        .collect();
    let traced_mean = traced.iter().sum::<f32>() / traced.len() as f32;
    (error, traced_mean)
}

#[test]
fn pcss_agrees_with_the_traced_area_light() {
    for kind in [PlankLight::Point, PlankLight::Spot, PlankLight::Sun] {
        for samples in [16, 32] {
            let (e, traced) = measure(kind, ShadowMode::Pcss, samples);
            eprintln!(
                "{kind:?}, {samples} samples: {} pixels, mean |dv| {:.4}, p95 {:.4}, > 0.1 on {:.3}%; traced against \
                 the disc's profile: mean {traced:.4}",
                e.compared,
                e.mean_abs,
                e.p95_abs,
                100.0 * e.far_off
            );
            assert!(e.compared > 10_000, "{kind:?}: {} pixels compared", e.compared);
            assert!(traced < 0.02, "{kind:?}: the traced penumbra is off the disc light's by {traced}");
            assert!(e.mean_abs < 0.012 && e.p95_abs < 0.1 && e.far_off < 0.04, "{kind:?}, {samples}: {e:?}");
        }
        // The same light's hard shadow is what PCSS improves on.
        let (pcss, _) = measure(kind, ShadowMode::Pcss, 16);
        let (hard, _) = measure(kind, ShadowMode::Hard, 16);
        eprintln!(
            "{kind:?}, hard: mean |dv| {:.4}, p95 {:.4}, > 0.1 on {:.3}%",
            hard.mean_abs,
            hard.p95_abs,
            100.0 * hard.far_off
        );
        assert!(hard.mean_abs > 2.0 * pcss.mean_abs && hard.far_off > 2.0 * pcss.far_off, "{kind:?}: {hard:?}");
    }
}

/// Virtual shadow maps keep PCSS penumbrae: a contact-hardening light's pages come from a
/// mip coarse enough that its blocker search stays within a page's border.
#[test]
fn virtual_maps_keep_the_traced_penumbra() {
    for kind in [PlankLight::Point, PlankLight::Spot, PlankLight::Sun] {
        let (atlas, _) = measure(kind, ShadowMode::Pcss, 16);
        let (virt, _) = measure_with(kind, ShadowMode::Pcss, 16, ShadowTechnique::Virtual);
        eprintln!(
            "{kind:?}: atlas mean |dv| {:.4}, p95 {:.4}, > 0.1 on {:.3}%; virtual {:.4}, {:.4}, {:.3}%",
            atlas.mean_abs,
            atlas.p95_abs,
            100.0 * atlas.far_off,
            virt.mean_abs,
            virt.p95_abs,
            100.0 * virt.far_off
        );
        assert!(virt.compared > 10_000, "{kind:?}: {} pixels compared", virt.compared);
        assert!(virt.mean_abs < 0.012 && virt.p95_abs < 0.1 && virt.far_off < 0.04, "{kind:?}: {virt:?}");
    }
}

/// A thin caster's soft shadow: a pole 8 cm thick (a few texels in its light's tile) under
/// a 0.25 m light, whose shadow on the floor is penumbra almost everywhere, against the
/// traced disc.
#[test]
fn a_thin_pole_casts_the_traced_soft_shadow() {
    let scene = pole_and_plank_scene(ShadowMode::Pcss, 4.0 / 3.0);
    let mut renderer = renderer();
    let prepared = renderer.prepare(&scene).expect("prepare");
    let view = View::from_camera(&scene, 0, 360, 270);
    let settings = Settings::default();
    let rendered = render_shadows(&mut renderer, &scene, &prepared, &view, &settings).expect("render");
    let result = compare_rendered(&scene, &view, &settings, rendered);
    let traced = &result.reference.visibility[0];
    let floor = |i: usize| result.reference.position[i].is_some_and(|p| p.y.abs() < 1e-3);
    // The pole's shadow on the floor: where the traced disc is partly hidden, left of the
    // plank.
    let pole: Vec<usize> = (0..traced.len())
        .filter(|&i| floor(i) && traced[i] < 0.9 && result.reference.position[i].is_some_and(|p| p.x < 0.3))
        .collect();
    let error = pole.iter().map(|&i| (result.rendered[0][i] - traced[i]).abs()).sum::<f32>() / pole.len() as f32;
    let rendered = pole.iter().map(|&i| result.rendered[0][i]).sum::<f32>() / pole.len() as f32;
    let expected = pole.iter().map(|&i| traced[i]).sum::<f32>() / pole.len() as f32;
    eprintln!(
        "{} pixels of the pole's shadow: rendered {rendered:.3}, traced {expected:.3}, mean |dv| {error:.3}",
        pole.len()
    );
    assert!(pole.len() > 200, "{} pixels", pole.len());
    assert!(
        error < 0.1 && (rendered - expected).abs() < 0.05,
        "the pole's shadow: mean |dv| {error}, rendered {rendered}"
    );
}
