//! The camera a frame renders from: a scene camera or one framed around the bounds.

use chiaro_math::camera::{Projection, frame_bounds, perspective_reverse_z};
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
    /// Perspective (its vertical field of view) or orthographic (its half height).
    pub projection: Projection,
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

    /// The camera's position in world space, metres: for an orthographic camera, the
    /// centre of the view's plane.
    pub fn eye(&self) -> Vec3 {
        self.world_from_view.w_axis.truncate()
    }

    /// The unit direction the camera looks along (view space -Z) in world space.
    pub fn forward(&self) -> Vec3 {
        (-self.world_from_view.z_axis.truncate()).normalize()
    }

    /// Whether the camera's rays are parallel.
    pub fn is_orthographic(&self) -> bool {
        self.projection.is_orthographic()
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
        View::projected(world_from_view, Projection::Perspective { yfov_rad }, znear, zfar, width, height)
    }

    /// A camera with pose `world_from_view` and either projection, for a `width` x
    /// `height` image: the projection's height is kept and its width follows the image.
    pub fn projected(
        world_from_view: Mat4,
        projection: Projection,
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
            clip_from_view: projection.clip_from_view(aspect, znear, zfar),
            projection,
            znear,
            zfar,
        }
    }

    /// The view of `scene.cameras[index]` at the given output size.
    pub fn from_camera(scene: &Scene, index: usize, width: u32, height: u32) -> View {
        let c = &scene.cameras[index];
        View::projected(c.world_from_view, c.projection, c.znear, c.zfar, width, height)
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
            projection: Projection::Perspective { yfov_rad },
            znear: near,
            zfar: Some(far),
        }
    }
}
