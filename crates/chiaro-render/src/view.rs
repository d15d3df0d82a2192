//! The camera a frame renders from: a scene camera or one framed around the bounds.

use chiaro_math::camera::{frame_bounds, perspective_reverse_z};
use chiaro_scene::Scene;
use glam::{Mat4, Vec3};

/// The camera of one frame: output size in pixels, its pose and its reverse-Z projection.
#[derive(Clone, Copy, Debug)]
pub struct View {
    /// Output width in pixels.
    pub width: u32,
    /// Output height in pixels.
    pub height: u32,
    /// The camera's pose: view space (right-handed, -Z forward) to world space.
    pub world_from_view: Mat4,
    /// View space to reverse-Z clip space.
    pub clip_from_view: Mat4,
    /// Vertical field of view, radians.
    pub yfov_rad: f32,
    /// Near plane distance, metres.
    pub znear: f32,
    /// `None` for an infinite projection.
    pub zfar: Option<f32>,
}

impl View {
    /// World space to view space (the pose's inverse).
    pub fn view_from_world(&self) -> Mat4 {
        self.world_from_view.inverse()
    }

    /// World space to clip space.
    pub fn clip_from_world(&self) -> Mat4 {
        self.clip_from_view * self.view_from_world()
    }

    /// Width over height.
    pub fn aspect(&self) -> f32 {
        self.width as f32 / self.height as f32
    }

    /// The camera's position in world space, metres.
    pub fn eye(&self) -> Vec3 {
        self.world_from_view.w_axis.truncate()
    }

    /// A perspective camera with pose `world_from_view`, for a `width` x `height` image
    /// (the aspect ratio is the image's).
    pub fn perspective(
        world_from_view: Mat4,
        yfov_rad: f32,
        znear: f32,
        zfar: Option<f32>,
        width: u32,
        height: u32,
    ) -> View {
        let aspect = width as f32 / height as f32;
        View {
            width,
            height,
            world_from_view,
            clip_from_view: perspective_reverse_z(yfov_rad, aspect, znear, zfar),
            yfov_rad,
            znear,
            zfar,
        }
    }

    /// The view of `scene.cameras[index]` at the given output size.
    pub fn from_camera(scene: &Scene, index: usize, width: u32, height: u32) -> View {
        let c = &scene.cameras[index];
        View::perspective(c.world_from_view, c.yfov_rad, c.znear, c.zfar, width, height)
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
