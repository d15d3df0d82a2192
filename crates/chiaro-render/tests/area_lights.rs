//! Rect and disk lights (EXT_lights_area) without shadows, on the GPU, against the light
//! integrated on the CPU: the BRDF of `chiaro_math::brdf` summed over a fine grid of
//! points on the light (not the shader's LTC twin), in the forward and deferred paths.

mod common;

use chiaro_math::brdf::brdf_cos;
use chiaro_scene::{Light, LightKind, RenderPath, ShadowMode};
use common::*;
use glam::{Vec2, Vec3, Vec4};

const EYE: Vec3 = Vec3::new(0.0, 4.0, 2.5);

/// An area light of `nits` at `position` shining along `direction`, without shadows.
fn area_light(kind: LightKind, position: Vec3, direction: Vec3, nits: f32) -> Light {
    let mut light = Light { name: "area".into(), node: 10, intensity: nits, ..Light::new(kind, position, direction) };
    light.shadow.mode = ShadowMode::None;
    light
}

/// Radiance towards the eye from `p` on the floor (normal +Y) lit by `light`: the BRDF
/// integrated over `side` x `side` points of the light's area.
fn integrated(light: &Light, p: Vec3, base: Vec3, metallic: f32, roughness: f32, side: u32) -> Vec3 {
    let shape = light.kind.area_shape().unwrap();
    let v = (EYE - p).normalize();
    let (axis_x, axis_y) = (light.world_from_light.x_axis.truncate(), light.world_from_light.y_axis.truncate());
    let cell_area = shape.area() / (side * side) as f32;
    let mut sum = Vec3::ZERO;
    for j in 0..side {
        for i in 0..side {
            let u = (Vec2::new(i as f32, j as f32) + 0.5) / side as f32;
            let local = shape.point(u);
            let q = light.position() + axis_x * local.x + axis_y * local.y;
            let to_light = q - p;
            let d2 = to_light.length_squared();
            let l = to_light / d2.sqrt();
            let emitted = light.direction().dot(-l).max(0.0);
            sum += brdf_cos(base, metallic, roughness, Vec3::Y, v, l) * (emitted * cell_area / d2);
        }
    }
    sum * light.intensity * light.color
}

/// Rendered over predicted radiance (red channel) at every 3rd lit floor pixel: the
/// median ratio and the shares within 5% and 15%.
fn judge(frame: &chiaro_render::FrameOutput, predict: impl Fn(Vec3) -> f32) -> (f32, f32, f32) {
    let mut ratios: Vec<f32> = surface_pixels(frame)
        .iter()
        .step_by(3)
        .filter_map(|&(_, p, _, radiance)| {
            let expected = predict(p);
            (expected > 1e-3).then(|| radiance.x / expected)
        })
        .collect();
    assert!(ratios.len() > 2000, "{} lit pixels", ratios.len());
    ratios.sort_by(f32::total_cmp);
    let within = |t: f32| ratios.iter().filter(|r| (*r - 1.0).abs() <= t).count() as f32 / ratios.len() as f32;
    (ratios[ratios.len() / 2], within(0.05), within(0.15))
}

fn floor_with(light: Light, roughness: f32, metallic: f32) -> chiaro_scene::Scene {
    let mut scene = floor_scene(10.0, EYE, vec![light]);
    scene.materials[0].roughness = roughness;
    scene.materials[0].metallic = metallic;
    scene.materials[0].base_color = Vec4::new(0.8, 0.8, 0.8, 1.0);
    scene
}

#[test]
fn a_rough_floor_under_a_tilted_rect_and_a_disk_gets_the_integrated_light() {
    let tilt = Vec3::new(0.5, -1.0, 0.2).normalize();
    // Last, a rect standing half below the floor, facing along it: the floor sees it
    // across its horizon.
    for (kind, position, direction) in [
        (LightKind::Rect { width: 1.2, height: 0.4 }, Vec3::new(0.3, 1.2, 0.0), tilt),
        (LightKind::Disk { diameter: 0.8 }, Vec3::new(0.3, 1.2, 0.0), tilt),
        (LightKind::Rect { width: 1.0, height: 1.0 }, Vec3::new(-1.5, 0.0, 0.0), Vec3::new(1.0, -0.2, 0.0).normalize()),
    ] {
        let light = area_light(kind, position, direction, 40.0);
        let scene = floor_with(light.clone(), 1.0, 0.0);
        let mut renderer = renderer();
        let forward = render(&mut renderer, &scene, &unlit_settings(), 160);
        let (median, within5, within15) = judge(&forward, |p| integrated(&light, p, Vec3::splat(0.8), 0.0, 1.0, 48).x);
        assert!((median - 1.0).abs() < 0.02, "{kind:?}: median ratio {median}");
        assert!(within5 > 0.95 && within15 > 0.99, "{kind:?}: {within5} within 5%, {within15} within 15%");

        let mut deferred_settings = unlit_settings();
        deferred_settings.render.path = RenderPath::Deferred;
        let deferred = render(&mut renderer, &scene, &deferred_settings, 160);
        for (f, d) in forward.hdr.iter().zip(&deferred.hdr) {
            assert!((f[0] - d[0]).abs() <= 1e-3 * f[0].max(1.0), "{kind:?}: forward {f:?} deferred {d:?}");
        }
    }
}

#[test]
fn a_tiny_rect_is_a_point_light_of_luminance_times_area() {
    let position = Vec3::new(0.2, 1.0, -0.3);
    let side = 0.01;
    let nits = 2.0e4;
    let rect = area_light(LightKind::Rect { width: side, height: side }, position, Vec3::NEG_Y, nits);
    let mut point = point_light(position, nits * side * side, None);
    point.shadow.mode = ShadowMode::None;
    let mut renderer = renderer();
    let area_frame = render(&mut renderer, &floor_with(rect, 1.0, 0.0), &unlit_settings(), 128);
    let point_frame = render(&mut renderer, &floor_with(point, 1.0, 0.0), &unlit_settings(), 128);
    let (area_pixels, point_pixels) = (surface_pixels(&area_frame), surface_pixels(&point_frame));
    let mut compared = 0;
    for (a, p) in area_pixels.iter().zip(&point_pixels) {
        // A point light lights all around; the rect only below its plane, by its cosine:
        // compare straight under it, where that cosine is near 1.
        let below = position - a.1;
        if below.y / below.length() > 0.97 && p.3.x > 1e-3 {
            compared += 1;
            let cosine = below.y / below.length();
            assert!((a.3.x / (p.3.x * cosine) - 1.0).abs() < 0.01, "{} vs {} x {cosine}", a.3.x, p.3.x);
        }
    }
    assert!(compared > 20, "{compared} pixels under the light");
}

#[test]
fn nothing_behind_an_area_light_is_lit() {
    // Facing up: the floor under it is behind it.
    let light = area_light(LightKind::Disk { diameter: 1.0 }, Vec3::new(0.0, 0.5, 0.0), Vec3::Y, 100.0);
    let frame = render(&mut renderer(), &floor_with(light, 1.0, 0.0), &unlit_settings(), 96);
    for &(_, p, _, radiance) in &surface_pixels(&frame) {
        assert_eq!(radiance, Vec3::ZERO, "lit at {p}");
    }
}

/// The specular light the shader's LTC predicts, on the CPU: the table's lobe over the
/// light's outline in the shading frame, times the split-sum albedo and the
/// multiple-scattering compensation, for a metal of reflectance `f0`.
fn ltc_specular(light: &Light, p: Vec3, f0: f32, roughness: f32) -> f32 {
    let v = (EYE - p).normalize();
    let n_dot_v = v.y.clamp(1e-4, 1.0);
    let t1 = (v - Vec3::Y * v.y).normalize();
    let t2 = Vec3::Y.cross(t1);
    let points: Vec<Vec3> = light
        .area_outline_ws()
        .unwrap()
        .iter()
        .map(|&q| {
            let d = q - p;
            Vec3::new(d.dot(t1), d.dot(t2), d.y)
        })
        .collect();
    let terms = chiaro_math::environment::SplitSumTable::shared().terms(n_dot_v, roughness);
    let compensation = chiaro_math::brdf::multiple_scattering_compensation(
        Vec3::splat(f0),
        chiaro_math::brdf::multiple_scattering_energy(n_dot_v, roughness),
    )
    .x;
    let lobe = chiaro_math::ltc::polygon_integral(chiaro_math::ltc::inverse_at(n_dot_v, roughness), &points);
    light.intensity * (f0 * terms.x + terms.y) * compensation * lobe
}

#[test]
fn a_glossy_metal_floor_reflects_a_rect_as_the_ltc_table_predicts() {
    // The shader reads the table through the GPU's filter, in half floats, and clips and
    // integrates the outline as the CPU twin does.
    let light = area_light(LightKind::Rect { width: 1.0, height: 0.6 }, Vec3::new(0.0, 1.5, -1.0), Vec3::NEG_Y, 30.0);
    let scene = floor_with(light.clone(), 0.45, 1.0);
    let frame = render(&mut renderer(), &scene, &unlit_settings(), 160);
    let (median, within5, _) = judge(&frame, |p| ltc_specular(&light, p, 0.8, 0.45));
    assert!((median - 1.0).abs() < 0.005, "median ratio {median}");
    assert!(within5 > 0.99, "{within5} within 5%");
}

/// Each shadow tile's side in texels, per light, in tile order.
fn local_tile_sides(scene: &chiaro_scene::Scene) -> Vec<Vec<u32>> {
    let mut renderer = renderer();
    let prepared = renderer.prepare(scene).expect("prepare");
    let view = chiaro_render::View::from_camera(scene, 0, 32, 32);
    let settings = chiaro_scene::Settings::default();
    let out = renderer.render(scene, &prepared, &view, &settings, Default::default()).expect("render");
    let mut sides = vec![Vec::new(); scene.lights.len()];
    for tile in &out.plan.shadows.tiles {
        sides[tile.light.index()].push(tile.viewport.2);
    }
    sides
}

#[test]
fn an_area_lights_cube_faces_towards_its_lit_side_get_finer_tiles() {
    // Cube faces in the order +X, -X, +Y, -Y, +Z, -Z. A rect shining down beside a point
    // light: 12 tiles of 512 in the default 2048 atlas's uniform layout, room for the
    // rect's -Y face to double. A rect tilted towards +X (cosine 0.6 with +X, 0.8 with -Y)
    // alone: two faces double.
    let rect = LightKind::Rect { width: 1.0, height: 0.5 };
    let shadowed = |mut light: Light| {
        light.shadow.mode = ShadowMode::Pcss;
        light
    };
    let down = shadowed(area_light(rect, Vec3::new(0.0, 2.0, 0.0), Vec3::NEG_Y, 500.0));
    let tilted = shadowed(area_light(rect, Vec3::new(1.0, 2.0, 0.0), Vec3::new(0.6, -0.8, 0.0), 500.0));
    let mut point = point_light(Vec3::new(-1.0, 1.0, 0.0), 20.0, Some(10.0));
    point.shadow = chiaro_scene::LightShadow::default();
    let sides = local_tile_sides(&floor_scene(6.0, EYE, vec![down, point]));
    assert_eq!(sides, vec![vec![512, 512, 512, 1024, 512, 512], vec![512; 6]]);
    let sides = local_tile_sides(&floor_scene(6.0, EYE, vec![tilted]));
    assert_eq!(sides, vec![vec![1024, 512, 512, 1024, 512, 512]]);
}
