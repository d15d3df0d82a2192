//! Files the ecosystem's tools compressed (tests/assets/ShadowsSpot/encoded, made with
//! gltf-transform's draco and meshopt commands as its PROVENANCE.txt says) render as their
//! plain original, shadows included, within what the codecs' quantisation moves: a mean
//! FLIP under 0.005 and fewer than a thousandth of the pixels off by more than 8 levels
//! (measured: 0.0005 and 6 pixels for Draco's edgebreaker, nothing for the others).

mod common;

use chiaro_scene::load_gltf;
use common::*;
use std::path::Path;

const SIZE: u32 = 128;

fn rendered(file: &str) -> Vec<u8> {
    let root = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../../tests/assets/ShadowsSpot"));
    let scene = load_gltf(&root.join(file)).unwrap_or_else(|e| panic!("{e}"));
    ldr_rgb(&render(&mut renderer(), &scene, &chiaro_scene::Settings::default(), SIZE))
}

#[test]
fn compressed_files_render_as_their_original() {
    let original = rendered("glTF/shadows-spot.gltf");
    for file in [
        "encoded/shadows-spot-draco-edgebreaker.glb",
        "encoded/shadows-spot-draco-sequential.glb",
        "encoded/shadows-spot-meshopt.glb",
    ] {
        let decoded = rendered(file);
        let flip = mean_flip(SIZE, &original, &decoded);
        let differing = original
            .chunks_exact(3)
            .zip(decoded.chunks_exact(3))
            .filter(|(a, b)| a.iter().zip(*b).any(|(x, y)| x.abs_diff(*y) > 8));
        let differing = differing.count();
        println!("{file}: mean FLIP {flip:.4}, {differing} of {} pixels differ by more than 8 levels", SIZE * SIZE);
        assert!(flip < 0.005, "{file}: mean FLIP {flip}");
        assert!(differing < 16, "{file}: {differing} pixels differ");
    }
}

/// tests/assets/TexturedKtx2: a floor textured from a PNG, and from the same PNG encoded
/// to KTX2 by the Basis Universal encoder (ETC1S, UASTC with Zstandard), mip levels from
/// the files. Measured on lavapipe: mean FLIP 0.036 for ETC1S and 0.010 for UASTC, whose
/// texels are within 0.24 levels of the PNG's on average: most of its difference is the
/// encoder's mip levels (a sharper filter than the renderer's box) on the far floor.
#[test]
fn ktx2_textured_files_render_as_their_png() {
    let root = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../../tests/assets/TexturedKtx2"));
    let rendered = |file: &str| {
        let scene = load_gltf(&root.join(file)).unwrap_or_else(|e| panic!("{e}"));
        ldr_rgb(&render(&mut renderer(), &scene, &chiaro_scene::Settings::default(), SIZE))
    };
    let png = rendered("textured-png.gltf");
    for (file, bound) in [("textured-etc1s.gltf", 0.05), ("textured-uastc.gltf", 0.02)] {
        let flip = mean_flip(SIZE, &png, &rendered(file));
        println!("{file}: mean FLIP {flip:.4} against the PNG");
        assert!(flip < bound, "{file}: mean FLIP {flip}");
    }
}
