//! The baker end to end on small scenes: energy conservation in a closed box,
//! determinism for a seed, cancelling, and bake directories that know their scene.

mod common;

use chiaro_bake::bake::probe_layout;
use chiaro_bake::{BakeError, Silent, apply_bake_dir, bake, read_bake_dir, write_bake_dir};
use chiaro_scene::{CastShadows, LightMode, Material, Mesh, MeshInstance, Scene, Settings, shapes};
use chiaro_testkit::{add_box, floor_scene, point_light};
use glam::{Mat4, Vec3, Vec4};
use std::f32::consts::PI;
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;

/// A closed box of `size`, its faces turned to face inwards, base colour `rho`.
fn room(size: f32, rho: f32) -> Scene {
    let mut walls = shapes::cuboid(Vec3::splat(size));
    for tri in walls.indices.chunks_exact_mut(3) {
        tri.swap(1, 2);
    }
    for n in &mut walls.normals {
        *n = -*n;
    }
    walls.material = Some(0);
    Scene {
        meshes: vec![Mesh::of_triangles("room".into(), vec![walls])],
        instances: vec![MeshInstance {
            mesh: 0,
            node: 0,
            name: "room".into(),
            world_from_local: Mat4::IDENTITY,
            cast_shadows: CastShadows::On,
            receive_shadows: true,
            is_static: true,
            lightmap: None,
            gpu_instance: None,
            label: 0,
        }],
        materials: vec![Material {
            name: "grey".into(),
            base_color: Vec4::new(rho, rho, rho, 1.0),
            metallic: 0.0,
            roughness: 1.0,
            ..Material::default()
        }],
        ..Scene::default()
    }
}

fn baked_point(position: Vec3, intensity: f32) -> chiaro_scene::Light {
    let mut light = point_light(position, intensity, Some(1.0e4));
    light.mode = LightMode::Baked;
    light
}

fn settings(samples: u32, bounces: u32, texels_per_metre: f32) -> Settings {
    let mut s = Settings::default();
    s.render.ambient = [0.0; 3];
    s.bake.samples = Some(samples);
    s.bake.bounces = bounces;
    s.bake.texels_per_metre = texels_per_metre;
    s.bake.probe_samples = Some(64);
    // The tracer's energy alone: the denoiser is measured on its own below.
    s.bake.denoise = false;
    s
}

/// Coverage-weighted mean irradiance over all lightmaps, and the covered area in m².
fn mean_irradiance(result: &chiaro_bake::BakeResult, texels_per_metre: f32) -> (f32, f32) {
    let (mut sum, mut weight) = (0.0f64, 0.0f64);
    for map in &result.lighting.lightmaps {
        for t in &map.texels {
            sum += t[0] as f64 * t[3] as f64;
            weight += t[3] as f64;
        }
    }
    ((sum / weight) as f32, (weight / (texels_per_metre as f64).powi(2)) as f32)
}

/// What a rough grey wall of base colour `rho` reflects of the light it receives: its
/// hemispherical albedo, both lobes (the diffuse share alone, (1 - F0) rho, is short of
/// it by the specular lobe's).
fn reflectance(rho: f32) -> f32 {
    chiaro_math::environment::hemispherical_albedo(Vec3::splat(rho), 0.0, 1.0, 256, 4096).x
}

#[test]
fn a_closed_room_absorbs_every_watt_wherever_the_light_is() {
    let (size, rho, intensity) = (2.0, 0.5, 10.0);
    let area = 6.0 * size * size;
    let expected = 4.0 * PI * intensity / (area * (1.0 - reflectance(rho)));
    for position in [Vec3::ZERO, Vec3::new(0.55, -0.4, 0.25)] {
        let mut scene = room(size, rho);
        scene.lights.push(baked_point(position, intensity));
        // rho^25 of the light is left after 24 bounces: 3e-8.
        let s = settings(16, 24, 8.0);
        let result = bake(&scene, &s, &Silent, &AtomicBool::new(false)).unwrap();
        let (mean, covered) = mean_irradiance(&result, 8.0);
        println!("light at {position}: mean irradiance {mean:.4} lux, expected {expected:.4}; covered {covered:.3} m²");
        assert!((covered - area).abs() / area < 0.01, "covered {covered} m² of {area}");
        assert!((mean - expected).abs() / expected < 0.01, "{mean} vs {expected}");
        // Direct light alone: every watt lands once, 4 pi I / A.
        let direct = bake(&scene, &settings(16, 0, 8.0), &Silent, &AtomicBool::new(false)).unwrap();
        let (mean_direct, _) = mean_irradiance(&direct, 8.0);
        let expected_direct = 4.0 * PI * intensity / area;
        println!("  direct only: {mean_direct:.4}, expected {expected_direct:.4}");
        assert!((mean_direct - expected_direct).abs() / expected_direct < 0.01);
    }
}

#[test]
fn glowing_walls_light_a_closed_room_by_pi_radiance_per_bounce() {
    // Every direction from a wall sees another wall of radiance L: E = pi L, and each
    // bounce adds r times the last (r the reflectance), so E = pi L (1 - r^(B + 1)) / (1 - r). Aiming
    // at the glowing walls (weighed against the bounces by MIS) adds noise where bounces
    // alone had none, so 64 samples.
    for (rho, bounces) in [(0.0, 0), (0.5, 1), (0.5, 20)] {
        let mut scene = room(2.0, rho);
        scene.materials[0].emissive = Vec3::ONE;
        let result = bake(&scene, &settings(64, bounces, 8.0), &Silent, &AtomicBool::new(false)).unwrap();
        let (mean, _) = mean_irradiance(&result, 8.0);
        let r = reflectance(rho);
        let expected = PI * (1.0 - r.powi(bounces as i32 + 1)) / (1.0 - r);
        println!("rho {rho}, {bounces} bounces: {mean:.5}, expected {expected:.5}");
        assert!((mean - expected).abs() / expected < 0.002, "{mean} vs {expected}");
    }
}

#[test]
fn denoising_keeps_a_glowing_rooms_energy() {
    // The filter's weights depend on the light (it keeps bright texels apart), which can
    // shift the mean; by no more than a fraction of the noise it removes.
    let mut scene = room(2.0, 0.5);
    scene.materials[0].emissive = Vec3::ONE;
    let mut s = settings(64, 20, 8.0);
    let traced = bake(&scene, &s, &Silent, &AtomicBool::new(false)).unwrap();
    s.bake.denoise = true;
    let denoised = bake(&scene, &s, &Silent, &AtomicBool::new(false)).unwrap();
    let ((before, _), (after, _)) = (mean_irradiance(&traced, 8.0), mean_irradiance(&denoised, 8.0));
    println!(
        "mean irradiance {before:.5} traced, {after:.5} denoised; noise {:.2}% -> {:.2}%",
        100.0 * denoised.stats.noise_traced,
        100.0 * denoised.stats.noise
    );
    assert!((after - before).abs() / before < 0.003, "{before} -> {after}");
    assert!(denoised.stats.noise < denoised.stats.noise_traced / 2.0);
}

#[test]
fn a_small_glowing_square_lights_the_floor_as_the_formula_says_texel_by_texel() {
    // A 0.2 m square of radiance 100 facing down 1 m above the floor: E = L A h^2 / r^4
    // under it (the square is small beside r). Bounces alone would hit it with 1 path in
    // 80 and leave most texels black at 64 samples; aiming at it, weighed by MIS, gets
    // every texel right.
    let (side, height, radiance) = (0.2f32, 1.0f32, 100.0f32);
    let mut scene = floor_scene(4.0, Vec3::new(0.0, 4.0, 3.0), vec![]);
    let mut square = shapes::plane(side, 1);
    square.material = Some(1);
    scene.materials.push(Material {
        name: "glow".into(),
        base_color: Vec4::new(0.0, 0.0, 0.0, 1.0),
        emissive: Vec3::splat(radiance),
        ..Material::default()
    });
    scene.meshes.push(Mesh::of_triangles("square".into(), vec![square]));
    scene.instances.push(MeshInstance {
        mesh: 1,
        node: 1,
        name: "square".into(),
        // Turned over so that its front faces the floor.
        world_from_local: Mat4::from_translation(Vec3::Y * height) * Mat4::from_rotation_x(PI),
        cast_shadows: CastShadows::Off,
        receive_shadows: false,
        is_static: true,
        lightmap: None,
        gpu_instance: None,
        label: 0,
    });
    let result = bake(&scene, &settings(64, 1, 16.0), &Silent, &AtomicBool::new(false)).unwrap();
    let layout = result.layout.instances.iter().find(|l| l.instance == 0).unwrap();
    let size = result.layout.size;
    let map = &result.lighting.lightmaps[layout.layer as usize];
    let mut errors = Vec::new();
    for t in &layout.triangles {
        // Texel centres inside this triangle, in world space through the barycentrics.
        let p = &scene.meshes[0].primitives[t.primitive as usize];
        let corners = [0, 1, 2].map(|k| p.positions[p.indices[3 * t.triangle as usize + k] as usize]);
        for y in 0..size {
            for x in 0..size {
                let q = glam::Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
                let Some(w) = chiaro_bake::raster::barycentric(&t.corners, q).filter(chiaro_bake::raster::inside)
                else {
                    continue;
                };
                let texel = map.texels[(y * size + x) as usize];
                let world = corners[0] * w[0] + corners[1] * w[1] + corners[2] * w[2];
                let r2 = world.x * world.x + world.z * world.z + height * height;
                if texel[3] < 0.999 || r2.sqrt() > 1.25 {
                    continue;
                }
                let expected = radiance * side * side * height * height / (r2 * r2);
                errors.push((texel[0] - expected).abs() / expected);
            }
        }
    }
    errors.sort_by(f32::total_cmp);
    let (median, p90) = (errors[errors.len() / 2], errors[errors.len() * 9 / 10]);
    println!("{} texels: median error {:.2}%, p90 {:.2}%", errors.len(), 100.0 * median, 100.0 * p90);
    assert!(errors.len() > 100);
    assert!(median < 0.03 && p90 < 0.08, "median {median}, p90 {p90}");
}

fn small_scene() -> Scene {
    let mut scene = floor_scene(4.0, Vec3::new(0.0, 4.0, 3.0), vec![baked_point(Vec3::new(0.3, 1.5, 0.2), 5.0)]);
    add_box(&mut scene, Vec3::new(0.0, 0.4, 0.0), Vec3::splat(0.8), 0.3, CastShadows::On);
    scene
}

#[test]
fn the_same_seed_bakes_the_same_bits_and_another_seed_other_noise() {
    let scene = small_scene();
    let mut s = settings(4, 2, 4.0);
    let run = |s: &Settings| bake(&scene, s, &Silent, &AtomicBool::new(false)).unwrap();
    let (a, b) = (run(&s), run(&s));
    assert_eq!(a.lighting, b.lighting);
    assert_eq!(a.layout, b.layout);
    s.bake.seed = 7;
    let c = run(&s);
    assert_eq!(a.layout, c.layout);
    assert_ne!(a.lighting.lightmaps, c.lighting.lightmaps);
}

#[test]
fn a_cancelled_bake_returns_nothing() {
    let scene = small_scene();
    let e = bake(&scene, &settings(4, 1, 4.0), &Silent, &AtomicBool::new(true));
    assert!(matches!(e, Err(BakeError::Cancelled)));
}

#[test]
fn probes_cover_the_scene_bounds_and_refuse_absurd_counts() {
    let scene = small_scene();
    let (origin, counts) = probe_layout(&scene, 1.0).unwrap().unwrap();
    let bounds = scene.bounds();
    assert_eq!(counts.to_array(), [5, 1, 5]);
    assert!((origin - Vec3::new(-2.0, bounds.min.y + (bounds.max.y - bounds.min.y) / 2.0, -2.0)).length() < 1e-4);
    let e = probe_layout(&scene, 0.001).unwrap_err().to_string();
    assert!(e.contains("bake.probe_spacing"), "{e}");
}

/// ShadowsSpot from the repository's test scenes, copied into `dir` (the tests edit it).
fn spot_scene_copy(dir: &Path) -> PathBuf {
    let source = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/assets/ShadowsSpot/glTF");
    for file in ["shadows-spot.gltf", "shadows-spot.bin"] {
        std::fs::copy(source.join(file), dir.join(file)).unwrap();
    }
    dir.join("shadows-spot.gltf")
}

#[test]
fn a_bake_directory_is_read_back_for_its_scene_and_refused_for_another() {
    let dir = tempfile::tempdir().unwrap();
    let path = spot_scene_copy(dir.path());
    let mut scene = chiaro_scene::load_gltf(&path).unwrap();
    for light in &mut scene.lights {
        light.mode = LightMode::Baked;
    }
    let s = settings(2, 1, 2.0);
    let result = bake(&scene, &s, &Silent, &AtomicBool::new(false)).unwrap();
    let out = chiaro_bake::default_bake_dir(&path);
    assert_eq!(out, dir.path().join("shadows-spot.bake"));
    write_bake_dir(&out, &scene, &s, &result, &AtomicBool::new(false)).unwrap();
    let loaded = read_bake_dir(&out, &scene).unwrap();
    assert_eq!(loaded.lighting.lightmaps.len(), result.lighting.lightmaps.len());
    for (read, baked) in loaded.lighting.lightmaps.iter().zip(&result.lighting.lightmaps) {
        assert_eq!(read, baked, "EXR float32 round trip is exact");
    }
    assert_eq!(loaded.lighting.probes, result.lighting.probes);
    assert_eq!(loaded.placements, result.layout.placements(&scene));
    let mut applied = scene.clone();
    apply_bake_dir(&out, &mut applied).unwrap();
    assert!(applied.baked.is_some());
    assert!(applied.instances.iter().any(|i| i.lightmap.is_some()));

    // The scene's buffer changes by one byte: the bake no longer fits.
    let bin = dir.path().join("shadows-spot.bin");
    let mut bytes = std::fs::read(&bin).unwrap();
    bytes[0] ^= 1;
    std::fs::write(&bin, &bytes).unwrap();
    let e = read_bake_dir(&out, &scene).err().unwrap().to_string();
    assert!(e.contains("another version of the scene"), "{e}");
    let mut untouched = scene.clone();
    assert!(apply_bake_dir(&out, &mut untouched).is_err());
    assert!(untouched.baked.is_none());

    // Broken or hostile numbers in the manifest are refused, never trusted.
    bytes[0] ^= 1;
    std::fs::write(&bin, &bytes).unwrap();
    let manifest = out.join("manifest.json");
    let original = std::fs::read_to_string(&manifest).unwrap();
    let mut doc: serde_json::Value = serde_json::from_str(&original).unwrap();
    doc["probes"]["counts"] = serde_json::json!([4194304, 2097152, 2097152]);
    std::fs::write(&manifest, doc.to_string()).unwrap();
    let e = read_bake_dir(&out, &scene).err().unwrap().to_string();
    assert!(e.contains("probe grid"), "{e}");
    doc["probes"]["counts"] = serde_json::json!([0, 1, 1]);
    std::fs::write(&manifest, doc.to_string()).unwrap();
    assert!(read_bake_dir(&out, &scene).err().unwrap().to_string().contains("probe grid"));
    let mut doc: serde_json::Value = serde_json::from_str(&original).unwrap();
    doc["lightmap_size"] = serde_json::json!(1 << 20);
    std::fs::write(&manifest, doc.to_string()).unwrap();
    assert!(read_bake_dir(&out, &scene).err().unwrap().to_string().contains("atlases"));
    let mut doc: serde_json::Value = serde_json::from_str(&original).unwrap();
    doc["lightmap_size"] = serde_json::json!(doc["lightmap_size"].as_u64().unwrap() * 2);
    std::fs::write(&manifest, doc.to_string()).unwrap();
    assert!(read_bake_dir(&out, &scene).err().unwrap().to_string().contains("as the manifest says"));
    std::fs::write(&manifest, &original).unwrap();
    assert!(read_bake_dir(&out, &scene).is_ok());

    // Another format version is refused with its number.
    let manifest = out.join("manifest.json");
    let text = std::fs::read_to_string(&manifest).unwrap().replace("\"format_version\": 1", "\"format_version\": 99");
    std::fs::write(&manifest, text).unwrap();
    let e = read_bake_dir(&out, &scene).err().unwrap().to_string();
    assert!(e.contains("format version 99"), "{e}");
}

#[test]
fn writing_replaces_an_old_bake_and_an_interrupt_leaves_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let path = spot_scene_copy(dir.path());
    let scene = chiaro_scene::load_gltf(&path).unwrap();
    let s = settings(1, 0, 1.0);
    let result = bake(&scene, &s, &Silent, &AtomicBool::new(false)).unwrap();
    let out = dir.path().join("out.bake");
    write_bake_dir(&out, &scene, &s, &result, &AtomicBool::new(true)).unwrap_err();
    let names = |d: &Path| -> Vec<String> {
        let mut v: Vec<String> =
            std::fs::read_dir(d).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
        v.sort();
        v
    };
    assert_eq!(names(dir.path()), vec!["shadows-spot.bin", "shadows-spot.gltf"]);
    write_bake_dir(&out, &scene, &s, &result, &AtomicBool::new(false)).unwrap();
    std::fs::write(out.join("stale"), b"old").unwrap();
    write_bake_dir(&out, &scene, &s, &result, &AtomicBool::new(false)).unwrap();
    assert!(!out.join("stale").exists());
    assert_eq!(names(dir.path()), vec!["out.bake", "shadows-spot.bin", "shadows-spot.gltf"]);
}

/// Irradiance under a corner of a w x h rect of unit luminance parallel to the receiver
/// at height d: the textbook form factor times pi.
fn corner_rect(w: f32, h: f32, d: f32) -> f32 {
    let (a, b) = (w / d, h / d);
    let (sa, sb) = ((1.0 + a * a).sqrt(), (1.0 + b * b).sqrt());
    0.5 * (a / sa * (b / sa).atan() + b / sb * (a / sb).atan())
}

#[test]
fn a_baked_rect_light_lights_the_floor_as_the_form_factor_says_texel_by_texel() {
    // A 1 x 0.5 m rect of 100 nits 1 m above the floor, facing down, baked.
    let (width, depth, height, nits) = (1.0f32, 0.5f32, 1.0f32, 100.0f32);
    let mut light = chiaro_scene::Light::new(
        chiaro_scene::LightKind::Rect { width, height: depth },
        Vec3::new(0.0, height, 0.0),
        Vec3::NEG_Y,
    );
    light.intensity = nits;
    light.mode = LightMode::Baked;
    let scene = floor_scene(4.0, Vec3::new(0.0, 4.0, 3.0), vec![light.clone()]);
    let result = bake(&scene, &settings(16, 0, 16.0), &Silent, &AtomicBool::new(false)).unwrap();
    let places = common::texel_places(&scene, &result);
    // The rect's local X and Y on the floor (its frame may be rolled).
    let (axis_x, axis_y) = (light.world_from_light.x_axis.truncate(), light.world_from_light.y_axis.truncate());
    let mut errors = Vec::new();
    for (map, layer) in result.lighting.lightmaps.iter().zip(&places) {
        for (texel, place) in map.texels.iter().zip(layer) {
            let Some((_, 0, p)) = *place else { continue };
            if texel[3] < 0.999 || p.length() > 1.5 {
                continue;
            }
            // Superpose the four rects that meet under the receiver.
            let (u, v) = (p.dot(axis_x), p.dot(axis_y));
            let (x0, x1) = (width / 2.0 + u, width / 2.0 - u);
            let (y0, y1) = (depth / 2.0 + v, depth / 2.0 - v);
            let part = |a: f32, b: f32| a.signum() * b.signum() * corner_rect(a.abs(), b.abs(), height);
            let expected = nits * (part(x0, y0) + part(x1, y0) + part(x0, y1) + part(x1, y1));
            errors.push((texel[0] - expected).abs() / expected);
        }
    }
    errors.sort_by(f32::total_cmp);
    let (median, worst) = (errors[errors.len() / 2], errors[errors.len() - 1]);
    println!("{} texels: median error {:.3}%, worst {:.3}%", errors.len(), 100.0 * median, 100.0 * worst);
    assert!(errors.len() > 500);
    assert!(median < 0.005 && worst < 0.02, "median {median}, worst {worst}");
}
