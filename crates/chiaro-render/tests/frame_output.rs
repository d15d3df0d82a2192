//! What frames deliver on the software device: the same image in a texture of the
//! caller's (as a window's surface would be) as offscreen, GPU times for frames nobody
//! waited for, and tone mapping equal to its CPU twin.

mod common;

use chiaro_math::tonemap::{aces_fitted, agx, exposure_scale, linear_clamp, pbr_neutral};
use chiaro_render::readback::{copy_texture, finish_copies};
use chiaro_render::{FrameOptions, View};
use chiaro_scene::demo::demo_scene;
use chiaro_scene::{Settings, ToneMapping};
use common::{renderer, srgb_encode};
use glam::Vec3;

const SIZE: u32 = 96;

#[test]
fn a_frame_renders_into_a_texture_of_the_callers_as_it_does_offscreen() {
    let mut renderer = renderer();
    let scene = demo_scene(4);
    let prepared = renderer.prepare(&scene).unwrap();
    let view = View::from_camera(&scene, 0, SIZE, SIZE);
    let settings = Settings::default();
    let offscreen = renderer
        .render(&scene, &prepared, &view, &settings, FrameOptions { readback: true, ..Default::default() })
        .unwrap();
    // A linear BGRA target, as many window surfaces are: the shader encodes sRGB itself
    // and the channels come swapped.
    for (format, bgra) in [(wgpu::TextureFormat::Bgra8Unorm, true), (wgpu::TextureFormat::Rgba8UnormSrgb, false)] {
        let texture = renderer.ctx.device.create_texture(&wgpu::TextureDescriptor {
            label: Some("caller's target"),
            size: wgpu::Extent3d { width: SIZE, height: SIZE, depth_or_array_layers: 1 },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        });
        let target = texture.create_view(&Default::default());
        let frame =
            renderer.render_to(&scene, &prepared, &view, &settings, FrameOptions::default(), &target, format).unwrap();
        assert!(frame.ldr.is_empty() && frame.timings.wall_ms.is_none(), "nothing read back or waited for");
        let mut encoder = renderer.ctx.device.create_command_encoder(&Default::default());
        let copy = copy_texture(&renderer.ctx.device, &mut encoder, &texture, 4);
        renderer.ctx.queue.submit([encoder.finish()]);
        let bytes = finish_copies(&renderer.ctx, vec![copy]).unwrap().remove(0);
        let mut worst = 0;
        for (got, want) in bytes.chunks_exact(4).zip(offscreen.ldr.chunks_exact(4)) {
            let got = if bgra { [got[2], got[1], got[0]] } else { [got[0], got[1], got[2]] };
            for c in 0..3 {
                worst = worst.max((got[c] as i32 - want[c] as i32).abs());
            }
        }
        assert!(worst <= 1, "{format:?}: differs from the offscreen image by up to {worst}/255");
    }
}

#[test]
fn frames_nobody_waits_for_report_their_gpu_times_later() {
    let mut renderer = renderer();
    let scene = demo_scene(4);
    let prepared = renderer.prepare(&scene).unwrap();
    let view = View::from_camera(&scene, 0, SIZE, SIZE);
    let mut frames = Vec::new();
    let mut planned = Vec::new();
    for _ in 0..4 {
        let out = renderer.render(&scene, &prepared, &view, &Settings::default(), FrameOptions::default()).unwrap();
        assert!(out.timings.gpu_pass_ms.is_empty() && out.timings.wall_ms.is_none());
        frames.push(out.timings.frame);
        planned.push(out.graph.passes.clone());
    }
    // The first frame draws the shadow tiles; the still frames after it keep them cached.
    assert_eq!(planned[0], ["shadows", "depth prepass", "forward", "tonemap"]);
    assert_eq!(planned[3], ["depth prepass", "forward", "tonemap"]);
    assert_eq!(frames, vec![0, 1, 2, 3]);
    let times = renderer.gpu_times(true).unwrap();
    let numbers: Vec<u64> = times.iter().map(|t| t.frame).collect();
    assert_eq!(numbers, frames, "every frame's times arrive once, in order");
    for (t, planned) in times.iter().zip(&planned) {
        let passes: Vec<&str> = t.passes.iter().map(|(p, _)| *p).collect();
        assert_eq!(&passes, planned);
        assert!(t.passes.iter().all(|(_, ms)| *ms > 0.0 && ms.is_finite()), "{t:?}");
    }
    assert!(renderer.gpu_times(true).unwrap().is_empty(), "taken once");
}

#[test]
fn every_tone_mapping_matches_its_cpu_twin() {
    let mut renderer = renderer();
    let scene = demo_scene(8);
    let prepared = renderer.prepare(&scene).unwrap();
    let view = View::from_camera(&scene, 0, SIZE, SIZE);
    let exposure = exposure_scale(-2.0);
    let mut images = Vec::new();
    for (curve, twin) in [
        (ToneMapping::PbrNeutral, pbr_neutral as fn(Vec3) -> Vec3),
        (ToneMapping::Aces, aces_fitted),
        (ToneMapping::Agx, agx),
        (ToneMapping::Linear, linear_clamp),
    ] {
        // Two stops brighter than the default, so highlights reach the compressed range.
        let mut settings = Settings::default();
        settings.render.exposure_ev100 = -2.0;
        settings.render.tone_mapping = curve;
        let options = FrameOptions { readback: true, ..Default::default() };
        let frame = renderer.render(&scene, &prepared, &view, &settings, options).unwrap();
        let (mut compressed, mut worst) = (0, 0.0f32);
        for (hdr, ldr) in frame.hdr.iter().zip(frame.ldr.chunks_exact(4)) {
            let exposed = Vec3::new(hdr[0], hdr[1], hdr[2]) * exposure;
            if exposed.max_element() > 0.8 {
                compressed += 1;
            }
            let display = twin(exposed.max(Vec3::ZERO));
            for c in 0..3 {
                let expected = srgb_encode(display[c]) * 255.0;
                worst = worst.max((ldr[c] as f32 - expected).abs());
            }
        }
        assert!(compressed > 100, "{curve:?}: only {compressed} pixels in the highlight roll-off");
        assert!(worst <= 1.0, "{curve:?}: tone mapped pixels differ from chiaro_math::tonemap by up to {worst}/255");
        images.push(frame.ldr);
    }
    // Each curve draws its own picture.
    for (i, a) in images.iter().enumerate() {
        for b in &images[i + 1..] {
            let differing = a.chunks_exact(4).zip(b.chunks_exact(4)).filter(|(p, q)| p != q).count();
            assert!(differing > 1000, "two curves agree on all but {differing} pixels");
        }
    }
}

#[test]
fn frames_submitted_before_the_last_is_read_back_come_back_as_rendered_one_at_a_time() {
    let mut renderer = renderer();
    let scene = demo_scene(4);
    let prepared = renderer.prepare(&scene).unwrap();
    let settings = Settings::default();
    let options = FrameOptions { readback: true, aovs: true, ids: true, ..Default::default() };
    let views: Vec<View> = [Vec3::new(6.0, 4.0, 8.0), Vec3::new(-7.0, 5.0, 3.0), Vec3::new(2.0, 9.0, -6.0)]
        .into_iter()
        .map(|eye| {
            let mut view = View::from_camera(&scene, 0, SIZE, SIZE);
            view.world_from_view = glam::Mat4::look_at_rh(eye, Vec3::ZERO, Vec3::Y).inverse();
            view
        })
        .collect();
    let alone: Vec<_> =
        views.iter().map(|v| renderer.render(&scene, &prepared, v, &settings, options).unwrap()).collect();
    // Three frames in flight at most two at a time: the third submission waits for the
    // first, whose read-back buffers must still hold its own pixels.
    let first = renderer.submit(&scene, &prepared, &views[0], &settings, options).unwrap();
    let second = renderer.submit(&scene, &prepared, &views[1], &settings, options).unwrap();
    let third = renderer.submit(&scene, &prepared, &views[2], &settings, options).unwrap();
    let pipelined =
        [renderer.finish(first).unwrap(), renderer.finish(second).unwrap(), renderer.finish(third).unwrap()];
    for (k, (one, piped)) in alone.iter().zip(&pipelined).enumerate() {
        assert_eq!(one.ldr, piped.ldr, "view {k}: the tone-mapped image");
        assert_eq!(one.aovs.as_ref().unwrap().depth, piped.aovs.as_ref().unwrap().depth, "view {k}: depth");
        assert_eq!(one.ids.as_ref().unwrap().instance, piped.ids.as_ref().unwrap().instance, "view {k}: ids");
        assert!(piped.timings.wall_ms.is_some());
    }
    assert_ne!(alone[0].ldr, alone[1].ldr, "the views differ, so a mix-up would show");
}

#[test]
fn a_depth_only_frame_gives_the_depth_of_a_full_aov_frame() {
    let mut renderer = renderer();
    let scene = demo_scene(4);
    let prepared = renderer.prepare(&scene).unwrap();
    let view = View::from_camera(&scene, 0, SIZE, SIZE);
    let settings = Settings::default();
    let full = FrameOptions { readback: true, aovs: true, ..Default::default() };
    let all = renderer.render(&scene, &prepared, &view, &settings, full).unwrap();
    let only = renderer.render(&scene, &prepared, &view, &settings, FrameOptions { depth_only: true, ..full }).unwrap();
    let (all, only) = (all.aovs.unwrap(), only.aovs.unwrap());
    assert_eq!(all.depth, only.depth);
    assert!(all.depth.iter().any(|d| d.is_infinite()) && all.depth.iter().any(|d| d.is_finite()));
    assert!(only.position_ws.is_empty() && only.normal_ws.is_empty() && only.baked_irradiance.is_empty());
}

#[test]
fn a_frame_that_skips_the_radiance_gives_the_same_image_and_depth_without_it() {
    let mut renderer = renderer();
    let scene = demo_scene(4);
    let prepared = renderer.prepare(&scene).unwrap();
    let view = View::from_camera(&scene, 0, SIZE, SIZE);
    let settings = Settings::default();
    let full = FrameOptions { readback: true, aovs: true, depth_only: true, ..Default::default() };
    let with = renderer.render(&scene, &prepared, &view, &settings, full).unwrap();
    let without =
        renderer.render(&scene, &prepared, &view, &settings, FrameOptions { skip_hdr: true, ..full }).unwrap();
    assert_eq!(with.hdr.len(), (SIZE * SIZE) as usize);
    assert!(without.hdr.is_empty(), "the radiance stayed on the GPU");
    assert_eq!(with.ldr, without.ldr);
    assert_eq!(with.aovs.unwrap().depth, without.aovs.unwrap().depth);
}
