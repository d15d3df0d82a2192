//! The frame's timings: numbers, and a graph of each pass's GPU time (stacked) under the
//! whole frame's interval and the CPU time. Reads the statistics; asks for nothing.

use crate::state::{FrameSample, FrameStats, GRAPH_FRAMES};

/// Timings of the latest frames: numbers, and a graph of each pass's GPU time (stacked)
/// under the whole frame's interval and the CPU time.
pub fn timings_panel(ui: &mut egui::Ui, stats: &FrameStats) {
    let last = stats.history.back().cloned().unwrap_or_default();
    let mut intervals: Vec<f64> = stats.history.iter().filter_map(|s| s.interval_ms).collect();
    intervals.sort_by(f64::total_cmp);
    if let Some(median) = intervals.get(intervals.len() / 2) {
        ui.label(format!("frame {median:.1} ms ({:.1} fps), median of the graph", 1000.0 / median));
    }
    ui.colored_label(CPU_COLOR, format!("CPU {:.1} ms to plan and record", last.cpu_ms));
    ui.label(format!("{} lights shaded, {} shadow tiles drawn", stats.lights_shaded, stats.shadow_tiles));
    if let Some(gpu) = &stats.gpu {
        ui.label(format!("GPU {:.1} ms (timestamps)", gpu.total_ms()));
        for (k, (pass, ms)) in gpu.passes.iter().enumerate() {
            ui.colored_label(pass_color(k), format!("  {pass}: {ms:.2} ms"));
        }
    }
    graph(ui, stats);
}

const CPU_COLOR: egui::Color32 = egui::Color32::from_rgb(120, 200, 255);
const FRAME_COLOR: egui::Color32 = egui::Color32::from_rgb(220, 220, 220);
const PASS_COLORS: [egui::Color32; 6] = [
    egui::Color32::from_rgb(230, 120, 60),
    egui::Color32::from_rgb(90, 170, 90),
    egui::Color32::from_rgb(200, 170, 60),
    egui::Color32::from_rgb(170, 110, 200),
    egui::Color32::from_rgb(80, 150, 200),
    egui::Color32::from_rgb(200, 90, 120),
];

/// The colour of the frame's `k`th pass in the graph and its legend.
fn pass_color(k: usize) -> egui::Color32 {
    PASS_COLORS[k % PASS_COLORS.len()]
}

fn graph(ui: &mut egui::Ui, stats: &FrameStats) {
    let (rect, _) = ui.allocate_exact_size(egui::vec2(ui.available_width(), 80.0), egui::Sense::hover());
    let painter = ui.painter_at(rect);
    painter.rect_filled(rect, 2.0, egui::Color32::from_gray(20));
    let top = stats
        .history
        .iter()
        .flat_map(|s| [Some(s.cpu_ms), Some(s.passes.iter().map(|p| p.1).sum()), s.interval_ms])
        .flatten()
        .fold(1.0f64, f64::max);
    let column = rect.width() / GRAPH_FRAMES as f32;
    let x_of = |i: usize| rect.left() + column * i as f32;
    let y_of = |ms: f64| rect.bottom() - rect.height() * (ms / top) as f32;
    for (i, sample) in stats.history.iter().enumerate() {
        let mut below = 0.0;
        for (k, (_, ms)) in sample.passes.iter().enumerate() {
            let bar = egui::Rect::from_min_max(
                egui::pos2(x_of(i), y_of(below + ms)),
                egui::pos2(x_of(i) + column.max(1.0), y_of(below)),
            );
            painter.rect_filled(bar, 0.0, pass_color(k));
            below += ms;
        }
    }
    let line = |value: &dyn Fn(&FrameSample) -> Option<f64>, color| {
        let points: Vec<egui::Pos2> = stats
            .history
            .iter()
            .enumerate()
            .filter_map(|(i, s)| value(s).map(|ms| egui::pos2(x_of(i) + 0.5 * column, y_of(ms))))
            .collect();
        painter.add(egui::Shape::line(points, egui::Stroke::new(1.0, color)));
    };
    line(&|s| s.interval_ms, FRAME_COLOR);
    line(&|s| Some(s.cpu_ms), CPU_COLOR);
    painter.text(
        rect.left_top() + egui::vec2(4.0, 2.0),
        egui::Align2::LEFT_TOP,
        format!("{top:.0} ms"),
        egui::FontId::monospace(10.0),
        egui::Color32::GRAY,
    );
    ui.horizontal(|ui| {
        ui.colored_label(FRAME_COLOR, "frame interval");
        ui.label("over GPU passes (stacked);");
        ui.colored_label(CPU_COLOR, "CPU");
    });
}
