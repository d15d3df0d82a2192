//! Pure math for Chiaro: bounds, frusta, projections and the punctual light model.
//!
//! Nothing here knows about the GPU; the render crate uploads what these functions return,
//! and the tests check them without an adapter.

pub mod area_light;
pub mod bounds;
pub mod brdf;
pub mod camera;
pub mod cube_map;
pub mod environment;
pub mod frustum;
pub mod light;
pub mod ltc;
pub mod rigid;
pub mod sampling;
pub mod sh;
pub mod shadow;
pub mod tonemap;

pub use bounds::{Aabb, Sphere};
pub use frustum::Frustum;
