//! One module per pass, each owning its pipelines and bind group layouts: the shadow
//! atlases, forward lighting, AOVs, tone mapping, and the per-light shadow AOV.

pub mod aov;
pub mod forward;
pub mod mesh;
pub mod shadow_aov;
pub mod shadows;
pub mod tonemap;
