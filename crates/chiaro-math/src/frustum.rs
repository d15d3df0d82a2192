//! View frusta as six planes, for culling light volumes against what the camera sees.

use crate::bounds::Sphere;
use glam::{Mat4, Vec3, Vec4};

/// Six inward-facing planes `(normal, d)` with `dot(normal, p) + d >= 0` inside.
#[derive(Clone, Copy, Debug)]
pub struct Frustum {
    pub planes: [Vec4; 6],
}

impl Frustum {
    /// Planes of a clip-from-world matrix with wgpu's clip space (z in [0, 1]). The far
    /// plane is dropped when the projection has none (infinite or reverse-Z infinite),
    /// which shows up as a degenerate plane and is replaced by one that accepts everything.
    pub fn from_clip_from_world(m: &Mat4) -> Frustum {
        let r0 = m.row(0);
        let r1 = m.row(1);
        let r2 = m.row(2);
        let r3 = m.row(3);
        let raw = [r3 + r0, r3 - r0, r3 + r1, r3 - r1, r2, r3 - r2];
        let planes = raw.map(|p| {
            let len = p.truncate().length();
            if len < 1e-12 || !len.is_finite() { Vec4::new(0.0, 0.0, 0.0, 1.0) } else { p / len }
        });
        Frustum { planes }
    }

    /// Whether the box reaches inside the four side planes (left, right, bottom, top),
    /// near and far ignored. For a perspective frustum these planes meet at the eye, so
    /// the test is exact for boxes behind it too: they lie outside.
    pub fn sides_hold_aabb(&self, bounds: &crate::Aabb) -> bool {
        !bounds.is_empty()
            && self.planes[..4].iter().all(|p| {
                let n = p.truncate();
                // The corner furthest along the plane's normal.
                let far_corner = Vec3::select(n.cmpge(Vec3::ZERO), bounds.max, bounds.min);
                n.dot(far_corner) + p.w >= 0.0
            })
    }

    pub fn intersects_sphere(&self, sphere: &Sphere) -> bool {
        self.planes.iter().all(|p| p.truncate().dot(sphere.center) + p.w >= -sphere.radius)
    }

    /// Conservative test for a spot light's cone: its apex at `apex`, unit `axis`, half
    /// angle `outer_rad` and length `range`. Uses the sphere around the cone
    /// (Real-Time Rendering 4th ed., 22.7), tighter than the range sphere for narrow cones.
    pub fn intersects_cone(&self, apex: Vec3, axis: Vec3, outer_rad: f32, range: f32) -> bool {
        self.intersects_sphere(&cone_bounding_sphere(apex, axis, outer_rad, range))
    }
}

/// Smallest sphere around a cone of length `range` (along `axis`) and half angle `outer_rad`.
pub fn cone_bounding_sphere(apex: Vec3, axis: Vec3, outer_rad: f32, range: f32) -> Sphere {
    if outer_rad > std::f32::consts::FRAC_PI_4 {
        // Wide cones: the sphere through the rim, centred on the cap's centre.
        let (s, c) = outer_rad.sin_cos();
        Sphere { center: apex + axis * (c * range), radius: s * range }
    } else {
        // Narrow cones: the sphere through apex and rim.
        let radius = range / (2.0 * outer_rad.cos());
        Sphere { center: apex + axis * radius, radius }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn side_planes_keep_boxes_in_front_and_cull_boxes_beside_or_behind_the_eye() {
        // A 90 degree face looking down -Z from the origin, as a point light's cube face.
        let clip = Mat4::perspective_rh(90f32.to_radians(), 1.0, 0.01, 10.0)
            * Mat4::look_to_rh(Vec3::ZERO, Vec3::NEG_Z, Vec3::Y);
        let f = Frustum::from_clip_from_world(&clip);
        let cube = |c: Vec3| crate::Aabb::from_points([c - 0.25, c + 0.25]);
        assert!(f.sides_hold_aabb(&cube(Vec3::new(0.0, 0.0, -2.0))));
        assert!(f.sides_hold_aabb(&cube(Vec3::new(1.9, 0.0, -2.0))), "straddles the side plane");
        assert!(!f.sides_hold_aabb(&cube(Vec3::new(3.0, 0.0, -2.0))), "beside the face");
        assert!(!f.sides_hold_aabb(&cube(Vec3::new(0.0, 0.0, 2.0))), "behind the eye");
        assert!(f.sides_hold_aabb(&cube(Vec3::new(0.0, 0.0, -0.1))), "touching the eye");
        assert!(f.sides_hold_aabb(&cube(Vec3::new(0.0, 0.0, -50.0))), "far is ignored");
    }

    fn camera() -> Mat4 {
        let proj = Mat4::perspective_rh(60f32.to_radians(), 1.0, 0.1, 100.0);
        let view = Mat4::look_at_rh(Vec3::ZERO, Vec3::NEG_Z, Vec3::Y);
        proj * view
    }

    #[test]
    fn spheres_in_front_pass_and_behind_fail() {
        let f = Frustum::from_clip_from_world(&camera());
        let s = |c: Vec3, r: f32| Sphere { center: c, radius: r };
        assert!(f.intersects_sphere(&s(Vec3::new(0.0, 0.0, -10.0), 1.0)));
        assert!(!f.intersects_sphere(&s(Vec3::new(0.0, 0.0, 10.0), 1.0)));
        // Behind, but its range reaches into view.
        assert!(f.intersects_sphere(&s(Vec3::new(0.0, 0.0, 2.0), 3.0)));
        assert!(!f.intersects_sphere(&s(Vec3::new(0.0, 0.0, -200.0), 1.0)));
        assert!(!f.intersects_sphere(&s(Vec3::new(50.0, 0.0, -10.0), 1.0)));
    }

    #[test]
    fn infinite_reverse_z_keeps_distant_spheres() {
        let proj = Mat4::perspective_infinite_reverse_rh(60f32.to_radians(), 1.0, 0.1);
        let view = Mat4::look_at_rh(Vec3::ZERO, Vec3::NEG_Z, Vec3::Y);
        let f = Frustum::from_clip_from_world(&(proj * view));
        let far = Sphere { center: Vec3::new(0.0, 0.0, -1.0e5), radius: 1.0 };
        assert!(f.intersects_sphere(&far));
        let behind = Sphere { center: Vec3::new(0.0, 0.0, 5.0), radius: 1.0 };
        assert!(!f.intersects_sphere(&behind));
    }

    #[test]
    fn cone_sphere_holds_apex_and_rim() {
        for deg in [5.0f32, 30.0, 44.0, 46.0, 80.0] {
            let outer = deg.to_radians();
            let axis = Vec3::new(0.3, -1.0, 0.2).normalize();
            let apex = Vec3::new(1.0, 2.0, 3.0);
            let s = cone_bounding_sphere(apex, axis, outer, 10.0);
            let perp = axis.any_orthonormal_vector();
            let rim = apex + (axis * outer.cos() + perp * outer.sin()) * 10.0;
            assert!(apex.distance(s.center) <= s.radius + 1e-4, "{deg}");
            assert!(rim.distance(s.center) <= s.radius + 1e-4, "{deg}");
            assert!(s.radius <= 10.0 + 1e-4);
        }
    }
}
