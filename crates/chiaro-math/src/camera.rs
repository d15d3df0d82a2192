//! Camera projections, cameras placed by eye and target, and automatic framing of a
//! scene's bounds.
//!
//! Chiaro renders with reverse-Z (near at depth 1, far at 0), which spreads float depth
//! precision evenly; with no far plane a perspective projection is infinite. Orthographic
//! cameras (glTF's xmag, ymag) always have a far plane.

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

/// Clip-from-view for an orthographic camera, reverse-Z: the view's half width `xmag` and
/// half height `ymag` in metres (glTF's names) map to NDC ±1, the near plane to depth 1
/// and the far plane to 0.
pub fn orthographic_reverse_z(xmag: f32, ymag: f32, znear: f32, zfar: f32) -> Mat4 {
    // As for perspective: swapping near and far in the [0, 1] projection gives reverse-Z.
    Mat4::orthographic_rh(-xmag, xmag, -ymag, ymag, zfar, znear)
}

/// How a camera projects: what stays fixed when the image's aspect changes. Either way the
/// image's width follows from its height and the output's aspect ratio.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Projection {
    /// A pinhole with a vertical field of view, radians.
    Perspective { yfov_rad: f32 },
    /// Parallel rays over a view `2 * ymag` metres high (glTF's `ymag`).
    Orthographic { ymag: f32 },
}

impl Projection {
    /// Reverse-Z clip-from-view for an image of `aspect` (width over height). An
    /// orthographic projection without a far plane gets one a million near planes out,
    /// the nearest thing to infinite a linear depth keeps precision for.
    pub fn clip_from_view(&self, aspect: f32, znear: f32, zfar: Option<f32>) -> Mat4 {
        match *self {
            Projection::Perspective { yfov_rad } => perspective_reverse_z(yfov_rad, aspect, znear, zfar),
            Projection::Orthographic { ymag } => {
                orthographic_reverse_z(ymag * aspect, ymag, znear, zfar.unwrap_or(znear * 1.0e6))
            }
        }
    }

    /// Whether the camera's rays are parallel.
    pub fn is_orthographic(&self) -> bool {
        matches!(self, Projection::Orthographic { .. })
    }

    /// The vertical field of view in radians, `None` for an orthographic camera.
    pub fn yfov_rad(&self) -> Option<f32> {
        match *self {
            Projection::Perspective { yfov_rad } => Some(yfov_rad),
            Projection::Orthographic { .. } => None,
        }
    }
}

/// A perspective (or, with `ymag`, orthographic) camera placed at `eye` looking at `target` (metres, world space), `up`
/// giving the image's up direction, with a vertical field of view and clip planes. The
/// Python package's `Camera.look_at` and the job lists of `chiaro batch` both make views
/// this way, with the same checks and messages.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LookAt {
    pub eye: Vec3,
    pub target: Vec3,
    pub up: Vec3,
    pub yfov_deg: f32,
    /// `Some` for an orthographic camera: half the view's height in metres (`yfov_deg`
    /// is then unused); it needs a far plane.
    pub ymag: Option<f32>,
    pub znear: f32,
    /// `None` for an infinite projection.
    pub zfar: Option<f32>,
}

/// Why a `LookAt` places no camera; the message names the value at fault.
#[derive(Clone, Debug, PartialEq)]
pub enum LookAtError {
    /// `eye`, `target` or `up` (named) has a NaN or infinite component.
    NotFinite(&'static str, Vec3),
    /// The eye is on the target: there is no viewing direction.
    SamePoint,
    /// `up` is zero or along the viewing direction: the image's roll is undefined.
    UpParallel,
    /// The field of view is not inside (0, 180) degrees.
    BadFov(f32),
    /// The near plane is not a positive distance.
    BadNear(f32),
    /// The far plane is not beyond the near plane.
    BadFar { far: f32, near: f32 },
    /// An orthographic view height that is not a positive distance.
    BadYmag(f32),
    /// An orthographic camera without a far plane.
    OrthographicWithoutFar,
}

impl std::fmt::Display for LookAtError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            LookAtError::NotFinite(name, v) => write!(f, "{name}: {v} is not finite"),
            LookAtError::SamePoint => write!(f, "look_at: eye and target are the same point"),
            LookAtError::UpParallel => write!(f, "look_at: up is zero or parallel to the viewing direction"),
            LookAtError::BadFov(deg) => write!(f, "yfov_deg: {deg} is not between 0 and 180 degrees"),
            LookAtError::BadNear(near) => write!(f, "znear: {near} is not positive"),
            LookAtError::BadFar { far, near } => write!(f, "zfar: {far} is not beyond znear ({near})"),
            LookAtError::BadYmag(ymag) => write!(f, "ymag: {ymag} is not a positive distance"),
            LookAtError::OrthographicWithoutFar => write!(f, "zfar: an orthographic camera (ymag) needs a far plane"),
        }
    }
}

impl std::error::Error for LookAtError {}

impl LookAt {
    /// The camera's pose, view space (-Z forward, +Y up) to world space, once every value
    /// is checked.
    pub fn world_from_view(&self) -> Result<Mat4, LookAtError> {
        for (name, v) in [("eye", self.eye), ("target", self.target), ("up", self.up)] {
            if !v.is_finite() {
                return Err(LookAtError::NotFinite(name, v));
            }
        }
        let forward = self.target - self.eye;
        if forward.length() < 1e-9 {
            return Err(LookAtError::SamePoint);
        }
        if self.up.length() < 1e-9 || forward.normalize().cross(self.up.normalize()).length() < 1e-6 {
            return Err(LookAtError::UpParallel);
        }
        match self.ymag {
            None if !(self.yfov_deg > 0.0 && self.yfov_deg < 180.0) => return Err(LookAtError::BadFov(self.yfov_deg)),
            Some(ymag) if !(ymag.is_finite() && ymag > 0.0) => return Err(LookAtError::BadYmag(ymag)),
            Some(_) if self.zfar.is_none() => return Err(LookAtError::OrthographicWithoutFar),
            _ => {}
        }
        if !(self.znear.is_finite() && self.znear > 0.0) {
            return Err(LookAtError::BadNear(self.znear));
        }
        if let Some(far) = self.zfar
            && !(far.is_finite() && far > self.znear)
        {
            return Err(LookAtError::BadFar { far, near: self.znear });
        }
        Ok(Mat4::look_at_rh(self.eye, self.target, self.up).inverse())
    }

    /// The camera's projection: orthographic with `ymag`, else perspective.
    pub fn projection(&self) -> Projection {
        match self.ymag {
            Some(ymag) => Projection::Orthographic { ymag },
            None => Projection::Perspective { yfov_rad: self.yfov_deg.to_radians() },
        }
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
    fn orthographic_reverse_z_maps_the_view_box_to_the_unit_cube_near_at_one() {
        let p = orthographic_reverse_z(3.0, 2.0, 0.5, 50.0);
        let corner_near = p.project_point3(Vec3::new(3.0, 2.0, -0.5));
        let corner_far = p.project_point3(Vec3::new(-3.0, -2.0, -50.0));
        assert!((corner_near - Vec3::new(1.0, 1.0, 1.0)).length() < 1e-5, "{corner_near}");
        assert!((corner_far - Vec3::new(-1.0, -1.0, 0.0)).length() < 1e-5, "{corner_far}");
        // Parallel rays: a point's NDC x and y do not depend on its depth.
        let (a, b) = (p.project_point3(Vec3::new(1.0, 1.0, -1.0)), p.project_point3(Vec3::new(1.0, 1.0, -40.0)));
        assert!((a.truncate() - b.truncate()).length() < 1e-6);
        let from_projection = Projection::Orthographic { ymag: 2.0 }.clip_from_view(1.5, 0.5, Some(50.0));
        assert!(from_projection.abs_diff_eq(p, 1e-6), "ymag fixed, the width follows the aspect");
        let unbounded = Projection::Orthographic { ymag: 2.0 }.clip_from_view(1.5, 0.5, None);
        assert!(unbounded.project_point3(Vec3::new(0.0, 0.0, -1.0e5)).z > 0.0, "a far plane far out");
    }

    #[test]
    fn a_look_at_camera_sees_its_target_ahead_and_refuses_what_places_none() {
        let camera = LookAt {
            eye: Vec3::new(3.0, 5.0, 6.0),
            target: Vec3::ZERO,
            up: Vec3::Y,
            yfov_deg: 50.0,
            ymag: None,
            znear: 0.05,
            zfar: None,
        };
        let world_from_view = camera.world_from_view().unwrap();
        let target_vs = world_from_view.inverse().transform_point3(Vec3::ZERO);
        let distance = Vec3::new(3.0, 5.0, 6.0).length();
        assert!(target_vs.truncate().length() < 1e-4 && (target_vs.z + distance).abs() < 1e-4, "{target_vs}");
        let fails = |change: &dyn Fn(&mut LookAt)| {
            let mut c = camera;
            change(&mut c);
            c.world_from_view().unwrap_err().to_string()
        };
        assert_eq!(fails(&|c| c.target = c.eye), "look_at: eye and target are the same point");
        assert_eq!(fails(&|c| c.up = c.target - c.eye), "look_at: up is zero or parallel to the viewing direction");
        assert_eq!(fails(&|c| c.eye.x = f32::NAN), "eye: [NaN, 5, 6] is not finite");
        assert_eq!(fails(&|c| c.yfov_deg = 180.0), "yfov_deg: 180 is not between 0 and 180 degrees");
        assert_eq!(fails(&|c| c.znear = 0.0), "znear: 0 is not positive");
        assert_eq!(fails(&|c| c.zfar = Some(0.01)), "zfar: 0.01 is not beyond znear (0.05)");
        assert_eq!(fails(&|c| c.ymag = Some(0.0)), "ymag: 0 is not a positive distance");
        assert_eq!(fails(&|c| c.ymag = Some(2.0)), "zfar: an orthographic camera (ymag) needs a far plane");
        let orthographic = LookAt { ymag: Some(2.0), zfar: Some(30.0), yfov_deg: 500.0, ..camera };
        assert!(orthographic.world_from_view().is_ok(), "an orthographic camera has no field of view to check");
        assert_eq!(orthographic.projection(), Projection::Orthographic { ymag: 2.0 });
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
