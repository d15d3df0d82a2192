//! Light cookies against their definition (docs/lights.md): for each light type and on
//! both paths, the ratio of a render with the cookie to one without it is, at every lit
//! pixel, the cookie looked up by the definition at that pixel's world position (from the
//! position AOV). The cookies are smooth patterns whose value where the coordinates wrap
//! or cross a cube face differs from their mean, so a seam or a wrong-mip fringe there
//! would show.

mod common;

use chiaro_math::cube_map::{cube_map_direction, cube_map_uv};
use chiaro_scene::{ColorSpace, Cookie, Image, Light, LightKind, RenderPath, Scene, ShadowMode};
use common::*;
use glam::{Mat4, Vec2, Vec3};
use std::f32::consts::TAU;

const SIZE: u32 = 256;
const EYE: Vec3 = Vec3::new(0.0, 7.0, 0.01);

/// An RGBA8 image whose texel centres hold `f(u, v)`.
fn image_from(width: u32, height: u32, f: impl Fn(f32, f32) -> Vec3) -> Image {
    let mut rgba8 = Vec::with_capacity((width * height * 4) as usize);
    for y in 0..height {
        for x in 0..width {
            let c = f((x as f32 + 0.5) / width as f32, (y as f32 + 0.5) / height as f32);
            rgba8.extend(c.to_array().map(|v| (v.clamp(0.0, 1.0) * 255.0).round() as u8));
            rgba8.push(255);
        }
    }
    Image {
        name: "cookie".into(),
        width,
        height,
        rgba8,
        file_mips: Vec::new(),
        color_space: ColorSpace::Linear,
        basis_source: None,
    }
}

/// Periodic in u and v, at its brightest where u wraps (red) and v wraps (green).
fn pattern(u: f32, v: f32) -> Vec3 {
    Vec3::new(0.5 + 0.45 * (TAU * u).cos(), 0.5 + 0.45 * (TAU * v).cos(), 0.5 + 0.45 * (TAU * (u + v)).sin())
}

/// Bilinear lookup between texel centres of `columns` (a column range of `image`),
/// repeating or clamping at the edges: what a GPU sampler does at the base mip.
fn bilinear(image: &Image, columns: (u32, u32), u: f32, v: f32, repeat: bool) -> Vec3 {
    let width = columns.1 - columns.0;
    let texel = |x: i64, y: i64| {
        let (x, y) = if repeat {
            (x.rem_euclid(width as i64), y.rem_euclid(image.height as i64))
        } else {
            (x.clamp(0, width as i64 - 1), y.clamp(0, image.height as i64 - 1))
        };
        let i = ((y as u32 * image.width + columns.0 + x as u32) * 4) as usize;
        Vec3::new(image.rgba8[i] as f32, image.rgba8[i + 1] as f32, image.rgba8[i + 2] as f32) / 255.0
    };
    let (x, y) = (u * width as f32 - 0.5, v * image.height as f32 - 0.5);
    let (x0, y0) = (x.floor(), y.floor());
    let (fx, fy) = (x - x0, y - y0);
    let (x0, y0) = (x0 as i64, y0 as i64);
    let top = texel(x0, y0).lerp(texel(x0 + 1, y0), fx);
    let bottom = texel(x0, y0 + 1).lerp(texel(x0 + 1, y0 + 1), fx);
    top.lerp(bottom, fy)
}

/// A point cookie, six faces of `n` texels, each texel the colour of its direction.
fn cube_image(n: u32) -> Image {
    image_from(6 * n, n, |u, v| {
        let face = (u * 6.0).floor() as u32;
        let d = cube_map_direction(face as usize, Vec2::new(u * 6.0 - face as f32, v));
        Vec3::splat(0.5) + 0.45 * Vec3::new(d.x, d.y * d.y.abs(), d.z)
    })
}

/// The cookie of `light` at world position `p`, by the definition.
fn cookie_at(light: &Light, image: &Image, p: Vec3) -> Vec3 {
    let local = light.world_from_light.inverse().transform_point3(p);
    match light.kind {
        LightKind::Directional => {
            let size = light.cookie.unwrap().size_m;
            bilinear(image, (0, image.width), local.x / size.x, -local.y / size.y, true)
        }
        LightKind::Spot { outer_cone_rad, .. } => {
            let z = -local.z;
            let scale = 0.5 / (z * outer_cone_rad.tan());
            bilinear(image, (0, image.width), 0.5 + local.x * scale, 0.5 - local.y * scale, false)
        }
        LightKind::Point => {
            let (face, st) = cube_map_uv(local);
            let (face, n) = (face as u32, image.height);
            bilinear(image, (face * n, (face + 1) * n), st.x, st.y, false)
        }
        LightKind::Rect { .. } | LightKind::Disk { .. } => unreachable!("area lights take no cookie"),
    }
}

/// Per-pixel cookie error on `path`: |rendered ratio - definition| over the pixels the
/// light lights to at least 5% of its brightest, per channel; returns (share of pixels
/// off by more than 0.02, worst error, pixels compared).
fn cookie_error(scene: &Scene, path: RenderPath) -> (f64, f32, usize) {
    let mut settings = unlit_settings();
    settings.render.path = path;
    let mut r = renderer();
    let with = render(&mut r, scene, &settings, SIZE);
    let mut bare = scene.clone();
    bare.lights[0].cookie = None;
    let without = render(&mut r, &bare, &settings, SIZE);
    let light = &scene.lights[0];
    let image = &scene.images[light.cookie.unwrap().image];
    let brightest = without.hdr.iter().map(|p| p[0].max(p[1]).max(p[2])).fold(0.0, f32::max);
    let aovs = with.aovs.as_ref().unwrap();
    let (mut compared, mut off, mut worst) = (0, 0, 0.0f32);
    for (i, (w, b)) in with.hdr.iter().zip(&without.hdr).enumerate() {
        let p = Vec3::from(aovs.position_ws[i]);
        if !p.is_finite() || b[0].min(b[1]).min(b[2]) < 0.05 * brightest {
            continue;
        }
        let ratio = Vec3::new(w[0] / b[0], w[1] / b[1], w[2] / b[2]);
        let error = (ratio - cookie_at(light, image, p)).abs().max_element();
        compared += 1;
        if error > 0.02 {
            off += 1;
        }
        worst = worst.max(error);
    }
    (off as f64 / compared.max(1) as f64, worst, compared)
}

fn check(name: &str, scene: &Scene, min_pixels: usize) {
    for path in [RenderPath::Forward, RenderPath::Deferred] {
        let (off, worst, compared) = cookie_error(scene, path);
        println!("{name} {path:?}: {compared} pixels, {:.3}% off by > 0.02, worst {worst:.4}", 100.0 * off);
        assert!(compared >= min_pixels, "{name} {path:?}: only {compared} pixels lit");
        assert!(off < 0.005 && worst < 0.1, "{name} {path:?}: {:.3}% off by > 0.02, worst {worst}", 100.0 * off);
    }
}

fn lit_floor(mut light: Light, image: Image, size_m: Vec2) -> Scene {
    light.shadow.mode = ShadowMode::None;
    light.cookie = Some(Cookie { image: 0, size_m });
    let mut scene = floor_scene(12.0, EYE, vec![light]);
    scene.images.push(image);
    scene
}

/// Rolls and turns a light about its own axes, so its local X and Y are not the world's.
fn turned(light: Light, rotation: Mat4) -> Light {
    Light { world_from_light: light.world_from_light * rotation, ..light }
}

#[test]
fn directional_cookies_tile_in_the_lights_plane() {
    let light = Light {
        intensity: 2.0,
        ..Light::new(LightKind::Directional, Vec3::new(0.3, 4.0, -0.7), Vec3::new(0.2, -1.0, 0.3))
    };
    let light = turned(light, Mat4::from_rotation_z(0.6));
    let scene = lit_floor(light, image_from(64, 48, pattern), Vec2::new(2.5, 1.5));
    check("directional", &scene, 40_000);
}

#[test]
fn spot_cookies_project_through_the_cone() {
    let spot = LightKind::Spot { inner_cone_rad: 0.45, outer_cone_rad: 0.6 };
    let light = Light {
        intensity: 40.0,
        range: Some(20.0),
        ..Light::new(spot, Vec3::new(0.4, 3.0, -0.3), Vec3::new(0.15, -1.0, 0.1))
    };
    let light = turned(light, Mat4::from_rotation_z(-0.9));
    check("spot", &lit_floor(light, image_from(64, 64, pattern), Vec2::ONE), 3_000);
}

#[test]
fn point_cookies_wrap_the_light_in_six_faces() {
    let base = Light {
        intensity: 20.0,
        range: Some(30.0),
        ..Light::new(LightKind::Point, Vec3::new(0.2, 1.5, -0.1), Vec3::NEG_Z)
    };
    // Local -Y, then local +Y facing the floor: between them every face is seen.
    for (name, rotation) in [
        ("point", Mat4::from_rotation_y(0.5)),
        ("point upside down", Mat4::from_rotation_x(std::f32::consts::PI) * Mat4::from_rotation_y(-0.3)),
    ] {
        let light = turned(base.clone(), rotation);
        check(name, &lit_floor(light, cube_image(32), Vec2::ONE), 20_000);
    }
}

#[test]
fn the_definition_helpers_agree_with_each_other() {
    // The lookup reproduces a texel centre and repeats.
    let image = image_from(8, 4, pattern);
    let centre = bilinear(&image, (0, 8), 2.5 / 8.0, 1.5 / 4.0, true);
    assert!((centre - pattern(2.5 / 8.0, 1.5 / 4.0)).abs().max_element() < 1.0 / 255.0);
    let wrapped = bilinear(&image, (0, 8), 0.3, 0.4, true) - bilinear(&image, (0, 8), 1.3, -0.6, true);
    assert!(wrapped.abs().max_element() < 1e-4, "{wrapped}");
}
