//! Shadow-map math of the Custom SRP "Directional Shadows" tutorial, free of the GPU:
//! cascade splits and culling spheres, stable (texel-snapped) cascade projections, atlas
//! tiling, bias and fade terms, and the tent filters' sample weights.

pub mod atlas;
pub mod bias;
pub mod cascades;
pub mod fade;
pub mod filter;
pub mod other;

pub mod culling;

pub use atlas::AtlasLayout;
pub use cascades::{CascadeFit, cascade_splits, fit_cascade, slice_culling_sphere};
pub use filter::ShadowFilter;

/// Most shadowed directional lights.
pub const MAX_SHADOWED_DIRECTIONAL_LIGHTS: usize = 4;
/// Most cascades per directional light.
pub const MAX_CASCADES: usize = 4;
