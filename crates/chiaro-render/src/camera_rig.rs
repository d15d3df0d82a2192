//! The viewers' camera (native and browser): yaw, pitch and distance about a target. Orbit turns about the
//! target; fly turns about the eye and moves it with the keys. It starts from the view
//! `chiaro render` would use, so that an untouched viewer shows the same image.

use crate::View;
use chiaro_math::bounds::Sphere;
use chiaro_math::camera::Projection;
use glam::{Mat4, Vec3};

/// What a mouse drag does.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Navigation {
    /// Drag turns about the target, the wheel zooms.
    #[default]
    Orbit,
    /// Drag looks around, W/A/S/D/Q/E move.
    Fly,
}

impl Navigation {
    /// The name the panels show.
    pub fn name(self) -> &'static str {
        match self {
            Navigation::Orbit => "orbit",
            Navigation::Fly => "fly",
        }
    }
}

/// A camera that looks at `target` from `distance` away, turned by `yaw` about +Y and
/// `pitch` above the horizon.
#[derive(Clone, Copy, Debug)]
pub struct CameraRig {
    /// The point the camera looks at and orbits about.
    pub target: Vec3,
    /// Radians about +Y of the direction from the target to the eye.
    pub yaw: f32,
    /// Radians above the horizon of that direction.
    pub pitch: f32,
    /// Metres from the target to the eye.
    pub distance: f32,
    /// `distance` at the start: an orthographic view's height scales with
    /// `distance / start_distance`, so that the wheel zooms it as it does a perspective one.
    pub start_distance: f32,
    /// Changed since the start: until then the start view is used as it is.
    pub moved: bool,
}

const MAX_PITCH: f32 = 1.55;
/// Fly speed, in scene radii per second (x4 with Shift).
const FLY_SPEED: f32 = 0.4;
/// Radians per pixel of mouse drag.
const TURN_PER_PIXEL: f32 = 0.008;

/// Which way a fly camera is asked to move, in its own axes (x right, y up, z back).
pub type FlyInput = Vec3;

impl CameraRig {
    /// Starts where `start` is, looking where it looks, with the target on its line of
    /// sight as far away as `center` (the scene's, say), so that the first drag turns about
    /// a point in front of it rather than snapping to `center`.
    pub fn from_view(start: &View, center: Vec3) -> CameraRig {
        let eye = start.eye();
        let forward = -start.world_from_view.z_axis.truncate().normalize_or(Vec3::NEG_Z);
        let distance = (center - eye).length().max(1e-3);
        let back = -forward;
        CameraRig {
            target: eye + forward * distance,
            yaw: back.x.atan2(back.z),
            // Straight up or down, looking at the target with +Y up has no answer.
            pitch: back.y.clamp(-1.0, 1.0).asin().clamp(-MAX_PITCH, MAX_PITCH),
            distance,
            start_distance: distance,
            moved: false,
        }
    }

    /// Unit vector from the target to the eye.
    fn back(&self) -> Vec3 {
        let (sy, cy) = self.yaw.sin_cos();
        let (sp, cp) = self.pitch.sin_cos();
        Vec3::new(sy * cp, sp, cy * cp)
    }

    /// Where the camera is.
    pub fn eye(&self) -> Vec3 {
        self.target + self.back() * self.distance
    }

    /// Turns by a mouse drag of `dx`, `dy` pixels: about the target when orbiting, about
    /// the eye when flying.
    pub fn drag(&mut self, navigation: Navigation, dx: f32, dy: f32) {
        let eye = self.eye();
        match navigation {
            Navigation::Orbit => {
                self.yaw -= dx * TURN_PER_PIXEL;
                self.pitch = (self.pitch + dy * TURN_PER_PIXEL).clamp(-MAX_PITCH, MAX_PITCH);
            }
            Navigation::Fly => {
                self.yaw -= dx * TURN_PER_PIXEL;
                self.pitch = (self.pitch - dy * TURN_PER_PIXEL).clamp(-MAX_PITCH, MAX_PITCH);
                self.target = eye - self.back() * self.distance;
            }
        }
        self.moved = true;
    }

    /// Moves closer (positive `steps`) or away by the mouse wheel.
    pub fn zoom(&mut self, steps: f32) {
        self.distance = (self.distance * 0.9f32.powf(steps)).max(1e-3);
        self.moved = true;
    }

    /// Moves eye and target by the held keys' `input` for `seconds` (at most a quarter of
    /// a second, so that a stalled frame does not throw the camera away), at 0.4
    /// `scene_radius` a second, four times as fast when `fast`: both viewers' fly speed.
    pub fn fly_for(&mut self, input: FlyInput, fast: bool, seconds: f32, scene_radius: f32) {
        let speed = if fast { 4.0 } else { 1.0 };
        self.fly(input, FLY_SPEED * speed * scene_radius * seconds.min(0.25));
    }

    /// Moves eye and target together by `input` (camera axes) x `metres`.
    pub fn fly(&mut self, input: FlyInput, metres: f32) {
        if input == Vec3::ZERO {
            return;
        }
        let back = self.back();
        let right = Vec3::Y.cross(back).try_normalize().unwrap_or(Vec3::X);
        let step = (right * input.x + Vec3::Y * input.y + back * input.z).normalize_or_zero() * metres;
        self.target += step;
        self.moved = true;
    }

    /// Looks at a sphere around `center` of `radius` from the current direction, close
    /// enough for it to fill the height of the start view's `projection`.
    pub fn frame(&mut self, center: Vec3, radius: f32, projection: Projection) {
        let radius = radius.max(1e-3);
        self.target = center;
        self.distance = match projection {
            Projection::Perspective { yfov_rad } => radius / (0.5 * yfov_rad).sin(),
            Projection::Orthographic { ymag } => radius / ymag * self.start_distance,
        }
        .max(1e-3);
        self.moved = true;
    }

    /// `start` seen from the rig: its field of view (or, orthographic, its height scaled
    /// by the zoom) and size kept, its near and far planes fitted to where the eye now is
    /// against `scene` (the scene's bounding sphere), so that zooming, flying and framing
    /// never clip the scene. Untouched, `start` itself.
    pub fn view(&self, start: &View, scene: Sphere) -> View {
        if !self.moved {
            return *start;
        }
        let radius = scene.radius.max(1e-3);
        let (eye, projection) = match start.projection {
            // Parallel rays see the same picture from any distance: the eye stands back
            // out of the scene and the zoom scales the view's height instead.
            Projection::Orthographic { ymag } => {
                let standoff = self.target.distance(scene.center) + radius * 1.01;
                let zoom = self.distance / self.start_distance;
                (self.target + self.back() * standoff, Projection::Orthographic { ymag: ymag * zoom })
            }
            perspective => (self.eye(), perspective),
        };
        let to_scene = eye.distance(scene.center);
        let znear = (to_scene - radius).max(radius * 1e-4).max(1e-4);
        let zfar = start.zfar.map(|_| (to_scene + radius * 2.0).max(znear * 2.0));
        View {
            world_from_view: Mat4::look_at_rh(eye, self.target, Vec3::Y).inverse(),
            clip_from_view: projection.clip_from_view(start.aspect(), znear, zfar),
            projection,
            znear,
            zfar,
            ..*start
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn demo_start() -> (View, Vec3) {
        let scene = chiaro_scene::demo::demo_scene(4);
        (View::from_camera(&scene, 0, 64, 64), scene.bounds().center())
    }

    fn demo_sphere() -> Sphere {
        chiaro_scene::demo::demo_scene(4).bounds().bounding_sphere()
    }

    fn forward(view: &View) -> Vec3 {
        -view.world_from_view.z_axis.truncate().normalize()
    }

    /// Whether `point` lies between the view's near and far planes.
    fn between_planes(view: &View, point: Vec3) -> bool {
        let depth = (point - view.eye()).dot(forward(view));
        depth > view.znear && view.zfar.is_none_or(|far| depth < far)
    }

    #[test]
    fn an_orbit_starts_where_the_view_looks_from() {
        let (start, center) = demo_start();
        let mut rig = CameraRig::from_view(&start, center);
        assert!(rig.eye().distance(start.eye()) < 1e-3);
        assert_eq!(rig.view(&start, demo_sphere()).world_from_view, start.world_from_view);
        // The target lies on the line of sight, as far as the scene's centre.
        let target = rig.target;
        assert!(((target - start.eye()).length() - (center - start.eye()).length()).abs() < 1e-3);
        rig.drag(Navigation::Orbit, 100.0, 0.0);
        let moved = rig.view(&start, demo_sphere());
        assert!((moved.eye().distance(target) - start.eye().distance(target)).abs() < 1e-3, "stays at its distance");
        assert!(moved.eye().distance(start.eye()) > 0.1);
    }

    #[test]
    fn flying_turns_about_the_eye_and_moves_it_forward() {
        let (start, target) = demo_start();
        let mut rig = CameraRig::from_view(&start, target);
        let eye = rig.eye();
        rig.drag(Navigation::Fly, 40.0, 10.0);
        assert!(rig.eye().distance(eye) < 1e-3, "looking around keeps the eye");
        let forward = (rig.target - rig.eye()).normalize();
        rig.fly(Vec3::new(0.0, 0.0, -1.0), 2.0);
        assert!((rig.eye() - (eye + forward * 2.0)).length() < 1e-3, "W moves along the view");
        let view = rig.view(&start, demo_sphere());
        assert!(view.eye().distance(rig.eye()) < 1e-3);
    }

    #[test]
    fn a_camera_not_looking_at_the_centre_keeps_its_direction_on_a_small_drag() {
        let scene = chiaro_scene::demo::demo_scene(4);
        let sphere = scene.bounds().bounding_sphere();
        // A camera looking off to the side of the scene's centre, and one straight down.
        let eye = Vec3::new(0.0, 3.0, 12.0);
        for look_at in [Vec3::new(9.0, 0.0, 0.0), eye - Vec3::Y] {
            let up = if look_at.x == 0.0 { Vec3::Z } else { Vec3::Y };
            let start = View { world_from_view: Mat4::look_at_rh(eye, look_at, up).inverse(), ..demo_start().0 };
            let mut rig = CameraRig::from_view(&start, sphere.center);
            rig.drag(Navigation::Orbit, 1.0, 0.0);
            let view = rig.view(&start, sphere);
            assert!(view.world_from_view.is_finite(), "no NaN looking straight down");
            assert!(forward(&view).dot(forward(&start)) > 0.99, "no jump: {} vs {}", forward(&view), forward(&start));
        }
    }

    #[test]
    fn zooming_and_flying_keep_the_scene_between_the_planes() {
        let (start, target) = demo_start();
        let sphere = demo_sphere();
        let mut rig = CameraRig::from_view(&start, target);
        for _ in 0..12 {
            rig.zoom(1.0);
        }
        let close = rig.view(&start, sphere);
        assert!(between_planes(&close, rig.target), "zoomed in, the target is drawn");
        assert!(close.znear < (rig.target - close.eye()).length());
        for _ in 0..60 {
            rig.zoom(-1.0);
        }
        let far = rig.view(&start, sphere);
        assert!(between_planes(&far, sphere.center + Vec3::Y * sphere.radius * 0.9), "zoomed out, all is drawn");
        rig.fly(Vec3::new(0.0, 0.0, -1.0), (far.eye() - sphere.center).length());
        let inside = rig.view(&start, sphere);
        assert!(inside.znear <= sphere.radius * 1e-3, "inside the scene the near plane comes close");
    }

    #[test]
    fn framing_fits_the_sphere_in_the_field_of_view() {
        let (start, target) = demo_start();
        let mut rig = CameraRig::from_view(&start, target);
        let center = Vec3::new(3.0, 1.0, -2.0);
        rig.frame(center, 2.0, Projection::Perspective { yfov_rad: 60f32.to_radians() });
        let view = rig.view(&start, demo_sphere());
        assert!(between_planes(&view, center), "the framed sphere is drawn");
        // The sphere's edge is seen at half the field of view from its centre.
        let to_center = center - view.eye();
        let half_angle = (2.0 / to_center.length()).asin();
        assert!((half_angle - 30f32.to_radians()).abs() < 1e-3, "{half_angle}");
        let forward = -view.world_from_view.z_axis.truncate();
        assert!(forward.dot(to_center.normalize()) > 0.9999, "looks at the centre");
    }

    #[test]
    fn an_orthographic_view_zooms_its_height_and_stands_back_from_the_scene() {
        let (perspective, target) = demo_start();
        let sphere = demo_sphere();
        let start = View::projected(
            perspective.world_from_view,
            Projection::Orthographic { ymag: 3.0 },
            0.05,
            Some(100.0),
            64,
            64,
        );
        let mut rig = CameraRig::from_view(&start, target);
        for _ in 0..12 {
            rig.zoom(1.0);
        }
        let close = rig.view(&start, sphere);
        let Projection::Orthographic { ymag } = close.projection else { panic!("stays orthographic") };
        assert!((ymag - 3.0 * 0.9f32.powi(12)).abs() < 1e-4, "zooming in narrows the view: {ymag}");
        // However close the zoom, the whole scene stays in front of the near plane.
        for probe in [sphere.center, sphere.center + forward(&close) * -sphere.radius * 0.99] {
            assert!(between_planes(&close, probe), "{probe} clipped");
        }
        rig.frame(Vec3::new(1.0, 0.5, 0.0), 2.0, start.projection);
        let framed = rig.view(&start, sphere);
        let Projection::Orthographic { ymag } = framed.projection else { panic!("stays orthographic") };
        assert!((ymag - 2.0).abs() < 1e-4, "framing fits the sphere's radius to the half height: {ymag}");
    }
}
