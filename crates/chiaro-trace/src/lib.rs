//! CPU ray tracing for Chiaro: a BVH over the scene's triangles, and the shadow and
//! ambient occlusion references that the GPU's are judged against.
//!
//! `Scene` values flow in; out come ray queries (`SceneBvh`), per-pixel traced shadow
//! visibility (`trace_shadow_reference`) and per-pixel traced ambient occlusion
//! (`trace_ambient_occlusion`). Judging a render against them is chiaro-compare's job.
//! Nothing here touches the GPU.

pub mod alpha;
pub mod area;
pub mod bvh;
pub mod environment;
pub mod occlusion;
pub mod reference;

pub use area::area_light_visibility;
pub use bvh::{Hit, SceneBvh};
pub use environment::environment_irradiance;
pub use occlusion::{OcclusionReference, REFERENCE_AO_RAYS, surface_occlusion, trace_ambient_occlusion};
pub use reference::{PixelCamera, ShadowReference, light_visibility, trace_shadow_reference};
