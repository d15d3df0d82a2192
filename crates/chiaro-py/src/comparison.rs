//! `chiaro.compare`'s rows: per light, how its realtime shadows agree with the ray-traced
//! reference, as `chiaro compare` prints them.

use chiaro_compare::{ShadowComparison, not_compared_because};
use chiaro_render::ShadowStatus;
use chiaro_scene::Scene;
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// One light's verdict, made without the GIL.
pub struct LightVerdict {
    node: usize,
    light: String,
    kind: &'static str,
    /// Why the light was not judged; None when it was.
    not_compared: Option<&'static str>,
    /// Judged by its baked shadow mask alone (no atlas tile).
    shadow_mask_only: bool,
    compared: usize,
    /// Disagreement, false and missed shadow, percent of compared pixels.
    percents: Option<[f64; 3]>,
    /// A contact-hardening or area light's visibility error: mean and 95th percentile of
    /// |rendered - reference|, the percent of pixels off by more than 0.1, and the mean
    /// and that percent over the reference's penumbra alone.
    visibility: Option<[f64; 5]>,
}

impl LightVerdict {
    /// Every light of the comparison, in the scene's order.
    pub fn all(scene: &Scene, result: &ShadowComparison) -> Vec<LightVerdict> {
        result
            .reports
            .iter()
            .map(|report| {
                let light = &scene.lights[report.light];
                let status = result.status[report.light];
                let c = &report.comparison;
                // A light judged on no pixel has no share to report, not a perfect one.
                let not_compared =
                    not_compared_because(status).or((c.compared == 0).then_some("no pixel of this view was judged"));
                LightVerdict {
                    node: light.node,
                    light: light.name.clone(),
                    kind: light.kind.name(),
                    not_compared,
                    shadow_mask_only: status == ShadowStatus::MaskOnly,
                    compared: if not_compared.is_some() { 0 } else { c.compared },
                    percents: not_compared
                        .is_none()
                        .then(|| [c.disagreement(), c.false_share(), c.missed_share()].map(|share| 100.0 * share)),
                    visibility: report.visibility.filter(|v| not_compared.is_none() && v.compared > 0).map(|v| {
                        [v.mean_abs, v.p95_abs, 100.0 * v.far_off, v.penumbra_mean_abs, 100.0 * v.penumbra_far_off]
                    }),
                }
            })
            .collect()
    }

    /// The row as `chiaro.compare` returns it.
    pub fn into_dict(self, py: Python<'_>) -> PyResult<Bound<'_, PyDict>> {
        let d = PyDict::new(py);
        d.set_item("node", self.node)?;
        d.set_item("light", self.light)?;
        d.set_item("kind", self.kind)?;
        d.set_item("compared", self.compared)?;
        d.set_item("disagree_percent", self.percents.map(|p| p[0]))?;
        d.set_item("false_percent", self.percents.map(|p| p[1]))?;
        d.set_item("missed_percent", self.percents.map(|p| p[2]))?;
        d.set_item("not_compared", self.not_compared)?;
        d.set_item("shadow_mask_only", self.shadow_mask_only)?;
        d.set_item("visibility_mean_abs", self.visibility.map(|v| v[0]))?;
        d.set_item("visibility_p95_abs", self.visibility.map(|v| v[1]))?;
        d.set_item("visibility_far_off_percent", self.visibility.map(|v| v[2]))?;
        d.set_item("penumbra_mean_abs", self.visibility.map(|v| v[3]))?;
        d.set_item("penumbra_far_off_percent", self.visibility.map(|v| v[4]))?;
        Ok(d)
    }
}
