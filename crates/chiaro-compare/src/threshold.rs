//! How far a light's rendered shadows may stray from the ray-traced reference before a
//! test calls it a regression: one limit, in the units `LightComparison::disagreement`
//! returns, and the check the tests share, so that every suite holds the same line.

use crate::verdict::LightComparison;

/// Share of compared pixels (0 to 1) on which rendered and traced shadows may disagree.
/// Shadow-map texels and the reference's exact rays still part here and there outside the
/// edge band that the comparison leaves out; the limit leaves room for that and no more.
pub const MAX_DISAGREEMENT: f64 = 0.005;

/// Panics, naming `label` and the pixel counts, unless `comparison` disagrees on less
/// than [`MAX_DISAGREEMENT`] of its pixels. For tests.
#[track_caller]
pub fn assert_agrees_with_reference(label: &str, comparison: &LightComparison) {
    assert!(
        comparison.disagreement() < MAX_DISAGREEMENT,
        "{label}: {:.3}% of pixels disagree with the reference ({} false, {} missed of {} compared), limit {}%",
        100.0 * comparison.disagreement(),
        comparison.false_shadow,
        comparison.missed_shadow,
        comparison.compared,
        100.0 * MAX_DISAGREEMENT
    );
}
