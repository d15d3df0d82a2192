//! The viewer's orbit camera: yaw, pitch and distance about a target, starting from the
//! view `chiaro render` would use, so that an untouched viewer shows the same image.

use chiaro_render::View;
use glam::{Mat4, Vec3};

#[derive(Clone, Copy, Debug)]
pub struct Orbit {
    pub target: Vec3,
    pub yaw: f32,
    pub pitch: f32,
    pub distance: f32,
    /// Changed since the start: until then the start view is used as it is.
    pub moved: bool,
}

const MAX_PITCH: f32 = 1.55;

impl Orbit {
    /// Orbits `target` from where `start` looks.
    pub fn from_view(start: &View, target: Vec3) -> Orbit {
        let offset = start.eye() - target;
        let distance = offset.length().max(1e-3);
        let dir = offset / distance;
        Orbit { target, yaw: dir.x.atan2(dir.z), pitch: dir.y.clamp(-1.0, 1.0).asin(), distance, moved: false }
    }

    /// Turns by a mouse drag of `dx`, `dy` pixels.
    pub fn drag(&mut self, dx: f32, dy: f32) {
        self.yaw -= dx * 0.008;
        self.pitch = (self.pitch + dy * 0.008).clamp(-MAX_PITCH, MAX_PITCH);
        self.moved = true;
    }

    /// Moves closer (positive `steps`) or away by the mouse wheel.
    pub fn zoom(&mut self, steps: f32) {
        self.distance = (self.distance * 0.9f32.powf(steps)).max(1e-3);
        self.moved = true;
    }

    pub fn eye(&self) -> Vec3 {
        let (sy, cy) = self.yaw.sin_cos();
        let (sp, cp) = self.pitch.sin_cos();
        self.target + Vec3::new(sy * cp, sp, cy * cp) * self.distance
    }

    /// `start` seen from the orbit (its projection and size kept).
    pub fn view(&self, start: &View) -> View {
        if !self.moved {
            return *start;
        }
        View { world_from_view: Mat4::look_at_rh(self.eye(), self.target, Vec3::Y).inverse(), ..*start }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_orbit_starts_where_the_view_looks_from() {
        let scene = chiaro_scene::demo::demo_scene(4);
        let start = View::from_camera(&scene, 0, 64, 64);
        let target = scene.bounds().center();
        let mut orbit = Orbit::from_view(&start, target);
        assert!(orbit.eye().distance(start.eye()) < 1e-3);
        assert_eq!(orbit.view(&start).world_from_view, start.world_from_view);
        orbit.drag(100.0, 0.0);
        let moved = orbit.view(&start);
        assert!((moved.eye().distance(target) - start.eye().distance(target)).abs() < 1e-3, "stays at its distance");
        assert!(moved.eye().distance(start.eye()) > 0.1);
    }
}
