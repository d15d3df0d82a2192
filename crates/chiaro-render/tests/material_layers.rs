//! The KHR_materials_* extensions by their defining behaviour, on both paths: a
//! clearcoat's sharp second highlight over a rough base, sheen brightening grazing angles
//! far more than facing ones, a thin film shifting hue with the viewing angle, anisotropy
//! stretching the highlight along the tangent, diffuse transmission lighting the side
//! away from the light in its colour, and ior and specular setting the dielectric's
//! reflectance. Each case compares the same sphere with and without the extension; the
//! deferred path (which draws layered materials forward over its G-buffer) must give the
//! forward path's image.

mod common;

use chiaro_render::{FrameOutput, Renderer};
use chiaro_scene::settings::EnvironmentSource;
use chiaro_scene::{Light, LightKind, MaterialLayers, RenderPath, Scene, Settings};
use common::*;
use glam::Vec3;

const SIZE: u32 = 160;

/// One sphere of `base` in `layers`, lit by `lights`, seen from +Z.
fn sphere_scene(base: Vec3, metallic: f32, roughness: f32, layers: MaterialLayers, lights: Vec<Light>) -> Scene {
    let mut scene = spheres_scene(&[SphereMaterial { base_color: base, metallic, roughness }]);
    scene.materials[0].layers = layers;
    scene.lights = lights;
    scene
}

/// A sun shining along `towards` (from the light to the scene).
fn sun(towards: Vec3, lux: f32) -> Light {
    Light { intensity: lux, ..Light::new(LightKind::Directional, Vec3::ZERO, towards) }
}

fn settings(path: RenderPath) -> Settings {
    let mut s = unlit_settings();
    s.render.path = path;
    s.render.msaa = 1;
    s
}

/// A sphere pixel: its normal, view direction and radiance.
struct Pixel {
    index: usize,
    position: Vec3,
    normal: Vec3,
    view: Vec3,
    radiance: Vec3,
}

fn sphere_pixels(frame: &FrameOutput, scene: &Scene) -> Vec<Pixel> {
    let eye = scene.cameras[0].world_from_view.w_axis.truncate();
    surface_pixels(frame)
        .into_iter()
        .map(|(index, position, normal, radiance)| Pixel {
            index,
            position,
            normal: normal.normalize(),
            view: (eye - position).normalize(),
            radiance,
        })
        .collect()
}

fn luminance(c: Vec3) -> f32 {
    c.dot(Vec3::new(0.2126, 0.7152, 0.0722))
}

/// Renders `scene` on `path`; asserts the frame drew the layered material forward there.
fn frame(renderer: &mut Renderer, scene: &Scene, settings: &Settings) -> FrameOutput {
    let frame = render(renderer, scene, settings, SIZE);
    if settings.render.path == RenderPath::Deferred && scene.materials[0].layers.is_layered() {
        assert_eq!(frame.plan.forward_draws.len(), 1, "the layered sphere is drawn forward over the G-buffer");
    }
    frame
}

/// Renders the sphere with `layers` and with none, on both paths; checks that the paths
/// agree and passes each path's two frames' pixels to `check`.
fn compare(
    base: Vec3,
    metallic: f32,
    roughness: f32,
    layers: MaterialLayers,
    lights: Vec<Light>,
    environment: Option<&std::path::Path>,
    check: impl Fn(RenderPath, &[Pixel], &[Pixel]),
) {
    let plain_scene = sphere_scene(base, metallic, roughness, MaterialLayers::default(), lights.clone());
    let layered_scene = sphere_scene(base, metallic, roughness, layers, lights);
    compare_scenes(&plain_scene, &layered_scene, environment, check);
}

/// `compare` for any two scenes that differ in their first material's layers.
fn compare_scenes(
    plain_scene: &Scene,
    layered_scene: &Scene,
    environment: Option<&std::path::Path>,
    check: impl Fn(RenderPath, &[Pixel], &[Pixel]),
) {
    let mut renderer = renderer();
    let mut forward_layered = Vec::new();
    for path in [RenderPath::Forward, RenderPath::Deferred] {
        let mut s = settings(path);
        if let Some(env) = environment {
            s.environment.source = EnvironmentSource::File(env.to_path_buf());
        }
        let plain = sphere_pixels(&frame(&mut renderer, plain_scene, &s), plain_scene);
        let layered = sphere_pixels(&frame(&mut renderer, layered_scene, &s), layered_scene);
        assert_eq!(plain.len(), layered.len(), "the same sphere covers the same pixels");
        assert!(plain.len() > 3000, "{} sphere pixels", plain.len());
        check(path, &plain, &layered);
        match path {
            RenderPath::Forward => forward_layered = layered,
            RenderPath::Deferred => {
                // The deferred path shades layered materials with the forward shader.
                let mean_error: f32 = forward_layered
                    .iter()
                    .zip(&layered)
                    .map(|(f, d)| (f.radiance - d.radiance).abs().max_element() / (luminance(f.radiance) + 0.01))
                    .sum::<f32>()
                    / layered.len() as f32;
                assert!(mean_error < 0.01, "forward and deferred differ by {mean_error} (relative)");
            }
        }
    }
}

#[test]
fn clearcoat_adds_a_sharp_second_highlight_over_a_rough_base() {
    let to_light = Vec3::new(-0.4, 0.5, 1.0).normalize();
    let layers = MaterialLayers { clearcoat: 1.0, clearcoat_roughness: 0.05, ..Default::default() };
    compare(Vec3::new(0.6, 0.05, 0.05), 0.0, 0.8, layers, vec![sun(-to_light, 3.0)], None, |path, plain, coated| {
        let peak = |pixels: &[Pixel]| pixels.iter().map(|p| luminance(p.radiance)).fold(0.0, f32::max);
        let (plain_peak, coated_peak) = (peak(plain), peak(coated));
        assert!(coated_peak > 4.0 * plain_peak, "{path:?}: coat peak {coated_peak} vs base peak {plain_peak}");
        // The coat's highlight sits where the normal is the half vector, and is small.
        let brightest = coated.iter().max_by(|a, b| luminance(a.radiance).total_cmp(&luminance(b.radiance))).unwrap();
        let half = (to_light + brightest.view).normalize();
        assert!(brightest.normal.dot(half) > 0.99, "{path:?}: coat peak at n.h {}", brightest.normal.dot(half));
        let bright = coated.iter().filter(|p| luminance(p.radiance) > 0.5 * coated_peak).count();
        assert!(bright < coated.len() / 100, "{path:?}: {bright} pixels in the coat's highlight");
        // Away from the highlight the coat only takes its Fresnel share of the base's light.
        for (p, c) in plain.iter().zip(coated) {
            let n_dot_h = p.normal.dot((to_light + p.view).normalize());
            if n_dot_h < 0.9 && p.normal.dot(to_light) > 0.2 && p.normal.dot(p.view) > 0.5 {
                let ratio = luminance(c.radiance) / luminance(p.radiance);
                assert!((0.85..=1.0).contains(&ratio), "{path:?}: pixel {} off the highlight: {ratio}", p.index);
            }
        }
    });
}

#[test]
fn sheen_brightens_grazing_angles_far_more_than_facing_ones() {
    // Lit from the camera: every visible point is lit, the rim at grazing angles.
    let layers = MaterialLayers { sheen_color: Vec3::ONE, sheen_roughness: 0.4, ..Default::default() };
    compare(Vec3::splat(0.05), 0.0, 0.9, layers, vec![sun(Vec3::NEG_Z, 3.0)], None, |path, plain, sheen| {
        let gain = |lo: f32, hi: f32| {
            let (mut a, mut b) = (0.0, 0.0);
            for (p, s) in plain.iter().zip(sheen) {
                let n_dot_v = p.normal.dot(p.view);
                if (lo..hi).contains(&n_dot_v) {
                    a += luminance(p.radiance);
                    b += luminance(s.radiance);
                }
            }
            b / a
        };
        let (rim, facing) = (gain(0.15, 0.35), gain(0.9, 1.0));
        assert!(rim > 3.0, "{path:?}: sheen multiplies the rim by {rim}");
        assert!(rim > 2.0 * facing, "{path:?}: rim gain {rim} vs facing gain {facing}");
    });
}

#[test]
fn a_thin_film_shifts_hue_with_the_viewing_angle() {
    // A black dielectric in a white furnace: all that comes back is the specular
    // reflection, white without the film.
    let env = write_uniform_environment("iridescence-furnace.hdr");
    let layers = MaterialLayers { iridescence: 1.0, iridescence_thickness_max: 450.0, ..Default::default() };
    compare(Vec3::ZERO, 0.0, 0.2, layers, Vec::new(), Some(&env), |path, plain, film| {
        let chroma = |pixels: &[Pixel], lo: f32, hi: f32| {
            let sum: Vec3 =
                pixels.iter().filter(|p| (lo..hi).contains(&p.normal.dot(p.view))).map(|p| p.radiance).sum();
            sum / (sum.x + sum.y + sum.z)
        };
        let grey = Vec3::splat(1.0 / 3.0);
        for (lo, hi) in [(0.9, 1.0), (0.4, 0.6)] {
            let c = chroma(plain, lo, hi);
            assert!((c - grey).abs().max_element() < 0.01, "{path:?}: without film, n.v {lo}..{hi} is {c}");
        }
        let (facing, oblique) = (chroma(film, 0.9, 1.0), chroma(film, 0.4, 0.6));
        assert!((facing - grey).abs().max_element() > 0.03, "{path:?}: the film's colour head-on {facing}");
        assert!((facing - oblique).abs().max_element() > 0.03, "{path:?}: hue {facing} head-on, {oblique} at 60 deg");
    });
}

#[test]
fn anisotropy_stretches_the_highlight_along_the_tangent() {
    // The sphere's tangents run along its parallels (shapes::sphere): screen X where
    // the highlight is, seen from +Z.
    let to_light = Vec3::new(0.0, 0.0, 1.0);
    let layers = MaterialLayers { anisotropy_strength: 0.8, ..Default::default() };
    compare(Vec3::new(0.9, 0.9, 0.9), 1.0, 0.3, layers, vec![sun(-to_light, 3.0)], None, |path, plain, aniso| {
        let extent = |pixels: &[Pixel]| {
            let peak = pixels.iter().map(|p| luminance(p.radiance)).fold(0.0, f32::max);
            let bright: Vec<&Pixel> = pixels.iter().filter(|p| luminance(p.radiance) > 0.5 * peak).collect();
            let spread = |axis: fn(Vec3) -> f32| {
                let values: Vec<f32> = bright.iter().map(|p| axis(p.normal)).collect();
                values.iter().cloned().fold(f32::MIN, f32::max) - values.iter().cloned().fold(f32::MAX, f32::min)
            };
            (spread(|n| n.x), spread(|n| n.y))
        };
        let (px, py) = extent(plain);
        assert!((px / py - 1.0).abs() < 0.2, "{path:?}: the isotropic highlight is round: {px} x {py}");
        let (ax, ay) = extent(aniso);
        assert!(ax > 1.8 * ay, "{path:?}: the anisotropic highlight is {ax} wide, {ay} tall");
    });
}

/// A double-sided 2 m square facing the camera (+Z) in place of the sphere: a leaf.
fn leaf_scene(layers: MaterialLayers, lights: Vec<Light>) -> Scene {
    let mut scene = sphere_scene(Vec3::splat(0.8), 0.0, 0.6, layers, lights);
    let mut leaf = chiaro_scene::shapes::plane(2.0, 1);
    leaf.material = Some(0);
    scene.meshes[0] = chiaro_scene::Mesh::of_triangles("leaf".into(), vec![leaf]);
    scene.materials[0].double_sided = true;
    scene.instances[0].world_from_local = glam::Mat4::from_rotation_x(std::f32::consts::FRAC_PI_2);
    scene
}

#[test]
fn diffuse_transmission_lights_the_far_side_in_its_colour() {
    // The sun is behind the leaf: the camera sees only its unlit side, which the leaf's
    // own shadow map must not darken.
    let layers = MaterialLayers {
        diffuse_transmission: 1.0,
        diffuse_transmission_color: Vec3::new(0.1, 1.0, 0.1),
        ..Default::default()
    };
    let lights = vec![sun(Vec3::new(0.3, -0.2, 1.0).normalize(), 3.0)];
    let (plain_scene, leaf) = (leaf_scene(MaterialLayers::default(), lights.clone()), leaf_scene(layers, lights));
    compare_scenes(&plain_scene, &leaf, None, |path, plain, through| {
        let centre: Vec<(&Pixel, &Pixel)> =
            plain.iter().zip(through).filter(|(p, _)| p.normal.dot(p.view) > 0.8).collect();
        assert!(centre.len() > 500);
        for (p, t) in centre {
            assert!(p.radiance.max_element() < 1e-4, "{path:?}: lit without transmission: {}", p.radiance);
            // Lambert from behind in the transmission colour (not the base's 0.8), less
            // the dielectric's reflection towards the eye: colour * cos / pi * 3 lux * (1 - F).
            let cos = Vec3::new(0.3, -0.2, 1.0).normalize().dot(Vec3::Z);
            let fresnel = 0.04 + 0.96 * (1.0 - p.normal.dot(p.view)).powi(5);
            let expected = 1.0 * 3.0 * cos / std::f32::consts::PI * (1.0 - fresnel);
            assert!((t.radiance.y / expected - 1.0).abs() < 0.05, "{path:?}: {} vs {expected}", t.radiance.y);
            assert!(t.radiance.y > 8.0 * t.radiance.x, "{path:?}: transmitted light is green: {}", t.radiance);
        }
    });
}

#[test]
fn ior_and_specular_set_the_dielectrics_reflectance() {
    // A black dielectric reflects only its Fresnel: F0 is ((ior - 1) / (ior + 1))^2.
    let to_light = Vec3::new(0.2, 0.3, 1.0).normalize();
    let lights = vec![sun(-to_light, 3.0)];
    let f0 = |ior: f32| ((ior - 1.0) / (ior + 1.0)).powi(2);
    let dense = MaterialLayers { ior: 2.5, ..Default::default() };
    compare(Vec3::ZERO, 0.0, 0.4, dense, lights.clone(), None, |path, plain, dense| {
        let near_normal: Vec<f32> = plain
            .iter()
            .zip(dense)
            .filter(|(p, _)| p.normal.dot((to_light + p.view).normalize()) > 0.999)
            .map(|(p, d)| luminance(d.radiance) / luminance(p.radiance))
            .collect();
        assert!(!near_normal.is_empty());
        let mean = near_normal.iter().sum::<f32>() / near_normal.len() as f32;
        // Schlick's F at the highlight's small v.h angle is F0 within a percent or two.
        let expected = f0(2.5) / f0(1.5);
        assert!((mean / expected - 1.0).abs() < 0.1, "{path:?}: highlight gain {mean}, F0 gain {expected}");
    });
    // A coloured specular tints the reflection, not the diffuse light under it: the spec
    // weighs the diffuse by 1 - max(F), a grey weight. Against the untinted material (red
    // channel alike), red is unchanged and green and blue only lose their reflection;
    // weighed per channel, their diffuse would grow instead.
    let tinted = MaterialLayers { specular_color: Vec3::new(1.0, 0.2, 0.2), ..Default::default() };
    compare(Vec3::ONE, 0.0, 0.9, tinted, lights.clone(), None, |path, plain, tinted| {
        for (p, t) in plain.iter().zip(tinted).filter(|(p, _)| p.normal.dot(to_light) > 0.3) {
            assert!(
                (t.radiance.x / p.radiance.x - 1.0).abs() < 0.005,
                "{path:?}: red {} vs {}",
                t.radiance,
                p.radiance
            );
            assert!(t.radiance.y <= p.radiance.y * 1.001, "{path:?}: green {} vs {}", t.radiance, p.radiance);
        }
    });
    let none = MaterialLayers { specular: 0.0, ..Default::default() };
    compare(Vec3::ZERO, 0.0, 0.4, none, lights, None, |path, _, none| {
        let brightest = none.iter().map(|p| p.radiance.max_element()).fold(0.0, f32::max);
        assert!(brightest < 1e-4, "{path:?}: specular 0 leaves a black dielectric black: {brightest}");
    });
}

/// A uniform white environment (radiance 1) written as an .hdr in this run's folder.
fn write_uniform_environment(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("chiaro-material-layers-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(name);
    chiaro_scene::environment::EnvironmentMap::from_fn(64, |_| Vec3::ONE).write_hdr(&path).unwrap();
    path
}

/// A transmissive sphere in front of an unlit wall (radiance `wall` exactly), no light.
fn sphere_before_wall(layers: MaterialLayers, wall: Vec3) -> Scene {
    let mut scene = sphere_scene(Vec3::ONE, 0.0, 0.05, layers, Vec::new());
    let mut plane = chiaro_scene::shapes::plane(40.0, 1);
    plane.material = Some(1);
    scene.meshes.push(chiaro_scene::Mesh::of_triangles("wall".into(), vec![plane]));
    scene.materials.push(chiaro_scene::Material {
        name: "wall".into(),
        base_color: wall.extend(1.0),
        unlit: true,
        ..Default::default()
    });
    let mut instance = scene.instances[0].clone();
    instance.mesh = 1;
    instance.node = 200;
    instance.name = "wall".into();
    instance.world_from_local = glam::Mat4::from_translation(Vec3::new(0.0, 0.0, -3.0))
        * glam::Mat4::from_rotation_x(std::f32::consts::FRAC_PI_2);
    scene.instances.push(instance);
    scene
}

/// The sphere's pixels near its centre (n.v above 0.95) in both paths' frames, each
/// path's mean radiance there.
fn centre_radiance(scene: &Scene) -> Vec<(RenderPath, Vec3)> {
    let mut renderer = renderer();
    [RenderPath::Forward, RenderPath::Deferred]
        .into_iter()
        .map(|path| {
            let frame = render(&mut renderer, scene, &settings(path), SIZE);
            let sphere: Vec<Vec3> = sphere_pixels(&frame, scene)
                .into_iter()
                .filter(|p| p.position.length() < 1.01 && p.normal.dot(p.view) > 0.95)
                .map(|p| p.radiance)
                .collect();
            assert!(sphere.len() > 100, "{path:?}: {} centre pixels", sphere.len());
            (path, sphere.iter().sum::<Vec3>() / sphere.len() as f32)
        })
        .collect()
}

#[test]
fn a_transmissive_sphere_shows_the_wall_behind_it() {
    let wall = Vec3::new(0.1, 0.8, 0.2);
    let opaque = centre_radiance(&sphere_before_wall(MaterialLayers::default(), wall));
    for (path, c) in &opaque {
        assert!(c.max_element() < 1e-3, "{path:?}: an opaque sphere in the dark is black: {c}");
    }
    // Thin-walled: the wall straight through, less what the surface reflects (about 4%
    // head-on, the sphere's white base tinting nothing).
    let glass = MaterialLayers { transmission: 1.0, ..Default::default() };
    for (path, c) in centre_radiance(&sphere_before_wall(glass, wall)) {
        let ratio = c / wall;
        assert!((ratio - Vec3::splat(0.96)).abs().max_element() < 0.03, "{path:?}: {c} through glass, wall {wall}");
    }
    // A volume of red glass absorbs green and blue on its way through: attenuation
    // colour (1, 0.5, 0.5) per unit, across the sphere's 2 units.
    let red_glass = MaterialLayers {
        transmission: 1.0,
        thickness: 2.0,
        attenuation_distance: 1.0,
        attenuation_color: Vec3::new(1.0, 0.5, 0.5),
        ..Default::default()
    };
    for (path, c) in centre_radiance(&sphere_before_wall(red_glass, Vec3::ONE)) {
        let expected = Vec3::new(1.0, 0.25, 0.25) * 0.96;
        assert!((c - expected).abs().max_element() < 0.04, "{path:?}: {c} through red glass, expected {expected}");
    }
}

#[test]
fn a_device_that_binds_sixteen_textures_draws_transmissive_materials_unrefracted() {
    // WebGPU's default limit: one texture short of what the refracting shader binds.
    let adapter = chiaro_render::GpuContext::adapters().into_iter().next().expect("an adapter");
    let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor::default())).unwrap();
    assert_eq!(device.limits().max_sampled_textures_per_shader_stage, 16);
    let mut renderer = Renderer::new(chiaro_render::GpuContext::from_device(&adapter, device, queue)).unwrap();
    let scene = sphere_before_wall(MaterialLayers { transmission: 1.0, ..Default::default() }, Vec3::Y);
    for path in [RenderPath::Forward, RenderPath::Deferred] {
        let frame = render(&mut renderer, &scene, &settings(path), SIZE);
        let centre: Vec<Vec3> = sphere_pixels(&frame, &scene)
            .into_iter()
            .filter(|p| p.position.length() < 1.01 && p.normal.dot(p.view) > 0.95)
            .map(|p| p.radiance)
            .collect();
        assert!(centre.len() > 100, "{path:?}: the sphere is drawn");
        // Drawn, unlit (no light), and showing nothing of the green wall behind it.
        for c in centre {
            assert!(c.max_element() < 1e-3, "{path:?}: {c}");
        }
    }
}

#[test]
fn an_anisotropic_metal_in_a_furnace_returns_no_more_light_than_it_receives() {
    // A 0.9 metal in a uniform white environment reflects at most 0.9 of it, however
    // stretched its lobe (multiple scattering returns what single scattering loses).
    let env = write_uniform_environment("anisotropy-furnace.hdr");
    for strength in [0.5, 1.0] {
        let layers = MaterialLayers { anisotropy_strength: strength, ..Default::default() };
        compare(Vec3::splat(0.9), 1.0, 0.4, layers, Vec::new(), Some(&env), |path, plain, aniso| {
            let mean =
                |pixels: &[Pixel]| pixels.iter().map(|p| luminance(p.radiance)).sum::<f32>() / pixels.len() as f32;
            let (plain, aniso) = (mean(plain), mean(aniso));
            assert!(plain <= 0.9 && aniso <= 0.9, "{path:?} strength {strength}: {plain} plain, {aniso} stretched");
            assert!(aniso > 0.95 * plain, "{path:?} strength {strength}: {aniso} against {plain}");
        });
    }
}

#[test]
fn dispersion_parts_the_colours_of_an_edge_seen_through_a_volume() {
    // A glass ball before a wall white on the left, black on the right: through the
    // ball the edge is refracted, each colour at its own ior where the glass disperses.
    let two_tone = |dispersion: f32| {
        let layers = MaterialLayers { transmission: 1.0, thickness: 2.0, dispersion, ..Default::default() };
        let mut scene = sphere_before_wall(layers, Vec3::ONE);
        let mut dark = scene.instances[1].clone();
        dark.node = 201;
        dark.name = "dark half".into();
        // A black unlit panel just in front of the right half of the wall.
        dark.world_from_local = glam::Mat4::from_translation(Vec3::new(20.0, 0.0, -2.9))
            * glam::Mat4::from_rotation_x(std::f32::consts::FRAC_PI_2);
        dark.mesh = scene.meshes.len();
        let mut panel = chiaro_scene::shapes::plane(40.0, 1);
        panel.material = Some(2);
        scene.meshes.push(chiaro_scene::Mesh::of_triangles("dark".into(), vec![panel]));
        scene.materials.push(chiaro_scene::Material {
            name: "dark".into(),
            base_color: glam::Vec4::new(0.0, 0.0, 0.0, 1.0),
            unlit: true,
            ..Default::default()
        });
        scene.instances.push(dark);
        scene
    };
    let mut renderer = renderer();
    for path in [RenderPath::Forward, RenderPath::Deferred] {
        let parting = |scene: &Scene, renderer: &mut Renderer| {
            let frame = render(renderer, scene, &settings(path), SIZE);
            sphere_pixels(&frame, scene)
                .into_iter()
                .filter(|p| p.position.length() < 1.01)
                .map(|p| (p.radiance.x - p.radiance.z).abs())
                .fold(0.0, f32::max)
        };
        let plain = parting(&two_tone(0.0), &mut renderer);
        let dispersed = parting(&two_tone(10.0), &mut renderer);
        assert!(plain < 0.01, "{path:?}: without dispersion red and blue refract alike: {plain}");
        assert!(dispersed > 0.2, "{path:?}: with dispersion the edge parts red from blue by {dispersed}");
    }
}

/// A 4x4 image of one texel value.
fn flat_image(name: &str, texel: [u8; 4], color_space: chiaro_scene::ColorSpace) -> chiaro_scene::Image {
    chiaro_scene::Image {
        name: name.into(),
        width: 4,
        height: 4,
        rgba8: texel.repeat(16),
        file_mips: Vec::new(),
        basis_source: None,
        color_space,
    }
}

#[test]
fn extension_textures_are_read_from_their_channels() {
    // Each case: a factor given by the factor alone, and the same value given by a
    // factor of 1 times a texture holding it in the slot's channel (sRGB-encoded in the
    // colour slots) and something else in every other channel. The two must render alike.
    use chiaro_scene::{ColorSpace, LayerTexture, TextureRef};
    let to_light = Vec3::new(-0.4, 0.5, 1.0).normalize();
    let lights = vec![sun(-to_light, 3.0), sun(Vec3::NEG_Z, 1.0)];
    type Case = (MaterialLayers, MaterialLayers, LayerTexture, [u8; 4], ColorSpace);
    let half = 128.0 / 255.0;
    let cases: Vec<Case> = vec![
        (
            MaterialLayers { clearcoat: half, clearcoat_roughness: 0.1, ..Default::default() },
            MaterialLayers { clearcoat: 1.0, clearcoat_roughness: 0.1, ..Default::default() },
            LayerTexture::Clearcoat,
            [128, 0, 255, 0],
            ColorSpace::Linear,
        ),
        (
            MaterialLayers { clearcoat: 1.0, clearcoat_roughness: 0.4 * half, ..Default::default() },
            MaterialLayers { clearcoat: 1.0, clearcoat_roughness: 0.4, ..Default::default() },
            LayerTexture::ClearcoatRoughness,
            [0, 128, 255, 0],
            ColorSpace::Linear,
        ),
        (
            MaterialLayers { specular: half, ..Default::default() },
            MaterialLayers::default(),
            LayerTexture::Specular,
            [0, 0, 0, 128],
            ColorSpace::Linear,
        ),
        (
            // sRGB 188 is linear 0.5029.
            MaterialLayers { sheen_color: Vec3::splat(0.5029), sheen_roughness: 0.5, ..Default::default() },
            MaterialLayers { sheen_color: Vec3::ONE, sheen_roughness: 0.5, ..Default::default() },
            LayerTexture::SheenColor,
            [188, 188, 188, 0],
            ColorSpace::Srgb,
        ),
        (
            MaterialLayers { sheen_color: Vec3::ONE, sheen_roughness: half, ..Default::default() },
            MaterialLayers { sheen_color: Vec3::ONE, sheen_roughness: 1.0, ..Default::default() },
            LayerTexture::SheenRoughness,
            [255, 0, 0, 128],
            ColorSpace::Linear,
        ),
    ];
    let mut renderer = renderer();
    for (by_factor, by_texture, slot, texel, color_space) in cases {
        let reference = sphere_scene(Vec3::new(0.3, 0.2, 0.1), 0.0, 0.6, by_factor, lights.clone());
        let mut textured = sphere_scene(Vec3::new(0.3, 0.2, 0.1), 0.0, 0.6, by_texture, lights.clone());
        textured.images.push(flat_image("slot", texel, color_space));
        textured.materials[0].layers.textures[slot.index()] = Some(TextureRef {
            image: textured.images.len() - 1,
            sampler: Default::default(),
            tex_coord: 0,
            transform: Default::default(),
        });
        for path in [RenderPath::Forward, RenderPath::Deferred] {
            let a = sphere_pixels(&frame(&mut renderer, &reference, &settings(path)), &reference);
            let b = sphere_pixels(&frame(&mut renderer, &textured, &settings(path)), &textured);
            let mean_error: f32 = a
                .iter()
                .zip(&b)
                .map(|(a, b)| (a.radiance - b.radiance).abs().max_element() / (luminance(a.radiance) + 0.01))
                .sum::<f32>()
                / a.len() as f32;
            assert!(mean_error < 0.01, "{slot:?} on {path:?}: factor and texture differ by {mean_error}");
        }
    }
}
