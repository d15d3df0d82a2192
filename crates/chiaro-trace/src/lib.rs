//! CPU ray tracing for Chiaro: a BVH over the scene's triangles, and the shadow reference
//! that GPU shadows are judged against.
//!
//! `Scene` values flow in; out come ray queries (`SceneBvh`), per-pixel traced shadow
//! visibility (`trace_shadow_reference`), and per-light verdicts comparing a rendered
//! shadow with it (`compare_light`, `difference_image`). Nothing here touches the GPU.

pub mod alpha;
pub mod bvh;
pub mod compare;
pub mod reference;

pub use bvh::{Hit, SceneBvh};
pub use compare::{LightComparison, PixelVerdict, classify_pixels, compare_light, difference_image};
pub use reference::{PixelCamera, ShadowReference, light_visibility, trace_shadow_reference};
