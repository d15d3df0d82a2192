//! One module per pass, each owning its pipelines and bind group layouts: the shadow
//! atlases, forward lighting, the deferred path's G-buffer, light volumes, LDR decoding
//! and debug views, AOVs, tone mapping, and the per-light shadow AOV.

pub mod aov;
pub mod debug_view;
pub mod deferred_lights;
pub mod depth_prepass;
pub mod forward;
pub mod fullscreen;
pub mod gbuffer;
pub mod ldr_decode;
pub mod mesh;
pub mod shadow_aov;
pub mod shadows;
pub mod tonemap;
