//! The disagreement debug view: the current camera's frame judged against the ray-traced
//! reference, as `chiaro compare` judges it, with its false (red) and missed (blue)
//! shadows painted over the image. The frame is rendered on the window's device; the
//! tracing runs on a thread of its own, so the window stays live meanwhile.

use chiaro_compare::PixelVerdict;
use chiaro_compare::{RenderedShadows, ShadowComparison, compare_rendered, not_compared_because};
use chiaro_render::View;
use chiaro_scene::{Scene, Settings};
use std::sync::mpsc;
use std::time::Instant;

/// A finished comparison, ready to show.
#[derive(Debug)]
pub struct Disagreement {
    /// The camera it was computed for.
    pub view: View,
    pub width: usize,
    pub height: usize,
    /// The frame dimmed, with false shadows red and missed shadows blue (RGBA8).
    pub overlay: Vec<u8>,
    /// One line per light: its share of disagreeing pixels, or why it was not compared.
    pub lines: Vec<String>,
    pub seconds: f64,
}

#[derive(Default)]
pub struct ReferenceJob {
    pending: Option<(View, Instant, mpsc::Receiver<Disagreement>)>,
}

impl ReferenceJob {
    pub fn running(&self) -> bool {
        self.pending.is_some()
    }

    /// Traces and judges `rendered` (the frame of `view`) on another thread.
    pub fn start(&mut self, scene: &Scene, view: View, settings: &Settings, rendered: RenderedShadows) {
        let (tx, rx) = mpsc::channel();
        let (scene, settings) = (scene.clone(), settings.clone());
        let started = Instant::now();
        std::thread::spawn(move || {
            let ldr = rendered.ldr.clone();
            let comparison = compare_rendered(&scene, &view, &settings, rendered);
            let _ = tx.send(Disagreement {
                view,
                width: view.width as usize,
                height: view.height as usize,
                overlay: overlay(&ldr, &comparison),
                lines: light_lines(&scene, &comparison),
                seconds: started.elapsed().as_secs_f64(),
            });
        });
        self.pending = Some((view, started, rx));
    }

    /// The comparison once it finished, or why there is none.
    pub fn poll(&mut self) -> Option<Result<Disagreement, String>> {
        let (_, _, rx) = self.pending.as_ref()?;
        match rx.try_recv() {
            Ok(done) => {
                self.pending = None;
                Some(Ok(done))
            }
            Err(mpsc::TryRecvError::Empty) => None,
            Err(mpsc::TryRecvError::Disconnected) => {
                self.pending = None;
                Some(Err("the comparison failed: its thread stopped without a result".into()))
            }
        }
    }
}

/// The frame at half brightness, each pixel where some light's shadow disagrees with the
/// reference painted in that verdict's colour (false shadows win over missed ones).
pub fn overlay(ldr: &[u8], comparison: &ShadowComparison) -> Vec<u8> {
    let false_color = PixelVerdict::FalseShadow.color();
    let missed_color = PixelVerdict::MissedShadow.color();
    ldr.chunks_exact(4)
        .enumerate()
        .flat_map(|(i, px)| {
            let verdicts = comparison.reports.iter().map(|r| r.difference[i]);
            let mut worst = None;
            for v in verdicts {
                if v == false_color {
                    worst = Some(false_color);
                    break;
                }
                if v == missed_color {
                    worst = Some(missed_color);
                }
            }
            worst.unwrap_or([px[0] / 2, px[1] / 2, px[2] / 2, 255])
        })
        .collect()
}

fn light_lines(scene: &Scene, comparison: &ShadowComparison) -> Vec<String> {
    comparison
        .reports
        .iter()
        .map(|report| {
            let light = &scene.lights[report.light];
            let name = if light.name.is_empty() { format!("light {}", report.light) } else { light.name.clone() };
            let c = &report.comparison;
            match (not_compared_because(comparison.status[report.light]), report.visibility) {
                // A contact-hardening light: how far its soft visibility is from the traced disc's.
                (None, Some(v)) => format!(
                    "{name} (pcss): visibility off by {:.4} on average, {:.4} at the 95th percentile, more than \
                     0.1 on {:.3}%",
                    v.mean_abs,
                    v.p95_abs,
                    100.0 * v.far_off
                ),
                (None, None) => format!(
                    "{name}: {:.3}% disagree ({:.3}% false, {:.3}% missed)",
                    100.0 * c.disagreement(),
                    100.0 * c.false_share(),
                    100.0 * c.missed_share()
                ),
                (Some(why), _) => format!("{name}: {why}"),
            }
        })
        .collect()
}
