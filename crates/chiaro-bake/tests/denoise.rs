//! The denoised default bake against a bake with 64 times its samples and no denoising,
//! on a scene with colour bleeding (a red and a green box on a white floor) and contact
//! shadows (the boxes stand on the floor): closer than the noisy bake everywhere, and
//! never blended across a chart border or into a contact shadow.

mod common;

use chiaro_bake::convergence::{DARK_SHARE, quantile, texel_errors};
use chiaro_bake::{BakeResult, Silent, bake};
use chiaro_scene::{CastShadows, Light, LightKind, LightMode, Material, Mesh, MeshInstance, Scene, Settings, shapes};
use chiaro_testkit::floor_scene;
use common::texel_places;
use glam::{Mat4, Vec3, Vec4};
use std::sync::atomic::AtomicBool;

/// Adds a box of `size` standing on the floor at `(x, z)`, of a material of its own.
fn add_coloured_box(scene: &mut Scene, x: f32, z: f32, size: Vec3, colour: Vec3) {
    scene.materials.push(Material {
        name: format!("{colour}"),
        base_color: colour.extend(1.0),
        metallic: 0.0,
        roughness: 1.0,
        ..Material::default()
    });
    let mut cube = shapes::cuboid(Vec3::ONE);
    cube.material = Some(scene.materials.len() - 1);
    scene.meshes.push(Mesh::of_triangles(format!("box {colour}"), vec![cube]));
    scene.instances.push(MeshInstance {
        mesh: scene.meshes.len() - 1,
        node: 100 + scene.instances.len(),
        name: format!("box {colour}"),
        world_from_local: Mat4::from_scale_rotation_translation(
            size,
            glam::Quat::IDENTITY,
            Vec3::new(x, size.y / 2.0, z),
        ),
        cast_shadows: CastShadows::On,
        receive_shadows: true,
        is_static: true,
        lightmap: None,
        gpu_instance: None,
        label: 0,
    });
}

fn scene(mode: LightMode) -> Scene {
    let mut light = Light::new(
        LightKind::Spot { inner_cone_rad: 0.6, outer_cone_rad: 0.8 },
        Vec3::new(0.3, 3.0, 1.2),
        Vec3::new(-0.1, -1.0, -0.35),
    );
    light.intensity = 60.0;
    light.range = Some(12.0);
    light.mode = mode;
    let mut scene = floor_scene(4.0, Vec3::new(0.0, 4.0, 3.0), vec![light]);
    scene.materials[0].base_color = Vec4::new(0.8, 0.8, 0.8, 1.0);
    add_coloured_box(&mut scene, -0.6, -0.2, Vec3::new(0.8, 0.8, 0.8), Vec3::new(0.9, 0.1, 0.1));
    add_coloured_box(&mut scene, 0.8, -0.5, Vec3::new(0.5, 1.2, 0.5), Vec3::new(0.1, 0.9, 0.1));
    scene
}

fn settings(samples: u32, denoise: bool) -> Settings {
    let mut s = Settings::default();
    s.render.ambient = [0.0; 3];
    s.bake.samples = Some(samples);
    s.bake.denoise = denoise;
    s.bake.probe_spacing = 4.0;
    s
}

/// The reference's samples over the default's. The figure is 16x, whose own noise
/// (a quarter of the default's) would hide most of what denoising does: the tests use
/// 64x, `examples/bake_error.rs` prints both.
const REFERENCE_FACTOR: u32 = 64;

fn run(scene: &Scene, s: &Settings) -> BakeResult {
    bake(scene, s, &Silent, &AtomicBool::new(false)).unwrap()
}

/// The default bake denoised, the same traced bake without denoising, and the reference.
struct Bakes {
    denoised: BakeResult,
    noisy: BakeResult,
    reference: BakeResult,
}

fn bakes(mode: LightMode) -> Bakes {
    let scene = scene(mode);
    let samples = Settings::default().bake.texel_samples();
    let b = Bakes {
        denoised: run(&scene, &settings(samples, true)),
        noisy: run(&scene, &settings(samples, false)),
        reference: run(&scene, &settings(REFERENCE_FACTOR * samples, false)),
    };
    println!(
        "{mode:?}: bake times {:.2} s denoised, {:.2} s not, reference {:.2} s",
        b.denoised.stats.seconds, b.noisy.stats.seconds, b.reference.stats.seconds
    );
    b
}

#[test]
fn the_denoised_default_bake_is_closer_to_64_times_the_samples_than_the_noisy_one() {
    // Mixed light: the lightmap holds bounced light alone, all of it noisy.
    let b = bakes(LightMode::Mixed);
    let noisy = texel_errors(&b.noisy.lighting.lightmaps, &b.reference.lighting.lightmaps);
    let denoised = texel_errors(&b.denoised.lighting.lightmaps, &b.reference.lighting.lightmaps);
    let (nm, n90) = (quantile(&noisy, 0.5), quantile(&noisy, 0.9));
    let (dm, d90) = (quantile(&denoised, 0.5), quantile(&denoised, 0.9));
    println!(
        "{} texels; noisy: median {:.1}%, p90 {:.1}%; denoised: median {:.1}%, p90 {:.1}%; estimated {:.1}% -> {:.1}%",
        noisy.len(),
        100.0 * nm,
        100.0 * n90,
        100.0 * dm,
        100.0 * d90,
        100.0 * b.denoised.stats.noise_traced,
        100.0 * b.denoised.stats.noise
    );
    assert!(noisy.len() > 500);
    assert!(dm < nm / 2.5 && d90 < n90 / 1.8, "median {nm} -> {dm}, p90 {n90} -> {d90}");
    // The estimate of the noise as traced is about what was measured; after denoising it
    // sees the noise go down (what it cannot see is the filter's bias).
    let (traced, left) = (b.denoised.stats.noise_traced, b.denoised.stats.noise);
    assert!((traced / nm - 1.0).abs() < 0.5, "estimated {traced}, measured {nm}");
    assert_eq!(b.noisy.stats.noise, b.noisy.stats.noise_traced);
    assert!(left < traced / 2.0, "estimated {traced} -> {left}");
}

fn luminance(t: &[f32; 4]) -> f32 {
    chiaro_math::tonemap::luminance(Vec3::new(t[0], t[1], t[2]))
}

/// The relative errors against the reference of the texels `pick(atlas, texel)` chooses,
/// wholly covered and not dark (as `texel_errors` counts them).
fn errors_where(b: &Bakes, result: &BakeResult, pick: &dyn Fn(usize, usize) -> bool) -> Vec<f32> {
    let all: Vec<f32> = b.reference.lighting.lightmaps.iter().flat_map(|m| m.texels.iter().map(luminance)).collect();
    let dark = DARK_SHARE * all.iter().sum::<f32>() / all.len() as f32;
    let mut e = Vec::new();
    for (layer, (test, reference)) in result.lighting.lightmaps.iter().zip(&b.reference.lighting.lightmaps).enumerate()
    {
        let (test, reference) = (&test.texels, &reference.texels);
        e.extend(
            (0..test.len())
                .filter(|&i| pick(layer, i) && reference[i][3] >= 0.999 && luminance(&reference[i]) > dark)
                .map(|i| (luminance(&test[i]) - luminance(&reference[i])).abs() / luminance(&reference[i])),
        );
    }
    e.sort_by(f32::total_cmp);
    e
}

#[test]
fn denoising_never_blends_across_a_chart_border_or_into_a_contact_shadow() {
    // Baked light: direct light and its sharp shadows in the lightmap, bounced light
    // around them.
    let b = bakes(LightMode::Baked);
    let scene = scene(LightMode::Baked);
    let places = texel_places(&scene, &b.reference);
    let size = b.reference.layout.size as i64;
    // Texels with a texel of another chart within 8 texels (covered texels of two charts
    // lie at least 5 apart, across the gutters): a blur across would reach them first.
    let at_border = |layer: usize, i: usize| -> bool {
        let places = &places[layer];
        let Some((chart, _, _)) = places[i] else { return false };
        let (x, y) = (i as i64 % size, i as i64 / size);
        (-8..=8i64).any(|dy| {
            (-8..=8i64).any(|dx| {
                let (nx, ny) = (x + dx, y + dy);
                (0..size).contains(&nx)
                    && (0..size).contains(&ny)
                    && places[(ny * size + nx) as usize].is_some_and(|(c, _, _)| c != chart)
            })
        })
    };
    // Floor texels (instance 0) within 0.12 m of a box's foot: the contact shadows.
    let boxes: Vec<(Vec3, Vec3)> = scene.instances[1..]
        .iter()
        .map(|i| {
            let (scale, _, centre) = i.world_from_local.to_scale_rotation_translation();
            (centre - scale / 2.0, centre + scale / 2.0)
        })
        .collect();
    let in_contact = |layer: usize, i: usize| -> bool {
        let Some((_, 0, p)) = places[layer][i] else { return false };
        boxes.iter().any(|(min, max)| {
            let outside = (p.x - max.x).max(min.x - p.x).max(p.z - max.z).max(min.z - p.z);
            (0.0..0.12).contains(&outside)
        })
    };
    let everywhere = errors_where(&b, &b.denoised, &|_, _| true);
    let noisy = errors_where(&b, &b.noisy, &at_border);
    let denoised = errors_where(&b, &b.denoised, &at_border);
    let (nm, n90, dm, d90) =
        (quantile(&noisy, 0.5), quantile(&noisy, 0.9), quantile(&denoised, 0.5), quantile(&denoised, 0.9));
    println!(
        "chart borders: {} texels; noisy median {:.1}% p90 {:.1}%, denoised median {:.1}% p90 {:.1}% (all texels: \
         median {:.1}%)",
        noisy.len(),
        100.0 * nm,
        100.0 * n90,
        100.0 * dm,
        100.0 * d90,
        100.0 * quantile(&everywhere, 0.5),
    );
    assert!(noisy.len() > 100, "{} texels", noisy.len());
    // Light blended from a chart across the gutter would leave these texels further from
    // the reference than the noise did.
    assert!(dm <= nm && d90 <= n90 && d90 < 0.15, "median {nm} -> {dm}, p90 {n90} -> {d90}");

    // Across the contact shadows, lit floor meets shadowed floor within a texel or two:
    // denoising moves no texel further from the reference than a few percent of the lit
    // level beyond where the traced bake already was (a blur across the edge would carry
    // half of it into the shadow).
    let band: Vec<(f32, f32, f32)> = (0..places.len())
        .flat_map(|layer| (0..places[layer].len()).map(move |i| (layer, i)))
        .filter(|&(layer, i)| in_contact(layer, i) && b.reference.lighting.lightmaps[layer].texels[i][3] >= 0.999)
        .map(|(layer, i)| {
            let texel = |r: &BakeResult| luminance(&r.lighting.lightmaps[layer].texels[i]);
            (texel(&b.reference), texel(&b.noisy), texel(&b.denoised))
        })
        .collect();
    let lit = band.iter().map(|t| t.0).fold(0.0, f32::max);
    let shadowed = band.iter().filter(|t| t.0 < 0.1 * lit).count();
    let worst = band.iter().map(|(r, n, d)| (d - r).abs() - (n - r).abs()).fold(0.0, f32::max);
    println!(
        "contact shadows: {} texels, {shadowed} in shadow; lit level {lit:.3}, largest move away \
         from the reference {worst:.4}",
        band.len()
    );
    assert!(shadowed >= 10 && band.len() - shadowed >= 10, "the band crosses the shadow's edge");
    assert!(worst < 0.05 * lit, "{worst} against a lit level of {lit}");
}

#[test]
fn probes_are_smooth_at_the_default_samples() {
    // Probes are not filtered: their default stratified directions, projected on nine
    // spherical harmonics, must already agree between two seeds (256 directions left
    // them 9.9% apart at the median, 38.7% at the 90th percentile).
    let scene = scene(LightMode::Mixed);
    let mut s = settings(4, false);
    s.bake.probe_spacing = 0.6;
    let grid = |seed: u64| {
        let mut s = s.clone();
        s.bake.seed = seed;
        run(&scene, &s).lighting.probes.unwrap()
    };
    let (a, b) = (grid(0), grid(1));
    let lum = chiaro_math::tonemap::luminance;
    let sides = [Vec3::X, Vec3::NEG_X, Vec3::Y, Vec3::NEG_Y, Vec3::Z, Vec3::NEG_Z];
    let pairs: Vec<(f32, f32)> = a
        .probes
        .iter()
        .zip(&b.probes)
        .flat_map(|(pa, pb)| sides.map(|n| (lum(pa.irradiance(n)), lum(pb.irradiance(n)))))
        .collect();
    let mean = pairs.iter().map(|(x, y)| x + y).sum::<f32>() / (2 * pairs.len()) as f32;
    let mut differences: Vec<f32> =
        pairs.iter().filter(|(x, y)| x + y > 0.02 * mean).map(|(x, y)| (x - y).abs() / ((x + y) / 2.0)).collect();
    differences.sort_by(f32::total_cmp);
    let (median, p90) = (quantile(&differences, 0.5), quantile(&differences, 0.9));
    println!(
        "{} probes, {} lit sides: seed 0 against seed 1 median {:.1}%, p90 {:.1}%",
        a.probes.len(),
        differences.len(),
        100.0 * median,
        100.0 * p90
    );
    assert!(differences.len() > 200);
    assert!(median < 0.03 && p90 < 0.08, "median {median}, p90 {p90}");
}
