//! Cascades for a directional light: the view frustum up to the max shadow distance is cut
//! into slices, each gets a culling sphere, and each sphere becomes an orthographic
//! projection along the light, snapped to whole texels so shadows hold still.

use crate::bounds::Sphere;
use glam::{Mat4, Vec3};

/// Far distance of each cascade: `ratios[i] * max_distance`, the last at `max_distance`.
/// With the defaults (0.1, 0.25, 0.5) and 100 m: 10, 25, 50, 100 m.
pub fn cascade_splits(max_distance: f32, ratios: [f32; 3], count: usize) -> Vec<f32> {
    (0..count).map(|i| if i + 1 == count { max_distance } else { ratios[i] * max_distance }).collect()
}

/// The smallest sphere around the slice of a symmetric perspective frustum between view
/// depths `near` and `far`, in view space (the camera looks down -Z). Its radius depends
/// only on the slice's shape, never on the camera's orientation, which is what keeps a
/// cascade's texel size fixed as the camera turns.
///
/// `tan_half_fov_y` and `aspect` give each slice's corner at depth d a distance of
/// `d * k` from the axis, `k = tan_half_fov_y * sqrt(1 + aspect²)`. The centre lies on the
/// axis where near and far corners are equally far, clamped to the far plane when the far
/// corners alone decide.
pub fn slice_culling_sphere(near: f32, far: f32, tan_half_fov_y: f32, aspect: f32) -> Sphere {
    let k = tan_half_fov_y * (1.0 + aspect * aspect).sqrt();
    let (a, b) = (near * k, far * k);
    let z = ((far * far - near * near + b * b - a * a) / (2.0 * (far - near))).clamp(near, far);
    let radius = ((z - near).powi(2) + a * a).sqrt().max(((far - z).powi(2) + b * b).sqrt());
    Sphere { center: Vec3::new(0.0, 0.0, -z), radius }
}

/// The smallest sphere around the box an orthographic view's slice from `near` to `far`
/// spans (view space, the view `2 * xmag` by `2 * ymag` metres): centred on the axis
/// halfway between, reaching the corners.
pub fn orthographic_slice_culling_sphere(near: f32, far: f32, xmag: f32, ymag: f32) -> Sphere {
    let half_depth = 0.5 * (far - near);
    Sphere {
        center: Vec3::new(0.0, 0.0, -0.5 * (near + far)),
        radius: (xmag * xmag + ymag * ymag + half_depth * half_depth).sqrt(),
    }
}

/// Everything the GPU needs about one cascade of one light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CascadeFit {
    /// World-space culling sphere, centre snapped to texels.
    pub sphere: Sphere,
    /// Clip-from-world of the orthographic shadow projection (wgpu depth 0..1, near at 0).
    pub clip_from_world: Mat4,
    /// World-space size of one texel.
    pub texel_size_ws: f32,
}

/// Fits an orthographic projection along `light_direction` (the way light travels) around
/// `sphere`, for a tile of `tile_size` texels. The sphere's centre is snapped to whole
/// texels in light space, so a small camera move leaves the projection unchanged or moves
/// it by whole texels. `near_plane_offset` pulls the near plane towards the light so that
/// casters just outside the sphere still land in front of it (depth clamping flattens
/// those further out onto the near plane).
pub fn fit_cascade(sphere: Sphere, light_direction: Vec3, tile_size: u32, near_plane_offset: f32) -> CascadeFit {
    let dir = light_direction.normalize();
    let up = if dir.y.abs() > 0.99 { Vec3::Z } else { Vec3::Y };
    // Light space without translation: the snapping grid is anchored at the world origin.
    let light_from_world = Mat4::look_to_rh(Vec3::ZERO, dir, up);
    let texel = 2.0 * sphere.radius / tile_size as f32;
    let center_ls = light_from_world.transform_point3(sphere.center);
    let snapped_ls =
        Vec3::new((center_ls.x / texel).floor() * texel, (center_ls.y / texel).floor() * texel, center_ls.z);
    let center = light_from_world.inverse().transform_point3(snapped_ls);
    let r = sphere.radius;
    // The eye sits on the light's side of the sphere, looking along the light.
    let near_offset = near_plane_offset.max(0.0);
    let view = Mat4::look_to_rh(center - dir * (r + near_offset), dir, up);
    let projection = Mat4::orthographic_rh(-r, r, -r, r, 0.0, 2.0 * r + near_offset);
    CascadeFit { sphere: Sphere { center, radius: r }, clip_from_world: projection * view, texel_size_ws: texel }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn splits_follow_the_ratios() {
        assert_eq!(cascade_splits(100.0, [0.1, 0.25, 0.5], 4), vec![10.0, 25.0, 50.0, 100.0]);
        assert_eq!(cascade_splits(100.0, [0.1, 0.25, 0.5], 2), vec![10.0, 100.0]);
        assert_eq!(cascade_splits(40.0, [0.1, 0.25, 0.5], 1), vec![40.0]);
    }

    fn slice_corners(near: f32, far: f32, t: f32, aspect: f32) -> Vec<Vec3> {
        let mut c = Vec::new();
        for d in [near, far] {
            for (sx, sy) in [(-1.0, -1.0), (1.0, -1.0), (-1.0, 1.0), (1.0, 1.0)] {
                c.push(Vec3::new(sx * d * t * aspect, sy * d * t, -d));
            }
        }
        c
    }

    proptest! {
        #[test]
        fn culling_spheres_contain_their_slices(near in 0.05f32..50.0, depth in 0.1f32..100.0, fov_deg in 10.0f32..120.0, aspect in 0.3f32..3.0) {
            let far = near + depth;
            let t = (fov_deg.to_radians() * 0.5).tan();
            let s = slice_culling_sphere(near, far, t, aspect);
            for c in slice_corners(near, far, t, aspect) {
                prop_assert!(c.distance(s.center) <= s.radius * (1.0 + 1e-4) + 1e-4);
            }
        }

        #[test]
        fn orthographic_culling_spheres_hold_their_slice_boxes_tightly(near in 0.05f32..50.0, depth in 0.1f32..100.0, ymag in 0.1f32..50.0, aspect in 0.3f32..3.0) {
            let (far, xmag) = (near + depth, ymag * aspect);
            let s = orthographic_slice_culling_sphere(near, far, xmag, ymag);
            let mut farthest = 0.0f32;
            for d in [near, far] {
                for (sx, sy) in [(-1.0, -1.0), (1.0, -1.0), (-1.0, 1.0), (1.0, 1.0)] {
                    farthest = farthest.max(Vec3::new(sx * xmag, sy * ymag, -d).distance(s.center));
                }
            }
            prop_assert!(farthest <= s.radius * (1.0 + 1e-5) && farthest >= s.radius * (1.0 - 1e-5));
        }

        #[test]
        fn sub_texel_camera_moves_leave_snapped_cascades_still(x in -50.0f32..50.0, z in -50.0f32..50.0, jitter in 0.0f32..1.0) {
            let dir = Vec3::new(-0.3, -1.0, -0.4).normalize();
            let sphere = Sphere { center: Vec3::new(x, 1.0, z), radius: 10.0 };
            let fit = fit_cascade(sphere, dir, 1024, 0.0);
            // Moving the sphere by a fraction of a texel across the light moves the
            // snapped projection by zero or one whole texel, never by a fraction.
            let across = dir.cross(Vec3::Y).normalize();
            let moved = Sphere { center: sphere.center + across * fit.texel_size_ws * 0.5 * jitter, ..sphere };
            let fit2 = fit_cascade(moved, dir, 1024, 0.0);
            let probe = Vec3::new(3.0, 0.0, -2.0);
            let a = fit.clip_from_world.project_point3(probe);
            let b = fit2.clip_from_world.project_point3(probe);
            let texels = (a - b).truncate() * 512.0; // clip spans 2 over 1024 texels
            for v in [texels.x, texels.y] {
                prop_assert!((v - v.round()).abs() < 0.02, "moved by {v} texels");
                prop_assert!(v.abs() <= 1.01);
            }
        }
    }

    #[test]
    fn cascade_projection_holds_its_sphere() {
        let dir = Vec3::new(0.2, -1.0, 0.1).normalize();
        let sphere = Sphere { center: Vec3::new(4.0, 2.0, -7.0), radius: 6.0 };
        let fit = fit_cascade(sphere, dir, 2048, 2.0);
        for axis in [Vec3::X, Vec3::Y, Vec3::Z, -Vec3::X, -Vec3::Y, -Vec3::Z] {
            // Inner points of the sphere (one texel of snapping slack) map inside clip space.
            let p = sphere.center + axis * (sphere.radius - 2.0 * fit.texel_size_ws);
            let c = fit.clip_from_world.project_point3(p);
            assert!(c.x.abs() <= 1.0 && c.y.abs() <= 1.0, "{axis}: {c}");
            assert!((0.0..=1.0).contains(&c.z), "{axis}: depth {}", c.z);
        }
        // Depth grows away from the light.
        let near = fit.clip_from_world.project_point3(sphere.center - dir * 3.0).z;
        let far = fit.clip_from_world.project_point3(sphere.center + dir * 3.0).z;
        assert!(near < far);
    }
}
