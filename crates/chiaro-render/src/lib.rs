//! Chiaro's renderer: the only crate that talks to wgpu.
//!
//! A `Scene` (plain data) and a `View` flow in; a frame is planned on the CPU
//! (`plan::FramePlan`: lights with stable ids, their lists and shadow slots, shadow
//! tiles and their casters, draw order, passes), its data uploaded (`frame_data`), and
//! its passes (`passes`) recorded through a small frame graph (`graph`) that owns the
//! targets, debug groups and timestamps. An HDR image, its tone-mapped copy, the AOVs and
//! GPU timings flow out, or the frame goes to a window's surface without a wait.

#![warn(missing_docs)]

pub mod camera_rig;
pub mod context;
pub mod debug_images;
pub mod debug_view;
pub mod environment;
pub mod error;
pub mod frame_bindings;
pub mod frame_data;
pub mod gpu;
pub mod graph;
pub mod output;
pub mod overrides;
pub mod passes;
pub mod plan;
pub mod readback;
pub mod renderer;
pub mod scene;
pub mod shader_constants;
pub mod shaders;
pub mod texel_table;
pub mod thread_clock;
mod unpack;
pub mod view;

/// The wgpu this crate renders with, for callers that lend it textures.
pub use wgpu;

pub use context::GpuContext;
pub use debug_view::{AovView, DebugView};
pub use error::RenderError;
pub use output::{FrameOptions, FrameOutput, FrameTimings, GpuFrameTimes, Ids, ShadowStatus};
pub use plan::FramePlan;
pub use plan::virtual_shadows::VirtualPageStats;
pub use renderer::{PendingFrame, PreparedScene, Renderer};
pub use view::View;
