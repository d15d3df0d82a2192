//! Files the ecosystem's tools compressed (tests/assets/ShadowsSpot/encoded; its
//! PROVENANCE.txt names the commands) load as their plain original within the codec's
//! quantisation: every triangle of the original is there, its corners moved by at most
//! what the position grid allows (Draco: half a step of its 14-bit grid over the
//! primitive; gltf-transform's meshopt, which also rescales the node, one step), its
//! normals turned by at most what the octahedral normals allow (Draco 10 bits a component:
//! a quarter degree; meshopt 8 bits: one and a half, Cigolle et al. 2014 measure 1.4).

use crate::gltf_import::load_gltf;
use crate::types::{Primitive, Scene};
use glam::{Mat3, Mat4, Vec3};
use std::path::Path;

fn asset(path: &str) -> Scene {
    let root = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../../tests/assets/ShadowsSpot"));
    load_gltf(&root.join(path)).unwrap_or_else(|e| panic!("{e}"))
}

/// The largest distance, over the original's triangles, to the closest decoded triangle
/// (corner by corner, in any rotation, since encoders may start a triangle anywhere),
/// and the largest normal turn at those corners, in radians.
/// Both primitives are placed by their instance's transform first: quantisers may move
/// the mesh into the grid's space and the node by the inverse.
fn worst_triangle_error(original: (&Primitive, Mat4), decoded: (&Primitive, Mat4)) -> (f32, f32) {
    let corners = |(p, world): (&Primitive, Mat4), t: &[u32]| -> [(Vec3, Vec3); 3] {
        let normal_matrix = Mat3::from_mat4(world).inverse().transpose();
        std::array::from_fn(|k| {
            let v = t[k] as usize;
            (world.transform_point3(p.positions[v]), (normal_matrix * p.normals[v]).normalize())
        })
    };
    let decoded: Vec<[(Vec3, Vec3); 3]> = decoded.0.indices.chunks_exact(3).map(|t| corners(decoded, t)).collect();
    let (mut worst_distance, mut worst_turn) = (0.0f32, 0.0f32);
    for t in original.0.indices.chunks_exact(3) {
        let o = corners(original, t);
        let (distance, turn) = decoded
            .iter()
            .flat_map(|d| (0..3).map(move |r| [d[r], d[(r + 1) % 3], d[(r + 2) % 3]]))
            .map(|d| {
                let distance = (0..3).map(|k| (d[k].0 - o[k].0).abs().max_element()).fold(0.0, f32::max);
                let turn = (0..3).map(|k| d[k].1.angle_between(o[k].1)).fold(0.0, f32::max);
                (distance, turn)
            })
            .min_by(|a, b| a.0.total_cmp(&b.0))
            .expect("the decoded primitive has triangles");
        worst_distance = worst_distance.max(distance);
        worst_turn = worst_turn.max(turn);
    }
    (worst_distance, worst_turn)
}

#[test]
fn draco_and_meshopt_files_load_as_their_original_within_the_quantisation() {
    let original = asset("glTF/shadows-spot.gltf");
    // (file, corner error bound in quantisation steps, normal error bound in degrees)
    for (file, steps, degrees) in [
        ("encoded/shadows-spot-draco-edgebreaker.glb", 0.5, 0.25),
        ("encoded/shadows-spot-draco-sequential.glb", 0.5, 0.25),
        ("encoded/shadows-spot-meshopt.glb", 1.0, 1.5),
    ] {
        let decoded = asset(file);
        assert_eq!(decoded.meshes.len(), original.meshes.len(), "{file}");
        assert_eq!(decoded.lights.len(), original.lights.len(), "{file}");
        assert_eq!(decoded.instances.len(), original.instances.len(), "{file}");
        for (oi, di) in original.instances.iter().zip(&decoded.instances) {
            let m = oi.mesh;
            let (om, dm) = (&original.meshes[oi.mesh], &decoded.meshes[di.mesh]);
            for (o, d) in om.primitives.iter().zip(&dm.primitives) {
                assert_eq!(o.indices.len(), d.indices.len(), "{file}: mesh {m}");
                assert_eq!(o.material, d.material, "{file}: mesh {m}");
                // Both encoders quantise positions to 14 bits over the primitive's bounds.
                let world_bounds = o.bounds.transformed(&oi.world_from_local);
                let step = world_bounds.size().max_element() / ((1u32 << 14) - 1) as f32;
                let (distance, turn) = worst_triangle_error((o, oi.world_from_local), (d, di.world_from_local));
                println!(
                    "{file} mesh {m}: corners within {:.2} steps, normals within {:.3} deg",
                    distance / step,
                    turn.to_degrees()
                );
                // f32 rounding of the dequantised values, a thousandth of a step.
                assert!(distance <= steps * step * 1.001, "{file}: mesh {m}: a corner moved {distance} m");
                assert!(turn.to_degrees() < degrees, "{file}: mesh {m}: a normal turned {} deg", turn.to_degrees());
            }
        }
    }
}

/// The mean and largest difference, in 8-bit levels, between two RGBA8 images' colours.
fn texel_error(a: &[u8], b: &[u8]) -> (f64, u8) {
    let differences: Vec<u8> =
        a.chunks_exact(4).zip(b.chunks_exact(4)).flat_map(|(p, q)| (0..3).map(move |c| p[c].abs_diff(q[c]))).collect();
    let mean = differences.iter().map(|&d| f64::from(d)).sum::<f64>() / differences.len() as f64;
    (mean, differences.iter().copied().max().unwrap_or(0))
}

#[test]
fn ktx2_textures_load_as_their_png_within_the_codecs_error_with_the_files_mips() {
    let root = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../../tests/assets/TexturedKtx2"));
    let load = |file: &str| load_gltf(&root.join(file)).unwrap_or_else(|e| panic!("{e}"));
    let png = load("textured-png.gltf");
    // (file, mean error bound, in 8-bit levels): ETC1S is the lossier codec.
    for (file, mean_bound) in [("textured-etc1s.gltf", 6.0), ("textured-uastc.gltf", 1.0)] {
        let ktx2 = load(file);
        assert_eq!(ktx2.images.len(), 1, "{file}: only the KTX2 image is read, not the fallback");
        let (a, b) = (&png.images[0], &ktx2.images[0]);
        assert_eq!((a.width, a.height), (b.width, b.height), "{file}");
        assert_eq!(b.color_space, crate::types::ColorSpace::Srgb, "{file}: a base colour texture is sRGB");
        let (mean, worst) = texel_error(&a.rgba8, &b.rgba8);
        println!("{file}: texels off by {mean:.2} levels on average, {worst} at worst");
        assert!(mean < mean_bound, "{file}: mean error {mean}");
        // 128 x 128 down to 1 x 1: the file's seven smaller levels, each half the last.
        assert_eq!(b.file_mips.len(), 7, "{file}");
        for (k, level) in b.file_mips.iter().enumerate() {
            let side = 128 >> (k + 1);
            assert_eq!(level.len(), side * side * 4, "{file}: level {}", k + 1);
        }
    }
}

/// The Draco files with bytes of their binary chunk (all Draco streams) flipped, cut or
/// repeated: every mutant loads or is refused, none panics or aborts.
#[test]
fn mutated_draco_streams_are_refused_or_decoded_never_a_panic() {
    let mut random = super::xorshift(0x9e37_79b9_7f4a_7c15);
    let mut next = move || random() as usize;
    let (mut loaded, mut refused) = (0, 0);
    for file in ["shadows-spot-draco-edgebreaker.glb", "shadows-spot-draco-sequential.glb"] {
        let path = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../../tests/assets/ShadowsSpot/encoded")).join(file);
        let original = std::fs::read(&path).unwrap();
        let (json, _) = crate::gltf_import::glb::split_glb(&original).unwrap();
        // The BIN chunk's bytes start after the JSON chunk and the BIN chunk's header.
        let bin_start = 12 + 8 + json.len().next_multiple_of(4) + 8;
        for _ in 0..3000 {
            let mut mutant = original.clone();
            let span = mutant.len() - bin_start;
            match next() % 3 {
                0 => {
                    // Zero a run, as a truncated stream padded out would read.
                    let at = bin_start + next() % span;
                    let end = (at + 1 + next() % 256).min(mutant.len());
                    mutant[at..end].fill(0);
                }
                _ => {
                    for _ in 0..1 + next() % 8 {
                        let at = bin_start + next() % span;
                        mutant[at] ^= 1 << (next() % 8);
                    }
                }
            }
            match crate::gltf_import::load_gltf_bytes(&path, &mutant) {
                Ok(_) => loaded += 1,
                Err(_) => refused += 1,
            }
        }
    }
    println!("{loaded} mutants loaded, {refused} refused");
    assert!(refused > 100, "{loaded} loaded, {refused} refused");
}
