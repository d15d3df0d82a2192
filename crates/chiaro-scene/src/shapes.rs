//! Procedural meshes for the demo scene and the tests: planes, boxes and UV spheres with
//! exact normals, tangents and UVs.

use crate::types::Primitive;
use chiaro_math::Aabb;
use glam::{Vec2, Vec3, Vec4};

fn finish(mut p: Primitive) -> Primitive {
    p.bounds = Aabb::from_points(p.positions.iter().copied());
    p
}

/// A square in the XZ plane, facing +Y, `size` metres on a side, centred on the origin,
/// split into `divisions`² quads.
pub fn plane(size: f32, divisions: u32) -> Primitive {
    let n = divisions.max(1);
    let mut p = Primitive::default();
    for j in 0..=n {
        for i in 0..=n {
            let u = i as f32 / n as f32;
            let v = j as f32 / n as f32;
            p.positions.push(Vec3::new((u - 0.5) * size, 0.0, (v - 0.5) * size));
            p.normals.push(Vec3::Y);
            p.tangents.push(Vec4::new(1.0, 0.0, 0.0, 1.0));
            p.uv0.push(Vec2::new(u, v) * size);
        }
    }
    for j in 0..n {
        for i in 0..n {
            let a = j * (n + 1) + i;
            let b = a + 1;
            let c = a + n + 1;
            let d = c + 1;
            // Counter-clockwise seen from +Y.
            p.indices.extend_from_slice(&[a, c, b, b, c, d]);
        }
    }
    finish(p)
}

/// An axis-aligned box centred on the origin with the given full extents.
pub fn cuboid(extents: Vec3) -> Primitive {
    let h = extents * 0.5;
    let mut p = Primitive::default();
    let faces = [
        (Vec3::X, Vec3::NEG_Z),
        (Vec3::NEG_X, Vec3::Z),
        (Vec3::Y, Vec3::X),
        (Vec3::NEG_Y, Vec3::X),
        (Vec3::Z, Vec3::X),
        (Vec3::NEG_Z, Vec3::NEG_X),
    ];
    for (normal, tangent) in faces {
        let bitangent = normal.cross(tangent);
        let base = p.positions.len() as u32;
        for (s, t) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
            let local = normal + tangent * s + bitangent * t;
            p.positions.push(local * h);
            p.normals.push(normal);
            p.tangents.push(tangent.extend(1.0));
            p.uv0.push(Vec2::new((s + 1.0) * 0.5, (1.0 - t) * 0.5));
        }
        p.indices.extend_from_slice(&[base, base + 1, base + 2, base, base + 2, base + 3]);
    }
    finish(p)
}

/// A UV sphere of `radius` centred on the origin.
pub fn sphere(radius: f32, segments: u32, rings: u32) -> Primitive {
    let (segments, rings) = (segments.max(3), rings.max(2));
    let mut p = Primitive::default();
    for r in 0..=rings {
        let v = r as f32 / rings as f32;
        let theta = v * std::f32::consts::PI;
        for s in 0..=segments {
            let u = s as f32 / segments as f32;
            let phi = u * std::f32::consts::TAU;
            let normal = Vec3::new(theta.sin() * phi.cos(), theta.cos(), -theta.sin() * phi.sin());
            p.positions.push(normal * radius);
            p.normals.push(normal);
            p.tangents.push(Vec3::new(-phi.sin(), 0.0, -phi.cos()).extend(1.0));
            p.uv0.push(Vec2::new(u, v));
        }
    }
    let stride = segments + 1;
    for r in 0..rings {
        for s in 0..segments {
            let a = r * stride + s;
            let b = a + stride;
            // The first and last rings meet at a pole, where one of the two triangles
            // collapses; leave it out rather than emit a sliver with a garbage normal.
            if r > 0 {
                p.indices.extend_from_slice(&[a, b, a + 1]);
            }
            if r + 1 < rings {
                p.indices.extend_from_slice(&[a + 1, b, b + 1]);
            }
        }
    }
    finish(p)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every triangle winds counter-clockwise seen from outside (its geometric normal
    /// agrees with the vertex normals).
    fn assert_outward_winding(p: &Primitive) {
        for tri in p.indices.chunks(3) {
            let [a, b, c] = [0, 1, 2].map(|k| p.positions[tri[k] as usize]);
            let face = (b - a).cross(c - a);
            if face.length() < 1e-9 {
                continue;
            }
            let n = p.normals[tri[0] as usize] + p.normals[tri[1] as usize] + p.normals[tri[2] as usize];
            assert!(face.dot(n) > 0.0, "triangle {tri:?} winds inward");
        }
    }

    #[test]
    fn shapes_wind_outward_and_have_unit_normals() {
        for p in [plane(4.0, 3), cuboid(Vec3::new(1.0, 2.0, 3.0)), sphere(1.5, 16, 8)] {
            assert_outward_winding(&p);
            assert!(p.normals.iter().all(|n| (n.length() - 1.0).abs() < 1e-4));
            assert!(p.tangents.iter().zip(&p.normals).all(|(t, n)| t.truncate().dot(*n).abs() < 1e-4));
            assert_eq!(p.positions.len(), p.uv0.len());
            assert!(p.indices.iter().all(|&i| (i as usize) < p.positions.len()));
        }
    }

    #[test]
    fn cuboid_bounds_match_extents() {
        let b = cuboid(Vec3::new(1.0, 2.0, 3.0)).bounds;
        assert_eq!(b.min, Vec3::new(-0.5, -1.0, -1.5));
        assert_eq!(b.max, Vec3::new(0.5, 1.0, 1.5));
    }
}
