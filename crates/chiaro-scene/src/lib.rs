//! Scenes as plain data: glTF 2.0 import, the built-in demo scene, and pipeline settings.
//!
//! Files flow in, `Scene` values flow out; nothing here touches the GPU, so the render
//! crate and the tests share one description of what was loaded.

#![warn(missing_docs)]

pub mod animation;
pub mod baked;
pub mod demo;
pub mod environment;
pub mod error;
pub mod files;
pub mod gltf_import;
pub mod layers;
pub mod light;
pub mod names;
pub mod nodes;
pub mod settings;
pub mod shapes;
pub mod types;
pub mod variants;
pub mod vertex_gen;

pub use animation::{AnimationError, SceneAnimation};
pub use error::SceneError;
pub use gltf_import::{GivenFiles, load_gltf, load_gltf_bytes, load_gltf_given, referenced_files};
pub use layers::{LayerTexture, MaterialLayers};
pub use nodes::{NodeError, NodeMove, SceneNode};
pub use settings::{
    AmbientOcclusionSettings, AoQuality, CascadeBlend, DeferredAntialiasing, LightBuffer, LightCulling, MixedMode,
    RenderPath, Settings, ShadowTechnique, ToneMapping,
};
pub use types::*;
pub use variants::{MaterialVariants, VariantError, VariantMapping};
