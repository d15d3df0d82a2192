//! The spec seeds load, and each gives what its rule says: a seed that the importer
//! refused, or read some other way, would leave its rule unfuzzed.

use chiaro_fuzz::spec_seeds::spec_seeds;
use chiaro_scene::Scene;
use std::path::Path;

const QUAD: [[f32; 3]; 4] = [[-1.0, 0.0, -1.0], [1.0, 0.0, -1.0], [1.0, 0.0, 1.0], [-1.0, 0.0, 1.0]];
const UVS: [[f32; 2]; 4] = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
const INDICES: [u32; 6] = [0, 2, 1, 0, 3, 2];

fn load(name: &str) -> Scene {
    let seed = spec_seeds().into_iter().find(|s| s.name == name).unwrap_or_else(|| panic!("no seed {name}"));
    chiaro_scene::load_gltf_bytes(Path::new("seed.gltf"), &seed.bytes).unwrap_or_else(|e| panic!("{name}: {e}"))
}

fn close<const N: usize>(got: [f32; N], want: [f32; N], tolerance: f32) -> bool {
    got.iter().zip(want).all(|(g, w)| (g - w).abs() <= tolerance)
}

fn positions(scene: &Scene) -> Vec<[f32; 3]> {
    scene.meshes[0].primitives[0].positions.iter().map(|p| p.to_array()).collect()
}

fn uvs(scene: &Scene) -> Vec<[f32; 2]> {
    scene.meshes[0].primitives[0].uv0.iter().map(|p| p.to_array()).collect()
}

fn noted(scene: &Scene, words: &str) -> bool {
    scene.ignored.iter().any(|note| note.contains(words))
}

#[test]
fn every_spec_seed_loads() {
    let seeds = spec_seeds();
    assert_eq!(seeds.len(), 12);
    for seed in &seeds {
        chiaro_scene::load_gltf_bytes(Path::new("seed.gltf"), &seed.bytes)
            .unwrap_or_else(|e| panic!("{}: {e}", seed.name));
    }
}

#[test]
fn the_quantized_seed_reads_integers_scaled_by_its_node() {
    let scene = load("quantized");
    let primitive = &scene.meshes[0].primitives[0];
    assert_eq!(positions(&scene), QUAD.map(|p| p.map(|c| c * 100.0)));
    assert!(primitive.normals.iter().all(|n| close(n.to_array(), [0.0, 1.0, 0.0], 1e-6)), "{:?}", primitive.normals);
    assert!(uvs(&scene).iter().zip(UVS).all(|(&got, want)| close(got, want, 1e-6)), "{:?}", primitive.uv0);
    assert_eq!(primitive.indices, INDICES);
    let bounds = scene.bounds();
    assert!(close(bounds.max.to_array(), [1.0, 0.0, 1.0], 1e-6), "{bounds:?}");
}

#[test]
fn the_meshopt_seeds_decode_every_stream_and_filter() {
    for name in ["meshopt", "meshopt glb"] {
        let scene = load(name);
        assert!(
            positions(&scene).iter().zip(QUAD).all(|(&got, want)| close(got, want, 1e-4)),
            "{name}: {:?}",
            positions(&scene)
        );
        let primitives = &scene.meshes[0].primitives;
        assert_eq!(primitives.len(), 2);
        assert!(
            primitives[0].normals.iter().all(|n| close(n.to_array(), [0.0, 1.0, 0.0], 1e-2)),
            "{name}: {:?}",
            primitives[0].normals
        );
        assert_eq!(uvs(&scene), UVS, "{name}");
        // TRIANGLES may rotate a triangle's corners; INDICES keeps them.
        let mut triangles: Vec<[u32; 3]> = primitives[0]
            .indices
            .chunks_exact(3)
            .map(|t| {
                let k = (0..3).min_by_key(|&k| t[k]).unwrap_or(0);
                [t[k], t[(k + 1) % 3], t[(k + 2) % 3]]
            })
            .collect();
        triangles.sort();
        assert_eq!(triangles, [[0, 2, 1], [0, 3, 2]], "{name}");
        assert_eq!(primitives[1].indices, INDICES, "{name}");
    }
}

#[test]
fn the_webp_seed_decodes_its_texture() {
    let scene = load("webp");
    assert_eq!(scene.images.len(), 1);
    let image = &scene.images[0];
    assert_eq!((image.width, image.height), (2, 2));
    assert_eq!(image.rgba8, [255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255, 255, 255, 255, 128]);
}

#[test]
fn the_sparse_seed_substitutes_on_a_view_and_on_zeros() {
    let scene = load("sparse");
    let mut expected = QUAD;
    expected[2] = [1.0, 0.5, 1.0];
    assert_eq!(positions(&scene), expected);
    assert_eq!(uvs(&scene), [[0.0, 0.0], [1.0, 0.0], [0.0, 0.0], [0.0, 1.0]]);
}

#[test]
fn the_hidden_nodes_seed_draws_and_lights_only_the_visible_copy() {
    let scene = load("hidden nodes");
    assert_eq!(scene.instances.len(), 1);
    assert_eq!(scene.instances[0].world_from_local.w_axis.x, 3.0);
    assert!(scene.lights.is_empty(), "the spot under the hidden node lights: {:?}", scene.lights);
}

#[test]
fn the_unlit_seed_marks_its_material() {
    let scene = load("unlit");
    assert!(scene.materials[0].unlit);
}

#[test]
fn the_unknown_light_seed_keeps_the_spot_and_notes_the_other() {
    let scene = load("unknown light type");
    assert_eq!(scene.lights.len(), 1, "{:?}", scene.lights);
    assert!(noted(&scene, "area"), "{:?}", scene.ignored);
}

#[test]
fn the_integers_as_floats_seed_reads_as_integers() {
    let scene = load("integers as floats");
    assert_eq!(scene.instances.len(), 1);
    assert_eq!(scene.lights.len(), 1);
    assert_eq!(positions(&scene), QUAD);
    assert_eq!(scene.meshes[0].primitives[0].indices, INDICES);
}

#[test]
fn the_optional_properties_seed_takes_the_defaults() {
    let scene = load("optional properties absent");
    let primitives = &scene.meshes[0].primitives;
    assert_eq!(primitives.len(), 2);
    assert!(primitives[0].uv1.iter().all(|uv| uv.to_array() == [0.0, 0.0]) && primitives[0].uv1.len() == 4);
    assert_eq!(primitives[0].material, Some(0));
    assert_eq!(primitives[1].material, None);
    assert_eq!(scene.cameras.len(), 1);
    assert!(noted(&scene, "has no image"), "{:?}", scene.ignored);
}

#[test]
fn the_no_scene_seed_draws_nothing_and_says_so() {
    let scene = load("no scene");
    assert!(scene.instances.is_empty() && scene.lights.is_empty());
    assert!(noted(&scene, "no scene"), "{:?}", scene.ignored);
}

#[test]
fn the_animation_pointer_seed_animates_a_light_and_a_material_and_has_an_orthographic_camera() {
    let mut scene = load("animation pointer");
    assert!(scene.cameras.iter().any(|c| c.projection.is_orthographic()));
    assert_eq!(scene.animation_duration(), Some(2.0));
    let rest = (scene.lights[0].color, scene.materials[0].base_color);
    scene.pose(Some(1.0)).unwrap();
    assert_ne!((scene.lights[0].color, scene.materials[0].base_color), rest, "the pointers move what they name");
}
