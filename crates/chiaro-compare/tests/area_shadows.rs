//! Area lights' shadows against the traced reference (64 rays multi-jittered over the
//! light's real shape a pixel): a plank 1 m above a floor under a 1 x 0.1 m strip light 3 m up,
//! across the plank's edge and along it, and under a 0.5 m disk. Judged where it matters,
//! in the reference's penumbra: the mean |rendered - traced| visibility and the share of
//! pixels off by more than 0.1, for `pcss` (the light's points seen through the centre's
//! cube at the blockers' depth) and for `soft` (a filter around the centre's hard shadow).

mod common;

use chiaro_compare::{VisibilityError, compare_rendered, render_shadows};
use chiaro_render::View;
use chiaro_scene::{CastShadows, Light, LightKind, Material, Scene, Settings, ShadowMode, shapes};
use chiaro_testkit::{
    PLANK_EDGE_X, PLANK_HEIGHT, PLANK_LIGHT_HEIGHT, PlankLight, add_mesh, floor_scene, look_from, plank_scene,
};
use common::*;
use glam::Vec3;

const SIZE: u32 = 192;

/// The plank scene under `kind` (rolled so that its local X runs along `along`) with
/// `mode` shadows: its visibility error against the traced shape.
fn measure(kind: LightKind, along: Vec3, mode: ShadowMode, atlas_size: u32) -> VisibilityError {
    measure_from(0.0, kind, along, mode, atlas_size)
}

/// `measure` with the light at `light_x` along the floor instead of over the origin.
fn measure_from(light_x: f32, kind: LightKind, along: Vec3, mode: ShadowMode, atlas_size: u32) -> VisibilityError {
    judge(&area_scene(light_x, kind, along, mode), atlas_size)
}

/// The plank scene under an area light of `kind` at `light_x`, its local X along `along`.
fn area_scene(light_x: f32, kind: LightKind, along: Vec3, mode: ShadowMode) -> Scene {
    // The shadow of the plank's edge falls about here on the floor.
    let edge = light_x + (PLANK_EDGE_X - light_x) * PLANK_LIGHT_HEIGHT / (PLANK_LIGHT_HEIGHT - PLANK_HEIGHT);
    let mut scene = plank_scene(PlankLight::Point, 0.2, 2.0, edge);
    let mut light = Light {
        name: "area".into(),
        node: 10,
        intensity: 2000.0,
        ..Light::new(kind, Vec3::new(light_x, PLANK_LIGHT_HEIGHT, 0.0), Vec3::NEG_Y)
    };
    // Local X along `along`, shining down.
    light.world_from_light = glam::Mat4::from_cols(
        along.extend(0.0),
        (-Vec3::NEG_Y.cross(along)).extend(0.0),
        Vec3::Y.extend(0.0),
        light.position().extend(1.0),
    );
    light.shadow.mode = mode;
    scene.lights = vec![light];
    scene
}

/// The visibility error of `scene`'s one light, rendered with a local atlas of `atlas_size`.
fn judge(scene: &Scene, atlas_size: u32) -> VisibilityError {
    let mut settings = Settings::default();
    settings.shadows.other.atlas_size = atlas_size;
    judge_with(scene, &settings)
}

/// The visibility error of `scene`'s one light, rendered with `settings`.
fn judge_with(scene: &Scene, settings: &Settings) -> VisibilityError {
    let mut renderer = renderer();
    let prepared = renderer.prepare(scene).expect("prepare");
    let view = View::from_camera(scene, 0, SIZE, SIZE);
    let settings = settings.clone();
    let rendered = render_shadows(&mut renderer, scene, &prepared, &view, &settings).expect("render");
    let result = compare_rendered(scene, &view, &settings, rendered);
    result.reports[0].visibility.expect("an area light is judged by its visibility")
}

const DEFAULT_ATLAS: u32 = 2048;

fn report(name: &str, mode: &str, e: &VisibilityError) {
    eprintln!(
        "{name}, {mode}: {} penumbra pixels of {}, penumbra mean |dv| {:.4}, > 0.1 on {:.2}%; all pixels mean |dv| {:.4}",
        e.penumbra_compared,
        e.compared,
        e.penumbra_mean_abs,
        100.0 * e.penumbra_far_off,
        e.mean_abs
    );
}

/// With virtual shadow maps, an area light's pages come from a mip coarse enough that its
/// blocker search and its rays stay within a page's border: the strip's penumbra keeps its
/// shape as with the atlas. The disk's comes out at 0.053 (atlas 0.021): the coarse mip
/// its rays need is too coarse for it (docs/shadows.md, not yet); it still beats the
/// filtered hard shadow by far.
#[test]
fn virtual_maps_keep_wide_area_light_penumbrae() {
    let mut settings = Settings::default();
    settings.shadows.technique = chiaro_scene::ShadowTechnique::Virtual;
    for (name, kind) in [
        ("strip across the edge", LightKind::Rect { width: 1.0, height: 0.1 }),
        ("disk", LightKind::Disk { diameter: 0.5 }),
    ] {
        let atlas = measure(kind, Vec3::X, ShadowMode::Pcss, DEFAULT_ATLAS);
        let virt = judge_with(&area_scene(0.0, kind, Vec3::X, ShadowMode::Pcss), &settings);
        let soft = judge_with(&area_scene(0.0, kind, Vec3::X, ShadowMode::Soft), &settings);
        report(name, "pcss, atlas", &atlas);
        report(name, "pcss, virtual", &virt);
        report(name, "soft, virtual", &soft);
        assert!(virt.penumbra_compared > 3000, "{name}: {} penumbra pixels", virt.penumbra_compared);
        assert!(soft.penumbra_mean_abs > 2.0 * virt.penumbra_mean_abs, "{name}: soft {soft:?}, pcss {virt:?}");
        if name.starts_with("strip") {
            assert!(virt.penumbra_mean_abs < 0.05 && virt.penumbra_far_off < 0.05, "{name}: {virt:?}");
        }
    }
}

#[test]
fn wide_area_light_penumbrae_follow_the_traced_shape() {
    // Penumbrae 0.5 m (across the strip's length) and 0.25 m wide on the floor.
    for (name, kind, along) in [
        ("strip across the edge", LightKind::Rect { width: 1.0, height: 0.1 }, Vec3::X),
        ("disk", LightKind::Disk { diameter: 0.5 }, Vec3::X),
    ] {
        let pcss = measure(kind, along, ShadowMode::Pcss, DEFAULT_ATLAS);
        let soft = measure(kind, along, ShadowMode::Soft, DEFAULT_ATLAS);
        report(name, "pcss", &pcss);
        report(name, "soft", &soft);
        assert!(pcss.penumbra_compared > 3000, "{name}: {} penumbra pixels", pcss.penumbra_compared);
        assert!(pcss.penumbra_mean_abs < 0.05 && pcss.penumbra_far_off < 0.05, "{name}: {pcss:?}");
        assert!(soft.penumbra_mean_abs > 2.0 * pcss.penumbra_mean_abs, "{name}: soft {soft:?}, pcss {pcss:?}");
    }
}

#[test]
fn a_penumbra_seen_through_a_side_face_of_the_cube_beats_the_filtered_one() {
    // The light 2.4 m to the side: the edge's shadow falls at x = 1.8, in the cube's +X
    // face, whose axis the strip's long side runs along, so the light's points lie at
    // depths of their own there.
    let strip = LightKind::Rect { width: 1.0, height: 0.1 };
    let pcss = measure_from(-2.4, strip, Vec3::X, ShadowMode::Pcss, DEFAULT_ATLAS);
    let soft = measure_from(-2.4, strip, Vec3::X, ShadowMode::Soft, DEFAULT_ATLAS);
    report("strip across the edge, side face", "pcss", &pcss);
    report("strip across the edge, side face", "soft", &soft);
    // The plank seen from the side spans a metre of depths: each ray is tested where it
    // crosses the nearest and the farthest blockers. Measured 0.045 (docs/lights.md; 0.047
    // before penumbrae took twice the rays); 0.060 with their mean depth alone, 0.070 with
    // rays from the normal-biased position, 0.248 for a filter around the centre's shadow.
    assert!(pcss.penumbra_compared > 3000, "{} penumbra pixels", pcss.penumbra_compared);
    assert!(pcss.penumbra_mean_abs < 0.05, "{pcss:?}");
    assert!(soft.penumbra_mean_abs > 3.0 * pcss.penumbra_mean_abs, "soft {soft:?}, pcss {pcss:?}");
}

#[test]
fn a_narrow_penumbra_is_as_sharp_as_the_shadow_maps_texels_allow() {
    // Along the edge the strip's 0.1 m side makes a 5 cm penumbra: a few texels of a cube
    // face there, so its error follows the texels' size. The light shines down, into the
    // cube's -Y face, which the default atlas (one cube: 6 of its 16 tiles) gives a tile
    // twice as wide as the other faces'. Measured 0.023 (0.059 before that face was
    // doubled and penumbrae took twice the rays); with the atlas half as wide, 0.057.
    let strip = LightKind::Rect { width: 1.0, height: 0.1 };
    let pcss = measure(strip, Vec3::Z, ShadowMode::Pcss, DEFAULT_ATLAS);
    let soft = measure(strip, Vec3::Z, ShadowMode::Soft, DEFAULT_ATLAS);
    let coarser = measure(strip, Vec3::Z, ShadowMode::Pcss, DEFAULT_ATLAS / 2);
    report("strip along the edge", "pcss", &pcss);
    report("strip along the edge", "soft", &soft);
    report("strip along the edge, atlas half as wide", "pcss", &coarser);
    assert!(pcss.penumbra_compared > 300, "{} penumbra pixels", pcss.penumbra_compared);
    assert!(pcss.penumbra_mean_abs < 0.05 && pcss.penumbra_far_off < 0.05, "{pcss:?}");
    assert!(soft.penumbra_mean_abs > 2.0 * pcss.penumbra_mean_abs, "soft {soft:?}, pcss {pcss:?}");
    assert!(pcss.penumbra_mean_abs < 0.7 * coarser.penumbra_mean_abs, "coarser {coarser:?}, default {pcss:?}");
}

#[test]
fn spheres_on_a_floor_cast_the_traced_penumbrae_under_a_tilted_rect() {
    // Three 0.5 m spheres resting on the floor under a 1 x 0.5 m rect 2 m up and 1.5 m to
    // the side, tilted towards them: blockers that span a radius of depths, whose outline
    // lies at their farthest visible depth, not their mean.
    let run = |mode: ShadowMode| {
        let at = Vec3::new(-1.5, 2.0, 0.0);
        let mut light = Light {
            name: "area".into(),
            node: 10,
            intensity: 2000.0,
            ..Light::new(LightKind::Rect { width: 1.0, height: 0.5 }, at, Vec3::new(1.5, -2.0, 0.0))
        };
        light.shadow.mode = mode;
        let mut scene = floor_scene(6.0, Vec3::new(0.0, 2.5, 3.0), vec![light]);
        for x in [-0.6, 0.6, 1.8] {
            let place = glam::Mat4::from_translation(Vec3::new(x, 0.5, 0.0));
            add_mesh(&mut scene, "sphere", shapes::sphere(0.5, 48, 24), Material::default(), place, CastShadows::On);
        }
        look_from(&mut scene, Vec3::new(0.6, 2.2, 2.8), Vec3::new(0.9, 0.2, 0.0));
        judge(&scene, DEFAULT_ATLAS)
    };
    let (pcss, soft) = (run(ShadowMode::Pcss), run(ShadowMode::Soft));
    report("spheres under a tilted rect", "pcss", &pcss);
    report("spheres under a tilted rect", "soft", &soft);
    // Measured 0.0445 (0.054 before penumbrae took twice the rays and the blocker search
    // twice the samples across a shadow's edge, 0.085 when every ray was tested at the
    // blockers' mean depth alone, 0.22 for `soft`; docs/lights.md).
    assert!(pcss.penumbra_compared > 1000, "{} penumbra pixels", pcss.penumbra_compared);
    assert!(pcss.penumbra_mean_abs < 0.05, "{pcss:?}");
    assert!(soft.penumbra_mean_abs > 2.0 * pcss.penumbra_mean_abs, "soft {soft:?}, pcss {pcss:?}");
}
