//! The legacy LDR light buffer of Catlike Coding's "Rendering 15, Deferred Lights" (`light_buffer = "ldr-exp2"`) against the HDR one:
//! every write of exp2(-light) to 8 bits rounds, so a pixel's decoded light may be off by
//! up to one 8-bit step per write, 2^x / (255 ln 2) at exposed light x (half a step if
//! conversion and blending rounded to nearest; Vulkan lets them round either way), and
//! light beyond log2(255) (about 8 after exposure) clips there. Measured on a point light's falloff
//! (one write per pixel) and on the demo (one write per light volume shading the pixel,
//! counted with the overdraw view), allowing for the half-float rounding of both images.

mod common;

use chiaro_render::{DebugView, FrameOptions, FrameOutput, View};
use chiaro_scene::demo::demo_scene;
use chiaro_scene::{LightBuffer, RenderPath, Scene, Settings, ShadowMode};
use common::*;
use glam::Vec3;

fn deferred(
    scene: &Scene,
    settings: &Settings,
    light_buffer: LightBuffer,
    debug_view: Option<DebugView>,
) -> FrameOutput {
    let mut settings = settings.clone();
    settings.render.path = RenderPath::Deferred;
    settings.render.light_buffer = light_buffer;
    let mut r = renderer();
    let prepared = r.prepare(scene).unwrap();
    let view = View::from_camera(scene, 0, 256, 256);
    let options = FrameOptions { readback: true, debug: debug_view, ..Default::default() };
    r.render(scene, &prepared, &view, &settings, options).unwrap()
}

/// One 8-bit step of exp2(-x), in x.
fn step(x: f32) -> f32 {
    x.exp2() / (255.0 * std::f32::consts::LN_2)
}

const CLIP: f32 = 7.994; // log2(255)

struct Measured {
    /// Channels below the clip whose error exceeds `writes` steps.
    over_bound: usize,
    /// The largest error below the clip, in steps per write.
    worst_steps: f32,
    below_clip: usize,
    clipped: usize,
    worst_clipped_error: f32,
    /// Share of lit pixels within 2% of the HDR light, and the mean relative error.
    within_2_percent: f64,
    mean_relative: f64,
}

/// Compares the LDR frame with the HDR one in exposed units; `writes[i]` is how many
/// times pixel i was written.
fn measure(hdr: &FrameOutput, ldr: &FrameOutput, exposure: f32, writes: &[f32]) -> Measured {
    let mut m = Measured {
        over_bound: 0,
        worst_steps: 0.0,
        below_clip: 0,
        clipped: 0,
        worst_clipped_error: 0.0,
        within_2_percent: 0.0,
        mean_relative: 0.0,
    };
    let (mut lit, mut within, mut relative) = (0usize, 0usize, 0f64);
    for (i, (h, l)) in hdr.hdr.iter().zip(&ldr.hdr).enumerate() {
        for c in 0..3 {
            let (x, y) = (h[c] * exposure, l[c] * exposure);
            if x < 7.0 {
                m.below_clip += 1;
                // Both images are half floats: each rounds by up to 2^-11 relative.
                let half_float_rounding = (x + y) * 2f32.powi(-11) + 1e-4;
                let error = ((y - x).abs() - half_float_rounding).max(0.0);
                m.worst_steps = m.worst_steps.max(error / (writes[i] * step(x)));
                if error > writes[i] * step(x) {
                    m.over_bound += 1;
                }
            } else if x > 8.5 {
                m.clipped += 1;
                m.worst_clipped_error = m.worst_clipped_error.max((y - CLIP).abs());
            }
        }
        let x = h[0].max(h[1]).max(h[2]) * exposure;
        if x > 1e-3 {
            lit += 1;
            let e = (0..3).map(|c| (l[c] - h[c]).abs() / h[c].abs().max(1e-6)).fold(0.0, f32::max);
            within += (e <= 0.02) as usize;
            relative += e as f64;
        }
    }
    m.within_2_percent = within as f64 / lit.max(1) as f64;
    m.mean_relative = relative / lit.max(1) as f64;
    m
}

#[test]
fn one_write_is_off_by_at_most_a_step_and_bright_light_clips() {
    let mut light = point_light(Vec3::new(0.0, 0.6, 0.0), 40.0, Some(20.0));
    light.shadow.mode = ShadowMode::None;
    let scene = floor_scene(12.0, Vec3::new(0.0, 6.0, 0.01), vec![light]);
    let settings = unlit_settings();
    let exposure = chiaro_math::tonemap::exposure_scale(settings.render.exposure_ev100);
    let hdr = deferred(&scene, &settings, LightBuffer::Hdr, None);
    let ldr = deferred(&scene, &settings, LightBuffer::LdrExp2, None);
    let m = measure(&hdr, &ldr, exposure, &vec![1.0; hdr.hdr.len()]);
    println!(
        "one light: {} of {} channels below the clip beyond a step (worst {:.2} steps); {} clipped (worst {:.4} \
         off log2(255)); {:.2}% of lit pixels within 2%, mean relative error {:.2}%",
        m.over_bound,
        m.below_clip,
        m.worst_steps,
        m.clipped,
        m.worst_clipped_error,
        100.0 * m.within_2_percent,
        100.0 * m.mean_relative
    );
    assert!(m.below_clip > 100_000 && m.clipped > 300, "the falloff spans both ranges");
    assert_eq!(m.over_bound, 0);
    assert!(m.worst_clipped_error < 0.01);
}

#[test]
fn the_demo_stays_within_a_step_per_light_volume() {
    let scene = demo_scene(8);
    // Light accumulation is measured, not edges: no FXAA blending pixels across them.
    let mut settings = Settings::default();
    settings.render.deferred_antialiasing = chiaro_scene::DeferredAntialiasing::None;
    let exposure = chiaro_math::tonemap::exposure_scale(settings.render.exposure_ev100);
    let hdr = deferred(&scene, &settings, LightBuffer::Hdr, None);
    let ldr = deferred(&scene, &settings, LightBuffer::LdrExp2, None);
    let overdraw = deferred(&scene, &settings, LightBuffer::Hdr, Some(DebugView::LightOverdraw));
    // The G-buffer pass writes once, then each volume; the read-back undid the exposure.
    let writes: Vec<f32> = overdraw.hdr.iter().map(|p| 1.0 + (p[0] * exposure).round()).collect();
    let m = measure(&hdr, &ldr, exposure, &writes);
    println!(
        "demo: {} of {} channels beyond a step per write (worst {:.2}); {:.2}% of lit pixels within 2%, mean \
         relative error {:.2}%",
        m.over_bound,
        m.below_clip,
        m.worst_steps,
        100.0 * m.within_2_percent,
        100.0 * m.mean_relative
    );
    assert!(m.below_clip > 150_000);
    assert_eq!(m.over_bound, 0);
}
