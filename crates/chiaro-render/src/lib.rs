//! Chiaro's renderer: the only crate that talks to wgpu.
//!
//! A `Scene` (plain data) and a `View` flow in; an HDR image, its tone-mapped sRGB copy,
//! the AOVs and GPU timings flow out. Passes: forward lighting into a pre-exposed HDR
//! target, an optional AOV pass (position, normal, depth), and tone mapping.

pub mod context;
pub mod error;
pub mod frame_lights;
pub mod gpu_scene;
pub mod gpu_types;
mod readback;
pub mod renderer;
pub mod shaders;
pub mod shadow_compare;
pub mod shadow_pass;
pub mod shadow_plan;
mod textures;
pub mod view;

pub use context::GpuContext;
pub use error::RenderError;
pub use renderer::{FrameOptions, FrameOutput, FrameTimings, Renderer, ShadowStatus};
pub use view::View;
