//! What the bake tests share: a scene with its bake applied, as `chiaro render` would
//! load it, and where each lightmap texel lies in the world.

#![allow(dead_code)]

use chiaro_bake::raster::{TexelTriangles, barycentric, clamp_to_triangle};
use chiaro_bake::{BakeResult, Silent, bake};
use chiaro_scene::{Scene, Settings, baked};
use glam::Vec3;
use std::sync::atomic::AtomicBool;

/// `scene` baked with `settings` and the bake applied, in memory.
pub fn baked_scene(scene: &Scene, settings: &Settings) -> Scene {
    let result = bake(scene, settings, &Silent, &AtomicBool::new(false)).unwrap();
    let mut baked_scene = scene.clone();
    baked::apply(&mut baked_scene, result.lighting, &result.layout.placements(scene)).unwrap();
    baked_scene
}

/// Where a surface covers a texel: its chart, its instance and the world position of the
/// texel's centre.
pub type Place = Option<(u32, u32, Vec3)>;

/// Per atlas, per texel, its place.
pub fn texel_places(scene: &Scene, result: &BakeResult) -> Vec<Vec<Place>> {
    let size = result.layout.size;
    (0..result.layout.atlas_count)
        .map(|layer| {
            let triangles: Vec<_> = result.layout.triangles_of(layer).copied().collect();
            let map = TexelTriangles::build(size, &triangles);
            (0..size * size)
                .map(|texel| {
                    let &id = map.of(texel as usize).first()?;
                    let t = &triangles[id as usize];
                    let centre = glam::Vec2::new((texel % size) as f32 + 0.5, (texel / size) as f32 + 0.5);
                    let w = barycentric(&t.corners, centre)
                        .filter(|w| w.iter().all(|&v| v >= 0.0))
                        .unwrap_or_else(|| clamp_to_triangle(&t.corners, centre));
                    let instance = &scene.instances[t.instance as usize];
                    let p = &scene.meshes[instance.mesh].primitives[t.primitive as usize];
                    let corner = |k: usize| p.positions[p.indices[3 * t.triangle as usize + k] as usize];
                    let local = corner(0) * w[0] + corner(1) * w[1] + corner(2) * w[2];
                    Some((t.chart, t.instance, instance.world_from_local.transform_point3(local)))
                })
                .collect()
        })
        .collect()
}
