//! Shadow math for local (point and spot) lights, as the Custom SRP "Point and Spot
//! Shadows" tutorial builds it: tiles in a second atlas (one per spot, six per point, one
//! per cube face), perspective projections, the cube face a direction falls on, the field
//! of view widened so filtering near a face edge stays inside the tile, and the normal bias
//! for a surface at distance 1 from the light plane (the shader scales it by distance).

use super::filter::ShadowFilter;
use glam::{Mat4, Vec3};

/// Tiles of the local-light atlas.
pub const MAX_LOCAL_SHADOW_TILES: usize = 64;
/// Cube faces of a point light, one tile each.
pub const POINT_LIGHT_FACES: usize = 6;

/// Unit axes of the cube faces in tile order +X, -X, +Y, -Y, +Z, -Z: the direction from the
/// light into the face, and an up vector for the face's view.
pub const CUBE_FACES: [(Vec3, Vec3); POINT_LIGHT_FACES] = [
    (Vec3::X, Vec3::Y),
    (Vec3::NEG_X, Vec3::Y),
    (Vec3::Y, Vec3::Z),
    (Vec3::NEG_Y, Vec3::NEG_Z),
    (Vec3::Z, Vec3::Y),
    (Vec3::NEG_Z, Vec3::Y),
];

/// Near plane of spot and point shadow projections when the light asks for none, metres.
/// Casters closer to the light are clipped. With float depth the precision at distance d
/// is about 6e-8 d² / near: 1 cm gives 0.4 mm at 8 m and 6 cm at 100 m, below the
/// shadow texel there (39 cm for a 512-texel face), so the biases cover it; 5 cm used to
/// clip a plate 3 cm from a point light.
pub const MIN_LOCAL_NEAR_PLANE: f32 = 0.01;

/// Tiles a light asks for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LocalShadowRequest {
    Spot,
    Point,
}

impl LocalShadowRequest {
    pub fn tiles(self) -> usize {
        match self {
            LocalShadowRequest::Spot => 1,
            LocalShadowRequest::Point => POINT_LIGHT_FACES,
        }
    }
}

/// The cube face (index into `CUBE_FACES`) that a light-to-surface direction falls on: its
/// largest component, ties going to X, then Y. The shader's `cube_face` is the same.
pub fn cube_face(direction: Vec3) -> usize {
    let a = direction.abs();
    if a.x >= a.y && a.x >= a.z {
        if direction.x >= 0.0 { 0 } else { 1 }
    } else if a.y >= a.z {
        if direction.y >= 0.0 { 2 } else { 3 }
    } else if direction.z >= 0.0 {
        4
    } else {
        5
    }
}

/// Full field of view of a point light's face, widened from 90 degrees so that the normal
/// bias and the filter's reach near the face's edge still sample inside the tile:
/// `2 atan(1 + bias + filter)` with both in clip-space units of a 90 degree tile
/// (the tutorial's FOV bias). A 512 tile, 2x2 filter, normal bias 1: texel 2/512,
/// filter 0.0039, bias 0.0055, fov 90.54 degrees.
pub fn point_face_fov_rad(tile_size: u32, filter: ShadowFilter, normal_bias: f32) -> f32 {
    let texel = 2.0 / tile_size as f32;
    let filter_size = texel * filter.footprint_texels();
    let bias = normal_bias * filter_size * std::f32::consts::SQRT_2;
    2.0 * (1.0 + bias + filter_size).atan()
}

/// Normal bias (world units per metre of distance from the light plane) of a perspective
/// tile: a texel at distance 1 spans `2 / (tile_size * proj[0][0])`; times the filter's
/// reach and sqrt(2) for the texel diagonal.
pub fn perspective_normal_bias(tile_size: u32, clip_from_view: &Mat4, filter: ShadowFilter) -> f32 {
    let texel_at_unit_distance = 2.0 / (tile_size as f32 * clip_from_view.x_axis.x);
    texel_at_unit_distance * filter.footprint_texels() * std::f32::consts::SQRT_2
}

/// A perspective shadow view (wgpu depth 0 at the near plane, 1 at `range`): returns
/// (clip_from_view, clip_from_world).
fn perspective_view(position: Vec3, forward: Vec3, up: Vec3, fov_rad: f32, near: f32, range: f32) -> (Mat4, Mat4) {
    let near = near.max(MIN_LOCAL_NEAR_PLANE);
    let far = range.max(near * 2.0);
    let clip_from_view = Mat4::perspective_rh(fov_rad, 1.0, near, far);
    (clip_from_view, clip_from_view * Mat4::look_to_rh(position, forward, up))
}

/// The spot's tile: a perspective projection fitted to the outer cone.
pub fn spot_shadow_view(position: Vec3, direction: Vec3, outer_rad: f32, near: f32, range: f32) -> (Mat4, Mat4) {
    let forward = direction.normalize();
    let up = if forward.y.abs() > 0.99 { Vec3::Z } else { Vec3::Y };
    perspective_view(position, forward, up, (2.0 * outer_rad).min(179f32.to_radians()), near, range)
}

/// A face counts as facing a one-sided (area) light when its axis lies within 60 degrees
/// of the light's direction (cosine 0.5): a Lambertian emitter sends three quarters of
/// its flux (sin^2 60) within that cone, so these faces hold most of what it lights.
pub const FACING_FACE_COSINE: f32 = 0.5;

/// The cube faces (indices into `CUBE_FACES`) that a one-sided light shining towards
/// `direction` faces, most aligned first: at most three (one for a light pointing along
/// an axis). The atlas gives these finer tiles where it has room (tiers::double_facing_tiles).
pub fn facing_faces(direction: Vec3) -> Vec<usize> {
    let d = direction.normalize_or_zero();
    let mut faces: Vec<(usize, f32)> = CUBE_FACES
        .iter()
        .enumerate()
        .map(|(face, (axis, _))| (face, axis.dot(d)))
        .filter(|&(_, cosine)| cosine > FACING_FACE_COSINE)
        .collect();
    faces.sort_by(|a, b| b.1.total_cmp(&a.1).then(a.0.cmp(&b.0)));
    faces.into_iter().map(|(face, _)| face).collect()
}

/// One face of a point light's cube.
pub fn point_face_view(position: Vec3, face: usize, fov_rad: f32, near: f32, range: f32) -> (Mat4, Mat4) {
    let (forward, up) = CUBE_FACES[face];
    perspective_view(position, forward, up, fov_rad, near, range)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn face_selection_on_and_near_every_boundary() {
        for (face, (axis, _)) in CUBE_FACES.iter().enumerate() {
            assert_eq!(cube_face(*axis), face);
            // Just inside the face, next to each of its four edges.
            for (other, _) in CUBE_FACES.iter().filter(|(o, _)| o.dot(*axis) == 0.0) {
                let d = *axis + *other * 0.999;
                assert_eq!(cube_face(d), face, "{d}");
                let across = *axis * 0.999 + *other;
                assert_ne!(cube_face(across), face, "{across}");
            }
        }
        // Exact ties resolve X before Y before Z, as in the shader.
        assert_eq!(cube_face(Vec3::new(1.0, 1.0, 1.0)), 0);
        assert_eq!(cube_face(Vec3::new(0.0, -1.0, 1.0)), 3);
        assert_eq!(cube_face(Vec3::new(-1.0, 0.0, -1.0)), 1);
    }

    #[test]
    fn a_one_sided_light_faces_the_faces_within_sixty_degrees_of_its_direction() {
        // Straight down: the -Y face alone; the side faces lie at 90 degrees.
        assert_eq!(facing_faces(Vec3::NEG_Y), vec![3]);
        // Tilted 37 degrees towards +X: -Y (cosine 0.8) before +X (0.6).
        assert_eq!(facing_faces(Vec3::new(0.6, -0.8, 0.0)), vec![3, 0]);
        // Along a cube diagonal all three faces around it (cosine 0.577), in axis order.
        assert_eq!(facing_faces(Vec3::new(1.0, -1.0, -1.0)), vec![0, 3, 5]);
        // Barely off an axis adds no face: 0.5 is not enough.
        assert_eq!(facing_faces(Vec3::new(0.05, 0.0, 1.0)), vec![4]);
        assert!(facing_faces(Vec3::ZERO).is_empty());
    }

    #[test]
    fn every_face_view_sees_its_own_directions() {
        let fov = point_face_fov_rad(512, ShadowFilter::Pcf2x2, 1.0);
        let light = Vec3::new(1.0, 2.0, 3.0);
        for (face, (axis, _)) in CUBE_FACES.iter().enumerate() {
            let (_, clip_from_world) = point_face_view(light, face, fov, 0.05, 10.0);
            let p = clip_from_world.project_point3(light + *axis * 2.0);
            assert!(p.x.abs() < 1e-4 && p.y.abs() < 1e-4 && (0.0..1.0).contains(&p.z), "{face}: {p}");
        }
    }

    #[test]
    fn fov_bias_widens_with_bias_and_filter() {
        let base = point_face_fov_rad(512, ShadowFilter::Pcf2x2, 0.0);
        assert!(base > 90f32.to_radians());
        let texel: f32 = 2.0 / 512.0;
        assert!((base - 2.0 * (1.0 + texel).atan()).abs() < 1e-6);
        assert!(point_face_fov_rad(512, ShadowFilter::Pcf2x2, 2.0) > base);
        assert!(point_face_fov_rad(512, ShadowFilter::Tent7x7, 0.0) > base);
        assert!(point_face_fov_rad(4096, ShadowFilter::Pcf2x2, 0.0) < base);
    }

    #[test]
    fn perspective_normal_bias_is_a_texel_at_unit_distance() {
        let (clip_from_view, _) = spot_shadow_view(Vec3::ZERO, Vec3::NEG_Y, 45f32.to_radians(), 0.1, 10.0);
        // 90 degree cone: proj[0][0] = 1, so a texel at distance 1 is 2 / 512.
        let b = perspective_normal_bias(512, &clip_from_view, ShadowFilter::Pcf2x2);
        assert!((b - 2.0 / 512.0 * std::f32::consts::SQRT_2).abs() < 1e-6);
        let wide = perspective_normal_bias(512, &clip_from_view, ShadowFilter::Tent5x5);
        assert!((wide / b - 3.0).abs() < 1e-5);
    }

    #[test]
    fn spot_projection_covers_the_outer_cone() {
        let dir = Vec3::new(0.3, -1.0, 0.2).normalize();
        let outer = 35f32.to_radians();
        let (_, clip) = spot_shadow_view(Vec3::new(0.0, 4.0, 0.0), dir, outer, 0.1, 20.0);
        let perp = dir.any_orthonormal_vector();
        let rim = Vec3::new(0.0, 4.0, 0.0) + (dir * outer.cos() + perp * outer.sin() * 0.999) * 5.0;
        let p = clip.project_point3(rim);
        assert!(p.x.abs() <= 1.0 && p.y.abs() <= 1.0 && (0.0..=1.0).contains(&p.z), "{p}");
    }
}
