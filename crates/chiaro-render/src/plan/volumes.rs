//! The deferred path's light volumes: which mesh bounds each light's reach (the screen for
//! directional lights, a sphere for points, a pyramid around a spot's cone), its
//! transform, and whether the camera may be inside it, where the stencil test that needs
//! the volume's front faces gives way to the fallback of Catlike Coding's "Rendering 15,
//! Deferred Lights" (back faces alone). The volume meshes are made here too, so the plan
//! knows how far they reach.

use crate::view::View;
use chiaro_scene::{Light, LightKind};
use glam::{Mat4, Vec3};
use std::sync::OnceLock;

/// Spots wider than this get a sphere: a pyramid around a wider cone is mostly waste,
/// and at 90 degrees it would be infinite.
pub const MAX_PYRAMID_OUTER_RAD: f32 = std::f32::consts::FRAC_PI_3;

/// Which mesh bounds a light's reach in the deferred path.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum VolumeShape {
    /// A full-screen triangle (every directional light at once).
    Screen,
    /// `unit_sphere()` scaled by the range.
    Sphere,
    /// `unit_pyramid()`: apex at the light, base at the range, around the cone.
    Pyramid,
}

/// One light volume to draw.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VolumeDraw {
    /// Index into `FramePlan::lights`.
    pub light: u32,
    /// The mesh drawn.
    pub shape: VolumeShape,
    /// The volume mesh to world space.
    pub world_from_volume: Mat4,
    /// The camera may be inside the volume (or its near plane cut it): shade its back
    /// faces alone, without the stencil pass.
    pub camera_inside: bool,
}

impl VolumeDraw {
    /// The full-screen draw of the directional lights (the first is `light`).
    pub fn screen(light: u32) -> VolumeDraw {
        VolumeDraw { light, shape: VolumeShape::Screen, world_from_volume: Mat4::IDENTITY, camera_inside: false }
    }
}

/// A closed triangle mesh with outward, counter-clockwise faces.
pub struct VolumeMesh {
    /// Vertex positions around the origin.
    pub positions: Vec<Vec3>,
    /// Triangle indices into `positions`.
    pub indices: Vec<u32>,
    /// Farthest vertex from the origin: the radius of a sphere that holds the mesh.
    pub circumradius: f32,
}

/// An icosphere (80 faces) scaled so that every face lies at least 1 from the origin:
/// it holds the unit sphere.
pub fn unit_sphere() -> &'static VolumeMesh {
    static MESH: OnceLock<VolumeMesh> = OnceLock::new();
    MESH.get_or_init(|| {
        let t = (1.0 + 5f32.sqrt()) / 2.0;
        let mut positions: Vec<Vec3> = [
            (-1.0, t, 0.0),
            (1.0, t, 0.0),
            (-1.0, -t, 0.0),
            (1.0, -t, 0.0),
            (0.0, -1.0, t),
            (0.0, 1.0, t),
            (0.0, -1.0, -t),
            (0.0, 1.0, -t),
            (t, 0.0, -1.0),
            (t, 0.0, 1.0),
            (-t, 0.0, -1.0),
            (-t, 0.0, 1.0),
        ]
        .iter()
        .map(|&(x, y, z)| Vec3::new(x, y, z).normalize())
        .collect();
        let faces: [[u32; 3]; 20] = [
            [0, 11, 5],
            [0, 5, 1],
            [0, 1, 7],
            [0, 7, 10],
            [0, 10, 11],
            [1, 5, 9],
            [5, 11, 4],
            [11, 10, 2],
            [10, 7, 6],
            [7, 1, 8],
            [3, 9, 4],
            [3, 4, 2],
            [3, 2, 6],
            [3, 6, 8],
            [3, 8, 9],
            [4, 9, 5],
            [2, 4, 11],
            [6, 2, 10],
            [8, 6, 7],
            [9, 8, 1],
        ];
        let mut midpoints = std::collections::HashMap::new();
        let mut midpoint = |a: u32, b: u32, positions: &mut Vec<Vec3>| {
            *midpoints.entry((a.min(b), a.max(b))).or_insert_with(|| {
                positions.push(((positions[a as usize] + positions[b as usize]) * 0.5).normalize());
                positions.len() as u32 - 1
            })
        };
        let mut indices = Vec::with_capacity(80 * 3);
        for [a, b, c] in faces {
            let (ab, bc, ca) =
                (midpoint(a, b, &mut positions), midpoint(b, c, &mut positions), midpoint(c, a, &mut positions));
            indices.extend_from_slice(&[a, ab, ca, b, bc, ab, c, ca, bc, ab, bc, ca]);
        }
        let nearest_face = indices
            .chunks_exact(3)
            .map(|f| {
                let [a, b, c] = [0, 1, 2].map(|k| positions[f[k] as usize]);
                (b - a).cross(c - a).normalize().dot(a)
            })
            .fold(f32::INFINITY, f32::min);
        for p in &mut positions {
            *p /= nearest_face;
        }
        VolumeMesh { circumradius: 1.0 / nearest_face, positions, indices }
    })
}

/// A pyramid with its apex at the origin, opening along -Z to a square base at z = -1
/// with corners at x, y = +-1.
pub fn unit_pyramid() -> &'static VolumeMesh {
    static MESH: OnceLock<VolumeMesh> = OnceLock::new();
    MESH.get_or_init(|| VolumeMesh {
        positions: vec![
            Vec3::ZERO,
            Vec3::new(-1.0, -1.0, -1.0),
            Vec3::new(1.0, -1.0, -1.0),
            Vec3::new(1.0, 1.0, -1.0),
            Vec3::new(-1.0, 1.0, -1.0),
        ],
        indices: vec![0, 1, 2, 0, 2, 3, 0, 3, 4, 0, 4, 1, 1, 3, 2, 1, 4, 3],
        circumradius: 3f32.sqrt(),
    })
}

/// The volume of a point or spot `light`, shaded out to `range`, for a camera at `view`.
pub fn light_volume(light: &Light, range: f32, view: &View, index: u32) -> VolumeDraw {
    let position = light.position();
    let (shape, world_from_volume, reach) = match light.kind {
        LightKind::Directional => (VolumeShape::Screen, Mat4::IDENTITY, f32::INFINITY),
        LightKind::Spot { outer_cone_rad, .. } if outer_cone_rad <= MAX_PYRAMID_OUTER_RAD => {
            let half = range * outer_cone_rad.tan();
            let world_from_volume = light.world_from_light * Mat4::from_scale(Vec3::new(half, half, range));
            (VolumeShape::Pyramid, world_from_volume, (2.0 * half * half + range * range).sqrt())
        }
        _ => {
            let world_from_volume = Mat4::from_translation(position) * Mat4::from_scale(Vec3::splat(range));
            (VolumeShape::Sphere, world_from_volume, range * unit_sphere().circumradius)
        }
    };
    // The near plane clips volumes the camera stands in or close to; an orthographic
    // camera's near plane is as wide as its view, so any volume reaching it counts.
    let margin = 2.0 * view.znear;
    let near_plane_gap = if view.is_orthographic() {
        (position - view.eye()).dot(view.forward()) - view.znear
    } else {
        view.eye().distance(position)
    };
    let camera_inside = shape != VolumeShape::Screen && near_plane_gap <= reach + margin;
    VolumeDraw { light: index, shape, world_from_volume, camera_inside }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_sphere_holds_the_unit_sphere_closely_with_outward_faces() {
        let mesh = unit_sphere();
        assert_eq!(mesh.indices.len(), 80 * 3);
        for f in mesh.indices.chunks_exact(3) {
            let [a, b, c] = [0, 1, 2].map(|k| mesh.positions[f[k] as usize]);
            let normal = (b - a).cross(c - a).normalize();
            let distance = normal.dot(a);
            assert!(distance >= 1.0 - 1e-5, "a face cuts the unit sphere: {distance}");
            assert!(normal.dot((a + b + c) / 3.0) > 0.0, "faces point outward");
        }
        assert!(mesh.circumradius < 1.1, "{}", mesh.circumradius);
    }

    #[test]
    fn the_pyramid_holds_the_cone_out_to_its_range() {
        let mesh = unit_pyramid();
        for f in mesh.indices.chunks_exact(3) {
            let [a, b, c] = [0, 1, 2].map(|k| mesh.positions[f[k] as usize]);
            let centroid = (a + b + c) / 3.0;
            let inner = Vec3::new(0.0, 0.0, -0.5);
            assert!((b - a).cross(c - a).dot(centroid - inner) > 0.0, "faces point outward");
        }
        // A 40 degree spot of range 5: points on the cone's rim at the range are inside.
        let outer = 40f32.to_radians();
        let light = Light::new(LightKind::Spot { inner_cone_rad: 0.3, outer_cone_rad: outer }, Vec3::Y, Vec3::NEG_Z);
        let view = View {
            width: 8,
            height: 8,
            world_from_view: Mat4::from_translation(Vec3::new(0.0, 1.0, 30.0)),
            clip_from_view: Mat4::IDENTITY,
            projection: chiaro_math::camera::Projection::Perspective { yfov_rad: 1.0 },
            znear: 0.1,
            zfar: None,
        };
        let volume = light_volume(&light, 5.0, &view, 0);
        assert_eq!(volume.shape, VolumeShape::Pyramid);
        assert!(!volume.camera_inside);
        let volume_from_world = volume.world_from_volume.inverse();
        for k in 0..16 {
            let a = k as f32 * std::f32::consts::TAU / 16.0;
            let rim = Vec3::Y + 5.0 * Vec3::new(outer.sin() * a.cos(), outer.sin() * a.sin(), -outer.cos());
            let p = volume_from_world.transform_point3(rim);
            assert!(p.z <= 0.0 && p.z >= -1.0 - 1e-5 && p.x.abs() <= -p.z + 1e-5 && p.y.abs() <= -p.z + 1e-5, "{p}");
        }
        // A camera beside the light is inside.
        let near = View { world_from_view: Mat4::from_translation(Vec3::new(0.5, 1.0, 0.0)), ..view };
        assert!(light_volume(&light, 5.0, &near, 0).camera_inside);
    }
}
