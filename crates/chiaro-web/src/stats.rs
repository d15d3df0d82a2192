//! The timed frames' summary the page publishes as `window.chiaro.stats`.

/// `frame_ms_median`, `frame_ms_min`, `frame_ms_max`, `frames` and `adapter`, as the
/// browser test and the three.js comparison read them.
#[derive(Clone, Debug, PartialEq)]
pub struct FrameStats {
    pub frame_ms_median: f64,
    pub frame_ms_min: f64,
    pub frame_ms_max: f64,
    pub frames: usize,
    pub adapter: String,
}

impl FrameStats {
    /// The summary of `times` (milliseconds, each from the start of the frame's preparation
    /// to GPU completion);
    /// `None` for no frames. The median of an even count is the mean of the middle two.
    pub fn new(times: &[f64], adapter: &str) -> Option<FrameStats> {
        let mut sorted: Vec<f64> = times.iter().copied().filter(|t| t.is_finite()).collect();
        if sorted.is_empty() {
            return None;
        }
        sorted.sort_by(f64::total_cmp);
        let n = sorted.len();
        let median = if n % 2 == 1 { sorted[n / 2] } else { 0.5 * (sorted[n / 2 - 1] + sorted[n / 2]) };
        Some(FrameStats {
            frame_ms_median: median,
            frame_ms_min: sorted[0],
            frame_ms_max: sorted[n - 1],
            frames: n,
            adapter: adapter.to_string(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn median_min_and_max_of_odd_and_even_counts() {
        let s = FrameStats::new(&[5.0, 1.0, 3.0], "gpu").unwrap();
        assert_eq!((s.frame_ms_median, s.frame_ms_min, s.frame_ms_max, s.frames), (3.0, 1.0, 5.0, 3));
        assert_eq!(s.adapter, "gpu");
        assert_eq!(FrameStats::new(&[4.0, 1.0, 2.0, 8.0], "").unwrap().frame_ms_median, 3.0);
        assert_eq!(FrameStats::new(&[], ""), None);
    }
}
