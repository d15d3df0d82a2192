//! Files the ecosystem's tools compressed (tests/assets/ShadowsSpot/encoded, made with
//! gltf-transform's draco and meshopt commands as its PROVENANCE.txt says) render as their
//! plain original, shadows included, within what the codecs' quantisation moves: a mean
//! FLIP under 0.005 and fewer than a thousandth of the pixels off by more than 8 levels
//! (measured: 0.0005 and 6 pixels for Draco's edgebreaker, nothing for the others).

mod common;

use chiaro_render::{FrameOptions, View};
use chiaro_scene::{Settings, load_gltf};
use common::*;
use std::path::Path;

const SIZE: u32 = 128;

/// Mean FLIP of a KTX2 image transcoded to BC7 against the same image transcoded to RGBA8:
/// about twice the worst measured on lavapipe (0.0146 ETC1S, whose BC7 transcode filters
/// chroma across blocks; 0.0097 UASTC). Against the PNG, BC7 measures 0.0338 and 0.0123.
const BC7_FROM_RGBA8: f32 = 0.03;

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
/// the files. Measured on lavapipe as RGBA8: mean FLIP 0.036 for ETC1S and 0.010 for
/// UASTC, whose texels are within 0.24 levels of the PNG's on average: most of its
/// difference is the encoder's mip levels (a sharper filter than the renderer's box) on
/// the far floor. As BC7 (lavapipe samples BC) each renders within `BC7_FROM_RGBA8` of its
/// RGBA8 self.
#[test]
fn ktx2_textured_files_render_as_their_png() {
    let root = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../../tests/assets/TexturedKtx2"));
    let mut r = renderer();
    let has_bc = r.ctx.device.features().contains(wgpu::Features::TEXTURE_COMPRESSION_BC);
    // The frame's LDR image and how many images went up as BC7; `rgba8` forgets the
    // Basis source, so that the image goes up as the RGBA8 it transcoded to on loading.
    let mut rendered = |file: &str, rgba8: bool| {
        let mut scene = load_gltf(&root.join(file)).unwrap_or_else(|e| panic!("{e}"));
        if rgba8 {
            scene.images.iter_mut().for_each(|i| i.basis_source = None);
        }
        let prepared = r.prepare(&scene).expect("prepare");
        let view = View::from_camera(&scene, 0, SIZE, SIZE);
        let options = FrameOptions { readback: true, ..Default::default() };
        let frame = r.render(&scene, &prepared, &view, &Settings::default(), options).expect("render");
        (ldr_rgb(&frame), prepared.gpu.bc7_images)
    };
    let (png, none) = rendered("textured-png.gltf", false);
    assert_eq!(none, 0);
    for (file, bound) in [("textured-etc1s.gltf", 0.05), ("textured-uastc.gltf", 0.02)] {
        let (as_rgba8, _) = rendered(file, true);
        let flip = mean_flip(SIZE, &png, &as_rgba8);
        println!("{file} as RGBA8: mean FLIP {flip:.4} against the PNG");
        assert!(flip < bound, "{file}: mean FLIP {flip}");
        // Where the device samples BC, the same file goes up as BC7.
        let (native, bc7_images) = rendered(file, false);
        assert_eq!(bc7_images, has_bc as usize, "{file}: BC7 on a device with BC");
        let flip = mean_flip(SIZE, &png, &native);
        let against_rgba8 = mean_flip(SIZE, &as_rgba8, &native);
        println!("{file} as BC7 ({has_bc}): mean FLIP {flip:.4} against the PNG, {against_rgba8:.4} against RGBA8");
        assert!(flip < bound, "{file} as BC7: mean FLIP {flip}");
        assert!(against_rgba8 < BC7_FROM_RGBA8, "{file} as BC7: mean FLIP {against_rgba8} against RGBA8");
    }
}
