//! Camera projections and automatic framing of a scene's bounds.
//!
//! Chiaro renders with reverse-Z (near at depth 1, far at 0), which spreads float depth
//! precision evenly; with no far plane the projection is infinite.

use crate::bounds::Aabb;
use glam::{Mat4, Vec3};

/// Clip-from-view for a perspective camera, reverse-Z, with an optional far plane.
pub fn perspective_reverse_z(yfov_rad: f32, aspect: f32, znear: f32, zfar: Option<f32>) -> Mat4 {
    match zfar {
        // Swapping near and far in a standard [0, 1] projection gives reverse-Z.
        Some(far) => Mat4::perspective_rh(yfov_rad, aspect, far, znear),
        None => Mat4::perspective_infinite_reverse_rh(yfov_rad, aspect, znear),
    }
}

/// Bounding-sphere radii, metres, that `frame_bounds` frames: below the smallest, f32
/// squares underflow; beyond the largest, they overflow.
pub const FRAMEABLE_RADIUS_M: std::ops::RangeInclusive<f32> = 1.0e-6..=1.0e15;

/// Whether `frame_bounds` can frame `bounds` (empty bounds get a unit view).
pub fn can_frame(bounds: &Aabb) -> bool {
    if bounds.is_empty() {
        return true;
    }
    let s = bounds.bounding_sphere();
    FRAMEABLE_RADIUS_M.contains(&s.radius) && s.center.abs().max_element() <= *FRAMEABLE_RADIUS_M.end()
}

/// A camera placed to see all of `bounds`: looking at its centre from above and in front
/// (a three-quarter view down the -Z axis), far enough that its bounding sphere fits the
/// narrower field of view. Returns `(world_from_view, znear, zfar)`. Bounds that
/// `can_frame` refuses are framed as well as f32 allows, which may be not at all.
pub fn frame_bounds(bounds: &Aabb, yfov_rad: f32, aspect: f32) -> (Mat4, f32, f32) {
    let (center, radius) = if bounds.is_empty() {
        (Vec3::ZERO, 1.0)
    } else {
        let s = bounds.bounding_sphere();
        (s.center, s.radius.max(*FRAMEABLE_RADIUS_M.start()))
    };
    let xfov = 2.0 * ((yfov_rad * 0.5).tan() * aspect).atan();
    let half_fov = 0.5 * yfov_rad.min(xfov);
    let distance = radius / half_fov.sin();
    let direction = Vec3::new(0.0, 0.5, 1.0).normalize();
    let eye = center + direction * distance;
    let view_from_world = Mat4::look_at_rh(eye, center, Vec3::Y);
    let znear = (distance - radius).max(distance * 1.0e-3);
    let zfar = distance + radius * 2.0;
    (view_from_world.inverse(), znear, zfar)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Sphere;
    use crate::frustum::Frustum;

    #[test]
    fn reverse_z_maps_near_to_one_and_far_to_zero() {
        let p = perspective_reverse_z(1.0, 1.5, 0.5, Some(50.0));
        let near = p.project_point3(Vec3::new(0.0, 0.0, -0.5));
        let far = p.project_point3(Vec3::new(0.0, 0.0, -50.0));
        assert!((near.z - 1.0).abs() < 1e-5 && far.z.abs() < 1e-5);
        let inf = perspective_reverse_z(1.0, 1.5, 0.5, None);
        assert!((inf.project_point3(Vec3::new(0.0, 0.0, -0.5)).z - 1.0).abs() < 1e-5);
        assert!(inf.project_point3(Vec3::new(0.0, 0.0, -1e6)).z < 1e-5);
    }

    #[test]
    fn framed_bounds_are_inside_the_frustum() {
        let box_at =
            |scale: f32| Aabb::from_points([Vec3::new(-3.0, 0.0, -1.0) * scale, Vec3::new(5.0, 2.0, 4.0) * scale]);
        for (bounds, aspect) in
            [(box_at(1.0), 0.5f32), (box_at(1.0), 1.0), (box_at(1.0), 2.0), (box_at(1e-6), 1.0), (box_at(1e14), 1.0)]
        {
            assert!(can_frame(&bounds));
            let yfov = 0.8;
            let (world_from_view, near, far) = frame_bounds(&bounds, yfov, aspect);
            let clip = perspective_reverse_z(yfov, aspect, near, Some(far)) * world_from_view.inverse();
            let f = Frustum::from_clip_from_world(&clip);
            for c in bounds.corners() {
                let inside = f.intersects_sphere(&Sphere { center: c, radius: 0.0 });
                assert!(inside, "corner {c} outside for aspect {aspect}");
            }
        }
        assert!(!can_frame(&box_at(1e19)) && !can_frame(&box_at(1e-9)));
    }
}
