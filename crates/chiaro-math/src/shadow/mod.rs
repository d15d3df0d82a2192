//! Shadow-map math of the Custom SRP "Directional Shadows" and "Point and Spot Shadows"
//! tutorials, free of the GPU: cascade splits and culling spheres, stable (texel-snapped)
//! cascade projections, atlas tiling and tile allocation, caster culling, bias and fade
//! terms, the tent filters' sample weights, the spot and cube-face projections, and the
//! lenses and penumbra widths of contact-hardening shadows.

pub mod allocator;
pub mod atlas;
pub mod bias;
pub mod cascades;
pub mod culling;
pub mod fade;
pub mod filter;
pub mod local;
pub mod pcss;
pub mod tiers;
pub mod virtual_map;

pub use allocator::{TileAllocation, TileAllocator, first_fit_tiles};
pub use atlas::AtlasLayout;
pub use cascades::{CascadeFit, cascade_splits, fit_cascade, slice_culling_sphere};
pub use filter::ShadowFilter;

/// Most shadowed directional lights.
pub const MAX_SHADOWED_DIRECTIONAL_LIGHTS: usize = 4;
/// Most cascades per directional light.
pub const MAX_CASCADES: usize = 4;
