//! EXT_mesh_gpu_instancing: tests/assets/InstancedBoxes holds 64 boxes placed by 64 nodes
//! and the same scene after gltf-transform's `instance` command made them one instanced
//! node. Both render the same image, shadows included; each copy has its own id in the
//! instance AOV; and the copies cast with instanced draws, not one draw each.

mod common;

use chiaro_render::{FrameOptions, FrameOutput, View};
use chiaro_scene::load_gltf;
use common::*;
use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

const SIZE: u32 = 128;

fn frame(file: &str) -> (chiaro_scene::Scene, FrameOutput) {
    let path = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../../tests/assets/InstancedBoxes")).join(file);
    let scene = load_gltf(&path).unwrap_or_else(|e| panic!("{e}"));
    let mut renderer = renderer();
    let prepared = renderer.prepare(&scene).unwrap();
    let view = View::from_camera(&scene, 0, SIZE, SIZE);
    let options = FrameOptions { ids: true, readback: true, ..Default::default() };
    let frame = renderer.render(&scene, &prepared, &view, &chiaro_scene::Settings::default(), options).unwrap();
    (scene, frame)
}

#[test]
fn instanced_copies_render_as_nodes_do_with_ids_of_their_own_and_instanced_draws() {
    let (nodes_scene, nodes) = frame("boxes-nodes.gltf");
    let (instanced_scene, instanced) = frame("boxes-instanced.glb");
    assert_eq!(instanced_scene.instances.len(), nodes_scene.instances.len());
    assert_eq!(instanced_scene.instances.iter().filter(|i| i.gpu_instance.is_some()).count(), 64);

    let flip = mean_flip(SIZE, &ldr_rgb(&nodes), &ldr_rgb(&instanced));
    println!("mean FLIP between the node and the instanced scene: {flip:.5}");
    assert!(flip < 1e-3, "mean FLIP {flip}");

    // Each box seen has one id in either file, and the ids pair one to one.
    let (a, b) = (&nodes.ids.as_ref().unwrap().instance, &instanced.ids.as_ref().unwrap().instance);
    let mut pairs: BTreeMap<u32, BTreeSet<u32>> = BTreeMap::new();
    for (&n, &i) in a.iter().zip(b) {
        pairs.entry(n).or_default().insert(i);
    }
    let boxes = pairs.len() - 2; // the sky and the floor
    assert!(boxes > 40, "only {boxes} boxes in view");
    // Ids at a box's edge can differ by a pixel where the two files' transforms round
    // apart; every box keeps one id for nearly all its pixels.
    let distinct: BTreeSet<u32> = b.iter().copied().collect();
    assert_eq!(distinct.len(), pairs.len(), "instance ids are not one per box: {distinct:?}");
    let node_count = instanced_scene.nodes.len() as u32;
    assert!(distinct.iter().filter(|&&id| id >= node_count && id != u32::MAX).count() == boxes);

    // The copies a tile reaches cast with one instanced draw per run of them that the
    // tile's culling leaves unbroken, not one draw each.
    let casters: usize = instanced.plan.shadows.redrawn_tiles().map(|(_, t)| t.casters.len()).sum();
    println!("{} tiles, {casters} casters, {} caster draws", instanced.shadow_tiles, instanced.shadow_caster_draws);
    assert!(instanced.shadow_tiles > 0);
    assert!(
        instanced.shadow_caster_draws * 10 < casters,
        "{} draws for {casters} casters",
        instanced.shadow_caster_draws
    );
}
