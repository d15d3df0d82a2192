//! The page: reads its URL parameters, loads the scene and settings, opens WebGPU on the
//! canvas, then either renders the requested frames, publishes their times and stops, or
//! runs the interactive viewer until the page closes.

mod app;
mod debug_images;
mod dom;
mod input;
mod load;
mod panel;

use crate::params::PageParams;
use crate::stats::FrameStats;
use app::App;
use chiaro_render::GpuContext;
use std::cell::RefCell;
use std::rc::Rc;
use wasm_bindgen::prelude::*;

/// What the browser build leaves out against the native viewer, as the page lists it.
const LACKS: [&str; 7] = [
    "virtual shadow maps (their page marking waits for a read-back within the frame)",
    "the baker and its lightmaps (threads), and the CPU ray-traced reference and its comparison view",
    "EXT_meshopt_compression (its decoder is C)",
    "files other than the scene's own: environment images and bakes named in settings",
    "saving images, settings or scenes (no filesystem): the panel's settings text can be copied",
    "per-pass GPU times (frame times are to GPU completion instead)",
    "the native panel's editors of light colour, intensity, cones and biases and of objects, picking and light outlines",
];

#[wasm_bindgen(start)]
pub fn start() {
    std::panic::set_hook(Box::new(|info| dom::report_error(&format!("panic: {info}"))));
    dom::publish("stats", &JsValue::NULL);
    let lacks: js_sys::Array = LACKS.iter().map(|s| JsValue::from_str(s)).collect();
    dom::publish("lacks", &lacks);
    wasm_bindgen_futures::spawn_local(async {
        if let Err(message) = run().await {
            dom::report_error(&message);
        }
    });
}

async fn run() -> Result<(), String> {
    let search = dom::window().location().search().unwrap_or_default();
    let params = PageParams::parse(&search)?;
    dom::set_text("chiaro-status", "loading the scene");
    let settings = load::settings(params.settings.as_deref()).await?;
    let width = params.width.unwrap_or(settings.render.width);
    let height = params.height.unwrap_or(settings.render.height);
    let canvas: web_sys::HtmlCanvasElement = dom::by_id("chiaro-canvas")?;
    canvas.set_width(width);
    canvas.set_height(height);
    // One canvas pixel per CSS pixel, so that a screenshot of it is the image.
    let style = canvas.style();
    style.set_property("width", &format!("{width}px")).map_err(|e| dom::js_message(&e))?;
    style.set_property("height", &format!("{height}px")).map_err(|e| dom::js_message(&e))?;
    if !params.panel {
        dom::by_id::<web_sys::HtmlElement>("chiaro-panel")?.set_hidden(true);
    }
    if params.check_shaders {
        let target = wgpu::SurfaceTarget::Canvas(canvas.clone());
        let (ctx, _) = GpuContext::for_surface_async(target).await.map_err(|e| e.to_string())?;
        return check_shaders(&ctx).await;
    }
    let scene = match params.scene.as_deref() {
        Some(url) => load::scene_from_url(url).await?,
        None => load::demo(),
    };
    let scene = load::with_variant(scene, &settings)?;
    dom::set_text("chiaro-status", "opening WebGPU");
    let target = wgpu::SurfaceTarget::Canvas(canvas.clone());
    let (ctx, surface) = GpuContext::for_surface_async(target).await.map_err(|e| e.to_string())?;
    let app = App::new(ctx, surface, scene, settings, params.camera.as_deref(), (width, height))?;
    let app = Rc::new(RefCell::new(app));
    panel::fill(&app.borrow())?;
    dom::set_text("chiaro-status", &app.borrow().adapter());
    match params.frames {
        Some(frames) => timed(&app, frames, params.warmup).await,
        None => {
            let keys = input::listen_all(&app, &canvas);
            panel::listen(&app)?;
            interactive(&app, keys).await
        }
    }
}

/// Compiles every shader artifact with the browser's own compiler (Tint in Chromium,
/// stricter than naga in places) and publishes `window.chiaro.shader_check`: `modules`
/// and every error message, labelled with its artifact.
async fn check_shaders(ctx: &GpuContext) -> Result<(), String> {
    let sources = chiaro_render::shaders::all();
    let mut errors = Vec::new();
    for &(name, source) in &sources {
        let module = chiaro_render::shaders::module(&ctx.device, name, source);
        for message in module.get_compilation_info().await.messages {
            if message.message_type == wgpu::CompilationMessageType::Error {
                errors.push(format!("{name}: {}", message.message));
            }
        }
    }
    let listed: js_sys::Array = errors.iter().map(|e| JsValue::from_str(e)).collect();
    dom::publish(
        "shader_check",
        &dom::object(&[("modules", (sources.len() as f64).into()), ("errors", listed.into())]),
    );
    dom::document().set_title("chiaro: done");
    Ok(())
}

/// Renders `warmup` frames, then `frames` timed ones, publishes `window.chiaro.stats` and
/// sets the title to `chiaro: done`.
async fn timed(app: &Rc<RefCell<App>>, frames: u32, warmup: u32) -> Result<(), String> {
    let mut times = Vec::with_capacity(frames as usize);
    let mut first_frame_ms = 0.0;
    let mut load_to_first_frame_ms = 0.0;
    for i in 0..warmup + frames {
        dom::next_animation_frame().await;
        // A timed run opens no other scene: every frame is this one's.
        let ms = App::frame(app).await?.unwrap_or_default();
        if i == 0 {
            first_frame_ms = ms;
            load_to_first_frame_ms = dom::now_ms();
        }
        if i >= warmup {
            times.push(ms);
        }
    }
    // The browser reports validation errors after the call that caused them returned.
    dom::next_animation_frame().await;
    app.borrow_mut().take_error()?;
    let adapter = app.borrow().adapter();
    let stats = FrameStats::new(&times, &adapter).ok_or("no frame was timed")?;
    panel::show_frame_time(stats.frame_ms_median);
    let all: js_sys::Array = times.iter().map(|&t| JsValue::from_f64(t)).collect();
    dom::publish(
        "stats",
        &dom::object(&[
            ("frame_ms_median", stats.frame_ms_median.into()),
            ("frame_ms_min", stats.frame_ms_min.into()),
            ("frame_ms_max", stats.frame_ms_max.into()),
            ("frames", (stats.frames as f64).into()),
            ("adapter", stats.adapter.as_str().into()),
            ("first_frame_ms", first_frame_ms.into()),
            ("load_to_first_frame_ms", load_to_first_frame_ms.into()),
            ("frame_ms", all.into()),
        ]),
    );
    dom::document().set_title("chiaro: done");
    Ok(())
}

/// Draws a frame whenever something changed, flying while keys are held.
async fn interactive(app: &Rc<RefCell<App>>, keys: input::Keys) -> Result<(), String> {
    let mut last = dom::now_ms();
    loop {
        dom::next_animation_frame().await;
        let now = dom::now_ms();
        let seconds = ((now - last) / 1000.0).min(0.1) as f32;
        last = now;
        let (fly, fast) = keys.fly_input();
        app.borrow_mut().fly(fly, fast, seconds);
        // `idle`: every change so far is drawn (tests wait on it after an action).
        if !app.borrow().dirty {
            dom::publish("idle", &true.into());
            continue;
        }
        dom::publish("idle", &false.into());
        let result = App::frame(app).await.and_then(|ms| app.borrow_mut().take_error().map(|()| ms));
        match result {
            Ok(None) => {}
            Ok(Some(ms)) => {
                panel::show_frame_time(ms);
                let mut app = app.borrow_mut();
                app.scene_frames += 1;
                dom::publish("scene_frames", &f64::from(app.scene_frames).into());
            }
            Err(e) => dom::report_error(&e),
        }
    }
}
