//! Lightmap charts of one mesh instance, in texels at the requested density.
//!
//! With a valid `TEXCOORD_1` (every coordinate finite and inside the unit square) the
//! instance is one chart: that square, scaled so that its texels cover the surface at
//! about the requested density. Otherwise charts are made here: triangles that share an
//! edge and face the same way along the same major axis form a chart, projected flat onto
//! the plane across that axis. Boxes and rooms get one chart per face, with exact density;
//! curved meshes get many small charts. (xatlas would make fewer, less stretched charts
//! for curved meshes, but its Rust bindings are unmaintained C++ builds; this is enough
//! for the architectural scenes lightmaps are for, and deterministic.)

use glam::{Vec2, Vec3};
use std::collections::HashMap;

/// A triangle of the instance: its primitive, its index in the primitive, and its corners
/// in chart texels (relative to the chart's lower corner).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ChartTriangle {
    pub primitive: u32,
    pub triangle: u32,
    pub corners: [Vec2; 3],
}

#[derive(Clone, Debug, PartialEq)]
pub struct Chart {
    pub triangles: Vec<ChartTriangle>,
    /// Extent of the corners in texels (they lie in `[0, size]`).
    pub size: Vec2,
}

/// Where an instance's lightmap coordinates come from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum UvSource {
    TexCoord1,
    Generated,
}

impl UvSource {
    pub fn name(self) -> &'static str {
        match self {
            UvSource::TexCoord1 => "texcoord1",
            UvSource::Generated => "generated",
        }
    }
}

/// One primitive of an instance, in world space.
pub struct WorldPrimitive<'a> {
    pub positions: Vec<Vec3>,
    pub indices: &'a [u32],
    pub uv1: &'a [Vec2],
}

impl WorldPrimitive<'_> {
    fn triangles(&self) -> impl Iterator<Item = (u32, [usize; 3])> + '_ {
        self.indices.chunks_exact(3).enumerate().filter_map(|(t, c)| {
            let corners = [c[0] as usize, c[1] as usize, c[2] as usize];
            corners.iter().all(|&i| i < self.positions.len()).then_some((t as u32, corners))
        })
    }

    fn area(&self) -> f32 {
        self.triangles()
            .map(|(_, [a, b, c])| {
                let p = &self.positions;
                (p[b] - p[a]).cross(p[c] - p[a]).length() * 0.5
            })
            .filter(|a| a.is_finite())
            .sum()
    }
}

/// The charts of one instance at `texels_per_metre`, and where their coordinates came from.
pub fn instance_charts(primitives: &[WorldPrimitive], texels_per_metre: f32) -> (Vec<Chart>, UvSource) {
    if let Some(chart) = texcoord1_chart(primitives, texels_per_metre) {
        return (vec![chart], UvSource::TexCoord1);
    }
    let charts =
        primitives.iter().enumerate().flat_map(|(k, p)| generated_charts(k as u32, p, texels_per_metre)).collect();
    (charts, UvSource::Generated)
}

fn texcoord1_chart(primitives: &[WorldPrimitive], texels_per_metre: f32) -> Option<Chart> {
    let valid = primitives.iter().all(|p| {
        p.uv1.len() == p.positions.len()
            && p.uv1.iter().all(|uv| uv.is_finite() && uv.cmpge(Vec2::ZERO).all() && uv.cmple(Vec2::ONE).all())
    });
    if !valid || primitives.is_empty() {
        return None;
    }
    let (mut world_area, mut uv_area) = (0.0, 0.0);
    for p in primitives {
        world_area += p.area();
        uv_area += p
            .triangles()
            .map(|(_, [a, b, c])| (p.uv1[b] - p.uv1[a]).perp_dot(p.uv1[c] - p.uv1[a]).abs() * 0.5)
            .sum::<f32>();
    }
    if !(uv_area > 1e-8 && world_area > 0.0) {
        return None;
    }
    // Texels per unit of UV so that the surface gets the requested density on average.
    let scale = (world_area / uv_area).sqrt() * texels_per_metre;
    let triangles = primitives
        .iter()
        .enumerate()
        .flat_map(|(k, p)| {
            p.triangles().map(move |(t, corners)| ChartTriangle {
                primitive: k as u32,
                triangle: t,
                corners: corners.map(|i| p.uv1[i] * scale),
            })
        })
        .collect();
    Some(Chart { triangles, size: Vec2::splat(scale) })
}

/// The major axis a triangle faces along, with its sign: 0 to 5.
fn facing_class(normal: Vec3) -> u8 {
    let a = normal.abs();
    let axis = if a.x >= a.y && a.x >= a.z {
        0
    } else if a.y >= a.z {
        1
    } else {
        2
    };
    axis * 2 + (normal[axis as usize] < 0.0) as u8
}

/// Positions are welded at this many steps per metre, so that meshes with split vertices
/// (hard edges, UV seams) still join their charts across the seam.
const WELD_STEPS_PER_METRE: f32 = 1.0e5;

fn weld_key(p: Vec3) -> [i64; 3] {
    (p * WELD_STEPS_PER_METRE).round().as_i64vec3().to_array()
}

fn find(parent: &mut [usize], mut i: usize) -> usize {
    while parent[i] != i {
        parent[i] = parent[parent[i]];
        i = parent[i];
    }
    i
}

/// A triangle's index in its primitive and its corners' vertex indices.
type CornerIndices = (u32, [usize; 3]);

fn generated_charts(primitive: u32, p: &WorldPrimitive, texels_per_metre: f32) -> Vec<Chart> {
    let triangles: Vec<(u32, [usize; 3], u8)> = p
        .triangles()
        .filter_map(|(t, c)| {
            let n = (p.positions[c[1]] - p.positions[c[0]]).cross(p.positions[c[2]] - p.positions[c[0]]);
            n.try_normalize().map(|n| (t, c, facing_class(n)))
        })
        .collect();
    // Union triangles that share a welded edge and a facing class.
    let mut parent: Vec<usize> = (0..triangles.len()).collect();
    let mut edges: HashMap<([i64; 3], [i64; 3], u8), usize> = HashMap::new();
    for (k, &(_, c, class)) in triangles.iter().enumerate() {
        for e in 0..3 {
            let (a, b) = (weld_key(p.positions[c[e]]), weld_key(p.positions[c[(e + 1) % 3]]));
            let key = if a <= b { (a, b, class) } else { (b, a, class) };
            match edges.get(&key) {
                Some(&other) => {
                    let (ra, rb) = (find(&mut parent, k), find(&mut parent, other));
                    parent[ra.max(rb)] = ra.min(rb);
                }
                None => {
                    edges.insert(key, k);
                }
            }
        }
    }
    // Charts in order of their first triangle, so the result does not depend on hashing.
    let mut chart_of_root: HashMap<usize, usize> = HashMap::new();
    let mut charts: Vec<(u8, Vec<CornerIndices>)> = Vec::new();
    for (k, &(t, c, class)) in triangles.iter().enumerate() {
        let root = find(&mut parent, k);
        let index = *chart_of_root.entry(root).or_insert_with(|| {
            charts.push((class, Vec::new()));
            charts.len() - 1
        });
        charts[index].1.push((t, c));
    }
    charts
        .into_iter()
        .map(|(class, tris)| {
            let axis = (class / 2) as usize;
            let project = |q: Vec3| Vec2::new(q[(axis + 1) % 3], q[(axis + 2) % 3]) * texels_per_metre;
            let mut min = Vec2::splat(f32::INFINITY);
            let mut max = Vec2::splat(f32::NEG_INFINITY);
            for &(_, c) in &tris {
                for i in c {
                    let q = project(p.positions[i]);
                    min = min.min(q);
                    max = max.max(q);
                }
            }
            let triangles = tris
                .into_iter()
                .map(|(t, c)| ChartTriangle {
                    primitive,
                    triangle: t,
                    corners: c.map(|i| project(p.positions[i]) - min),
                })
                .collect();
            Chart { triangles, size: max - min }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use chiaro_scene::shapes;

    fn world(p: &chiaro_scene::Primitive, scale: Vec3) -> WorldPrimitive<'_> {
        WorldPrimitive { positions: p.positions.iter().map(|&q| q * scale).collect(), indices: &p.indices, uv1: &p.uv1 }
    }

    #[test]
    fn a_box_gets_one_chart_per_face_at_the_requested_density() {
        let cube = shapes::cuboid(Vec3::ONE);
        let (charts, source) = instance_charts(&[world(&cube, Vec3::new(2.0, 1.0, 4.0))], 10.0);
        assert_eq!(source, UvSource::Generated);
        assert_eq!(charts.len(), 6);
        let mut sizes: Vec<[i32; 2]> = charts
            .iter()
            .map(|c| {
                let s = c.size.round().as_ivec2();
                [s.x.min(s.y), s.x.max(s.y)]
            })
            .collect();
        sizes.sort();
        assert_eq!(sizes, vec![[10, 20], [10, 20], [10, 40], [10, 40], [20, 40], [20, 40]]);
        let triangles: usize = charts.iter().map(|c| c.triangles.len()).sum();
        assert_eq!(triangles, cube.triangle_count());
    }

    #[test]
    fn valid_texcoord1_is_one_chart_scaled_to_the_density() {
        let mut plane = shapes::plane(4.0, 2);
        plane.uv1 = plane.uv0.iter().map(|&uv| uv / 4.0).collect();
        let (charts, source) = instance_charts(&[world(&plane, Vec3::ONE)], 8.0);
        assert_eq!(source, UvSource::TexCoord1);
        assert_eq!(charts.len(), 1);
        assert!((charts[0].size - Vec2::splat(32.0)).abs().max_element() < 1e-3);
        // Coordinates outside the unit square are not lightmap coordinates.
        plane.uv1[0] = Vec2::new(1.5, 0.0);
        assert_eq!(instance_charts(&[world(&plane, Vec3::ONE)], 8.0).1, UvSource::Generated);
    }
}
