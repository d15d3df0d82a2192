//! Rendered shadows against the ray-traced reference. `verdict` judges a rendered shadow
//! term pixel by pixel against chiaro-trace's reference (agreeing, false shadow, missed
//! shadow), counts the verdicts per light and paints them; `comparison` renders a view
//! with chiaro-render, traces it and applies the verdicts to every light; `environment`
//! judges a baked environment's light against the traced environment; `occlusion` judges a
//! rendered ambient occlusion against the traced one. It sits above both crates so that
//! the renderer does not depend on the tracer.

pub mod comparison;
pub mod environment;
pub mod occlusion;
mod threshold;
pub mod verdict;

pub use comparison::{
    CompareOptions, LightReport, RenderedShadows, ShadowComparison, compare_rendered, compare_rendered_with,
    compare_shadows, compare_shadows_with, not_compared_because, render_shadows,
};
pub use environment::{EnvironmentReport, compare_environment};
pub use occlusion::{OCCLUDED_BELOW, OcclusionReport, compare_occlusion};
pub use threshold::{MAX_DISAGREEMENT, assert_agrees_with_reference};
pub use verdict::{
    DISAGREEMENT_THRESHOLD, EDGE_BAND_PX, FAR_OFF, JudgedLight, LightComparison, MAX_EDGE_BAND_PX,
    POSITION_TOLERANCE_M, PixelVerdict, VisibilityError, classify_pixels, compare_light, difference_image,
    signed_difference_image, soft_shadow_report, visibility_error,
};
