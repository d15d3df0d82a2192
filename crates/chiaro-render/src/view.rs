//! The camera a frame renders from: a scene camera or one framed around the bounds.

use chiaro_math::camera::{frame_bounds, perspective_reverse_z};
use chiaro_scene::Scene;
use glam::{Mat4, Vec3};

#[derive(Clone, Copy, Debug)]
pub struct View {
    pub width: u32,
    pub height: u32,
    pub world_from_view: Mat4,
    pub clip_from_view: Mat4,
    pub yfov_rad: f32,
    pub znear: f32,
    /// `None` for an infinite projection.
    pub zfar: Option<f32>,
}

impl View {
    pub fn view_from_world(&self) -> Mat4 {
        self.world_from_view.inverse()
    }

    pub fn clip_from_world(&self) -> Mat4 {
        self.clip_from_view * self.view_from_world()
    }

    pub fn aspect(&self) -> f32 {
        self.width as f32 / self.height as f32
    }

    pub fn eye(&self) -> Vec3 {
        self.world_from_view.w_axis.truncate()
    }

    /// The view of `scene.cameras[index]` at the given output size.
    pub fn from_camera(scene: &Scene, index: usize, width: u32, height: u32) -> View {
        let c = &scene.cameras[index];
        let aspect = width as f32 / height as f32;
        View {
            width,
            height,
            world_from_view: c.world_from_view,
            clip_from_view: perspective_reverse_z(c.yfov_rad, aspect, c.znear, c.zfar),
            yfov_rad: c.yfov_rad,
            znear: c.znear,
            zfar: c.zfar,
        }
    }

    /// A camera that frames the whole scene, for files with no camera.
    pub fn framing(scene: &Scene, yfov_rad: f32, width: u32, height: u32) -> View {
        let aspect = width as f32 / height as f32;
        let (world_from_view, near, far) = frame_bounds(&scene.bounds(), yfov_rad, aspect);
        View {
            width,
            height,
            world_from_view,
            clip_from_view: perspective_reverse_z(yfov_rad, aspect, near, Some(far)),
            yfov_rad,
            znear: near,
            zfar: Some(far),
        }
    }
}
