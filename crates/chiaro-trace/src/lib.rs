//! CPU ray tracing for Chiaro: a BVH over the scene's triangles, and the shadow reference
//! that GPU shadows are judged against.
//!
//! `Scene` values flow in; out come ray queries (`SceneBvh`) and per-pixel traced shadow
//! visibility (`trace_shadow_reference`). Judging a rendered shadow against it is
//! chiaro-compare's job. Nothing here touches the GPU.

pub mod alpha;
pub mod area;
pub mod bvh;
pub mod environment;
pub mod reference;

pub use area::area_light_visibility;
pub use bvh::{Hit, SceneBvh};
pub use environment::environment_irradiance;
pub use reference::{PixelCamera, ShadowReference, light_visibility, trace_shadow_reference};
