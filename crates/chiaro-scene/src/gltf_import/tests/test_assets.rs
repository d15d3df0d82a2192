//! The repository's test scenes (`tests/assets` at the repository root, with their
//! licenses and provenance) in; for each, its triangles, the lights and cameras its README
//! lists, and well-formed vertex data out.

use crate::gltf_import::load_gltf;
use crate::types::LightKind;
use std::path::{Path, PathBuf};

/// Every scene under tests/assets loads with triangles and the lights its README lists.
#[test]
fn test_assets_load_with_their_documented_lights() {
    let assets = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../../tests/assets"));
    // (folder, directional, spot, point, cameras)
    let expected = [
        ("ShadowsDirectional", 1, 0, 0, 1),
        ("ShadowsSpot", 0, 1, 0, 1),
        ("LightsPunctualLamp", 0, 0, 5, 0),
        ("GlamVelvetSofa", 1, 0, 0, 0),
        ("IridescenceSuzanne", 1, 0, 0, 0),
        ("chiaro-bench", 1, 4, 60, 1),
        ("InstancedBoxes", 1, 1, 0, 1),
        ("TexturedKtx2", 1, 0, 0, 1),
        ("PointsAndLines", 1, 0, 0, 1),
    ];
    fn scene_files(dir: &Path, out: &mut Vec<PathBuf>) {
        for entry in std::fs::read_dir(dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                scene_files(&path, out);
            } else if path.extension().is_some_and(|e| e == "gltf" || e == "glb") {
                out.push(path);
            }
        }
    }
    for (folder, directional, spot, point, cameras) in expected {
        let mut files = Vec::new();
        scene_files(&assets.join(folder), &mut files);
        assert!(!files.is_empty(), "no glTF under {folder}");
        for file in files {
            let scene = load_gltf(&file).unwrap_or_else(|e| panic!("{e}"));
            assert!(scene.triangle_count() > 0, "{folder}: no triangles");
            let count = |f: fn(&LightKind) -> bool| scene.lights.iter().filter(|l| f(&l.kind)).count();
            assert_eq!(count(|k| *k == LightKind::Directional), directional, "{folder}");
            assert_eq!(count(|k| matches!(k, LightKind::Spot { .. })), spot, "{folder}");
            assert_eq!(count(|k| *k == LightKind::Point), point, "{folder}");
            // The orthographic copy keeps the original camera beside its own.
            let orthographic_copy = file.ends_with("orthographic/shadows-directional-orthographic.gltf");
            assert_eq!(scene.cameras.len(), cameras + orthographic_copy as usize, "{folder}");
            for light in &scene.lights {
                assert!((light.direction().length() - 1.0).abs() < 1e-4, "{folder}: {}", light.name);
            }
            for mesh in &scene.meshes {
                for (_, p) in mesh.drawn_parts() {
                    let n = p.positions.len();
                    // Points and lines without normals have neither (and draw unlit).
                    let bare = p.normals.is_empty() && p.tangents.is_empty();
                    assert!(bare || (p.normals.len() == n && p.tangents.len() == n));
                    assert!(p.uv0.len() == n && p.uv1.len() == n);
                    assert!(p.indices.iter().all(|&i| (i as usize) < n));
                    assert!(p.tangents.iter().all(|t| t.is_finite() && t.w.abs() == 1.0));
                }
            }
            if folder == "ShadowsSpot" {
                assert_eq!(scene.lights[0].range, Some(25.0));
            }
        }
    }
}

/// A document whose buffer and images are given in memory (as the browser build fetches
/// them) loads exactly as from disk, and one file left out is an error naming it.
#[test]
fn given_files_load_as_the_disk_does() {
    use crate::gltf_import::{GivenFiles, load_gltf_given, referenced_files};
    let path = Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../tests/assets/LightsPunctualLamp/glTF/LightsPunctualLamp.gltf"
    ));
    let bytes = std::fs::read(path).unwrap();
    let wanted = referenced_files(path, &bytes).unwrap();
    assert_eq!(wanted.len(), 8, "{wanted:?}");
    assert!(wanted.contains(&path.with_file_name("LightsPunctualLamp.data.bin")), "{wanted:?}");
    let mut files: GivenFiles = wanted.iter().map(|f| (f.clone(), std::fs::read(f).unwrap())).collect();
    let given = load_gltf_given(path, &bytes, &files).unwrap();
    let disk = load_gltf(path).unwrap();
    assert_eq!(given.triangle_count(), disk.triangle_count());
    assert_eq!(given.images.len(), disk.images.len());
    assert!(given.images.iter().zip(&disk.images).all(|(a, b)| a.rgba8 == b.rgba8));
    let missing = path.with_file_name("material1_normal.png");
    files.remove(&missing);
    let message = load_gltf_given(path, &bytes, &files).unwrap_err().to_string();
    assert!(message.contains("material1_normal.png") && message.contains("not among the files given"), "{message}");
}
