//! The lightmap layout of a scene: which static instances get lightmaps, their charts,
//! and where each chart lies in which atlas. Every atlas has the same size (a power of
//! two, at most `MAX_ATLAS_SIZE`), so that they load as layers of one texture array.

use crate::charts::{Chart, UvSource, WorldPrimitive, instance_charts};
use crate::pack::ShelfPacker;
use chiaro_scene::Scene;
use chiaro_scene::baked::InstanceLightmap;
use glam::Vec2;

pub const MAX_ATLAS_SIZE: u32 = 4096;
/// Empty texels around every chart: dilation fills them, so that bilinear filtering at a
/// chart's edge reads its own light and never the next chart's.
pub const GUTTER_TEXELS: u32 = 2;

/// One triangle placed in an atlas.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlacedTriangle {
    /// The chart it belongs to, counted over the whole layout.
    pub chart: u32,
    pub instance: u32,
    pub primitive: u32,
    pub triangle: u32,
    /// Corners in atlas texel coordinates (texel `(i, j)` spans `[i, i + 1] x [j, j + 1]`).
    pub corners: [Vec2; 3],
}

#[derive(Clone, Debug, PartialEq)]
pub struct InstanceLayout {
    pub instance: usize,
    pub layer: u32,
    pub uv_source: UvSource,
    /// The density used, lower than asked where the instance would not fit one atlas.
    pub texels_per_metre: f32,
    pub triangles: Vec<PlacedTriangle>,
}

#[derive(Clone, Debug, PartialEq)]
pub struct AtlasLayout {
    pub size: u32,
    pub atlas_count: u32,
    pub instances: Vec<InstanceLayout>,
}

impl AtlasLayout {
    /// The triangles of atlas `layer`.
    pub fn triangles_of(&self, layer: u32) -> impl Iterator<Item = &PlacedTriangle> {
        self.instances.iter().filter(move |i| i.layer == layer).flat_map(|i| &i.triangles)
    }

    /// Per lightmapped instance, its corners' atlas coordinates (0 to 1) in index order,
    /// as `chiaro_scene::baked::apply` takes them.
    pub fn placements(&self, scene: &Scene) -> Vec<InstanceLightmap> {
        self.instances
            .iter()
            .map(|layout| {
                let mesh = &scene.meshes[scene.instances[layout.instance].mesh];
                let mut corner_uvs: Vec<Vec<Vec2>> =
                    mesh.primitives.iter().map(|p| vec![Vec2::ZERO; p.indices.len()]).collect();
                for t in &layout.triangles {
                    let first = 3 * t.triangle as usize;
                    for (k, corner) in t.corners.iter().enumerate() {
                        corner_uvs[t.primitive as usize][first + k] = *corner / self.size as f32;
                    }
                }
                InstanceLightmap { instance: layout.instance, layer: layout.layer, corner_uvs }
            })
            .collect()
    }
}

/// The instances that get lightmaps: static, drawn (not shadows-only), with triangles.
pub fn lightmapped_instances(scene: &Scene) -> Vec<usize> {
    (0..scene.instances.len())
        .filter(|&i| {
            let instance = &scene.instances[i];
            instance.is_static
                && instance.cast_shadows != chiaro_scene::CastShadows::ShadowsOnly
                && scene.meshes.get(instance.mesh).is_some_and(|m| m.primitives.iter().any(|p| p.triangle_count() > 0))
        })
        .collect()
}

fn charts_of(scene: &Scene, instance: usize, texels_per_metre: f32) -> (Vec<Chart>, UvSource) {
    let inst = &scene.instances[instance];
    let primitives: Vec<WorldPrimitive> = scene.meshes[inst.mesh]
        .primitives
        .iter()
        .map(|p| WorldPrimitive {
            positions: p.positions.iter().map(|&q| inst.world_from_local.transform_point3(q)).collect(),
            indices: &p.indices,
            uv1: &p.uv1,
        })
        .collect();
    instance_charts(&primitives, texels_per_metre)
}

/// A chart's rectangle in texels: its extent, one texel so that its edges lie inside
/// texels, and the gutter on every side.
fn rect_of(chart: &Chart) -> (u32, u32) {
    let side = |extent: f32| extent.ceil() as u32 + 1 + 2 * GUTTER_TEXELS;
    (side(chart.size.x), side(chart.size.y))
}

/// Lays out every lightmapped instance of `scene` at `texels_per_metre`. An instance too
/// big for one atlas is laid out at a lower density, with a warning; one that fits at no
/// density (hundreds of thousands of charts) gets no lightmap and is lit by the probes.
pub fn layout_scene(scene: &Scene, texels_per_metre: f32) -> AtlasLayout {
    let mut charts: Vec<(usize, f32, Vec<Chart>, UvSource)> = Vec::new();
    for instance in lightmapped_instances(scene) {
        let mut density = texels_per_metre;
        loop {
            let (c, source) = charts_of(scene, instance, density);
            if fits(&c, MAX_ATLAS_SIZE) {
                if density < texels_per_metre {
                    tracing::warn!(
                        "{}: lowered to {density} texels per metre to fit one {MAX_ATLAS_SIZE}-texel atlas",
                        scene.instances[instance].name
                    );
                }
                charts.push((instance, density, c, source));
                break;
            }
            if density < 1e-3 {
                tracing::warn!(
                    "{}: {} lightmap charts fit no {MAX_ATLAS_SIZE}-texel atlas: lit by the probes instead",
                    scene.instances[instance].name,
                    c.len()
                );
                break;
            }
            density *= 0.5;
        }
    }
    let area: u64 = charts.iter().flat_map(|(_, _, c, _)| c).map(rect_of).map(|(w, h)| w as u64 * h as u64).sum();
    let mut size = ((area as f64 * 1.3).sqrt().ceil() as u32).next_power_of_two().clamp(16, MAX_ATLAS_SIZE);
    // Shelves waste space: grow the atlas until every instance fits an empty one.
    while size < MAX_ATLAS_SIZE && !charts.iter().all(|(_, _, c, _)| fits(c, size)) {
        size *= 2;
    }

    let mut packers = vec![ShelfPacker::new(size)];
    let mut instances = Vec::new();
    let mut chart_count = 0u32;
    for (instance, density, c, uv_source) in charts {
        let order = sorted_by_height(&c);
        let rects: Vec<(u32, u32)> = order.iter().map(|&k| rect_of(&c[k])).collect();
        let (layer, placed) = match packers.last_mut().and_then(|p| p.place_all(&rects)) {
            Some(placed) => (packers.len() - 1, placed),
            None => {
                let mut packer = ShelfPacker::new(size);
                let placed = packer.place_all(&rects).expect("every instance fits an empty atlas of this size");
                packers.push(packer);
                (packers.len() - 1, placed)
            }
        };
        let mut triangles = Vec::new();
        for (&k, p) in order.iter().zip(&placed) {
            let origin = Vec2::new(p.x as f32, p.y as f32) + (GUTTER_TEXELS as f32 + 0.5);
            let chart = chart_count;
            chart_count += 1;
            triangles.extend(c[k].triangles.iter().map(|t| PlacedTriangle {
                chart,
                instance: instance as u32,
                primitive: t.primitive,
                triangle: t.triangle,
                corners: t.corners.map(|q| origin + q),
            }));
        }
        instances.push(InstanceLayout {
            instance,
            layer: layer as u32,
            uv_source,
            texels_per_metre: density,
            triangles,
        });
    }
    AtlasLayout { size, atlas_count: if instances.is_empty() { 0 } else { packers.len() as u32 }, instances }
}

/// Whether an instance's charts fit one empty atlas of `size`.
fn fits(charts: &[Chart], size: u32) -> bool {
    let rects: Vec<(u32, u32)> = sorted_by_height(charts).iter().map(|&k| rect_of(&charts[k])).collect();
    ShelfPacker::new(size).place_all(&rects).is_some()
}

/// Chart indices, tallest first (ties by index, so the layout is deterministic).
fn sorted_by_height(charts: &[Chart]) -> Vec<usize> {
    let mut order: Vec<usize> = (0..charts.len()).collect();
    order.sort_by(|&a, &b| rect_of(&charts[b]).1.cmp(&rect_of(&charts[a]).1).then(a.cmp(&b)));
    order
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::raster::overlaps_texel;
    use chiaro_scene::{CastShadows, shapes};
    use chiaro_testkit::{add_box, floor_scene};
    use glam::Vec3;
    use std::collections::HashMap;

    fn scene() -> Scene {
        let mut scene = floor_scene(6.0, Vec3::new(0.0, 4.0, 3.0), Vec::new());
        for k in 0..12 {
            let x = k as f32 * 0.45 - 2.5;
            add_box(
                &mut scene,
                Vec3::new(x, 0.3, 0.2 * k as f32 - 1.0),
                Vec3::new(0.4, 0.6 + 0.1 * k as f32, 0.3),
                0.3 * k as f32,
                CastShadows::On,
            );
        }
        // A sphere: many small charts.
        scene.meshes.push(chiaro_scene::Mesh::of_triangles("ball".into(), vec![shapes::sphere(0.5, 16, 8)]));
        let mut ball = scene.instances[1].clone();
        ball.mesh = scene.meshes.len() - 1;
        ball.world_from_local = glam::Mat4::from_translation(Vec3::new(1.0, 0.5, 1.0));
        scene.instances.push(ball);
        scene
    }

    /// Every texel each chart's triangles overlap, per layer.
    fn chart_texels(layout: &AtlasLayout) -> HashMap<(u32, u32, u32), u32> {
        let mut owner = HashMap::new();
        for instance in &layout.instances {
            for t in &instance.triangles {
                let min = t.corners[0].min(t.corners[1]).min(t.corners[2]).floor();
                let max = t.corners[0].max(t.corners[1]).max(t.corners[2]).ceil();
                for y in min.y as u32..max.y as u32 {
                    for x in min.x as u32..max.x as u32 {
                        if overlaps_texel(&t.corners, x, y) {
                            let previous = owner.insert((instance.layer, x, y), t.chart);
                            assert!(previous.is_none_or(|c| c == t.chart), "texel {x},{y} is in two charts");
                        }
                    }
                }
            }
        }
        owner
    }

    #[test]
    fn charts_never_share_texels_and_keep_two_gutters_apart() {
        let scene = scene();
        let layout = layout_scene(&scene, 20.0);
        assert_eq!(layout.instances.len(), scene.instances.len());
        let owner = chart_texels(&layout);
        let g = GUTTER_TEXELS as i64;
        for (&(layer, x, y), &chart) in &owner {
            assert!(x < layout.size && y < layout.size);
            // No texel of another chart within 2 gutters: dilation fills `g` texels around
            // each chart, and bilinear filtering reads one texel further.
            for dy in -2 * g..=2 * g {
                for dx in -2 * g..=2 * g {
                    let (nx, ny) = (x as i64 + dx, y as i64 + dy);
                    if nx < 0 || ny < 0 {
                        continue;
                    }
                    if let Some(&other) = owner.get(&(layer, nx as u32, ny as u32)) {
                        assert!(
                            other == chart || dx.abs() >= 2 * g || dy.abs() >= 2 * g,
                            "charts {chart} and {other} at {x},{y} and {nx},{ny}"
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn a_slab_whose_faces_outgrow_the_estimated_atlas_still_gets_its_texels() {
        // Two 69x69 faces: more than the area estimate's 128-texel atlas holds on shelves.
        let mut scene = floor_scene(1.0, Vec3::new(0.0, 4.0, 3.0), Vec::new());
        scene.meshes[0].primitives[0] = shapes::cuboid(Vec3::new(8.0, 0.1, 8.0));
        let layout = layout_scene(&scene, 8.0);
        assert_eq!(layout.instances.len(), 1);
        assert_eq!(layout.instances[0].triangles.len(), 12);
        assert!(layout.size >= 256, "{}", layout.size);
        for t in &layout.instances[0].triangles {
            for c in t.corners {
                assert!(c.cmpge(glam::Vec2::ZERO).all() && c.cmple(glam::Vec2::splat(layout.size as f32)).all());
            }
        }
        chart_texels(&layout);
    }

    #[test]
    fn generated_charts_keep_the_requested_density() {
        let scene = scene();
        let layout = layout_scene(&scene, 20.0);
        // The floor is one flat chart: 6 m at 20 texels per metre.
        let floor = &layout.instances[0];
        assert_eq!(floor.uv_source, crate::charts::UvSource::Generated);
        let min = floor.triangles.iter().flat_map(|t| t.corners).fold(glam::Vec2::INFINITY, |a, c| a.min(c));
        let max = floor.triangles.iter().flat_map(|t| t.corners).fold(glam::Vec2::NEG_INFINITY, |a, c| a.max(c));
        assert!(((max - min) - glam::Vec2::splat(120.0)).abs().max_element() < 1e-3, "{min} {max}");
    }
}
