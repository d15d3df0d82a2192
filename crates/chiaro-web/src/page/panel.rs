//! The settings panel, in HTML: the scene (open files, the demo), its camera, orbit or
//! fly, the debug views the page can draw, and every setting as the TOML of
//! docs/settings.md, applied when valid (an invalid one shows its error and changes
//! nothing). HTML rather than egui: the page's text fields, selects and file buttons come
//! with the browser, and the canvas stays the renderer's alone, so its pixels are exactly
//! what `chiaro render` writes.

use super::app::{App, page_debug_views};
use super::dom::{by_id, clear_error, report_error, set_text};
use super::input::file_bytes;
use super::load;
use chiaro_render::camera_rig::Navigation;
use chiaro_scene::{Light, LightKind, Scene, Settings, ShadowMode};
use std::cell::RefCell;
use std::rc::Rc;
use wasm_bindgen::JsCast;
use web_sys::{HtmlButtonElement, HtmlInputElement, HtmlSelectElement, HtmlTextAreaElement};

fn set_options(select: &HtmlSelectElement, options: &[(String, String)], selected: &str) {
    select.set_inner_html("");
    let document = super::dom::document();
    for (value, label) in options {
        if let Ok(option) = document.create_element("option") {
            let _ = option.set_attribute("value", value);
            option.set_text_content(Some(label));
            let _ = select.append_child(&option);
        }
    }
    select.set_value(selected);
}

/// Fills the panel from `app` (after a scene or settings change).
pub fn fill(app: &App) -> Result<(), String> {
    let mut cameras = vec![("frame".to_string(), "frame the scene".to_string())];
    cameras.extend(app.scene.cameras.iter().enumerate().map(|(i, c)| (i.to_string(), format!("{i}: {}", c.name))));
    let camera = app.camera.map_or("frame".to_string(), |i| i.to_string());
    set_options(&by_id("chiaro-camera")?, &cameras, &camera);
    // Options by index into the page's list (a light's shadow AOV has no --debug name).
    let views = page_debug_views(app.scene.lights.len());
    let mut debug = vec![("none".to_string(), "none".to_string())];
    debug.extend(views.iter().enumerate().map(|(i, d)| (i.to_string(), d.label())));
    let shown =
        app.debug.and_then(|d| views.iter().position(|v| *v == d)).map_or("none".to_string(), |i| i.to_string());
    set_options(&by_id("chiaro-debug")?, &debug, &shown);
    fill_lights(app)?;
    by_id::<HtmlTextAreaElement>("chiaro-settings")?.set_value(&app.settings.to_toml());
    set_text("chiaro-settings-error", "");
    set_text("chiaro-scene-info", &scene_info(&app.scene));
    Ok(())
}

/// Shadow modes as a light's `extras.shadows` names them.
const SHADOW_MODES: [ShadowMode; 4] = [ShadowMode::None, ShadowMode::Hard, ShadowMode::Soft, ShadowMode::Pcss];

/// Most lights listed (the benchmark scene has 65; a scene of thousands would bury the
/// panel): each with its shadow mode, PCSS among them.
const MOST_LIGHTS_LISTED: usize = 128;

/// One row per light: its name and a select of its shadow mode (`data-light` = index).
fn fill_lights(app: &App) -> Result<(), String> {
    let holder: web_sys::HtmlElement = by_id("chiaro-lights")?;
    holder.set_inner_html("");
    let document = super::dom::document();
    let modes: Vec<(String, String)> =
        SHADOW_MODES.iter().map(|m| (m.name().to_string(), m.name().to_string())).collect();
    for (i, light) in app.scene.lights.iter().enumerate().take(MOST_LIGHTS_LISTED) {
        let row = document.create_element("label").map_err(|e| super::dom::js_message(&e))?;
        let name = if light.name.is_empty() { format!("light {i}") } else { light.name.clone() };
        row.set_text_content(Some(&format!("{name} ({}) ", light.kind.name())));
        let select: HtmlSelectElement = document
            .create_element("select")
            .map_err(|e| super::dom::js_message(&e))?
            .dyn_into()
            .map_err(|_| "a select element is not one".to_string())?;
        let _ = select.set_attribute("data-light", &i.to_string());
        set_options(&select, &modes, light.shadow.mode.name());
        let _ = row.append_child(&select);
        // The light's size, which PCSS widens the penumbra by: a radius in metres for
        // point and spot lights, the disc's angular diameter in degrees for directional.
        let size = document.create_element("input").map_err(|e| super::dom::js_message(&e))?;
        let (value, unit) = match light.kind {
            LightKind::Directional => (light.shadow.angular_diameter_deg, "deg"),
            _ => (light.shadow.light_radius, "m"),
        };
        for (key, v) in [("type", "number"), ("min", "0"), ("step", "0.01"), ("title", unit)] {
            let _ = size.set_attribute(key, v);
        }
        let _ = size.set_attribute("data-light-size", &i.to_string());
        let _ = size.set_attribute("value", &value.to_string());
        let _ = row.append_child(&size);
        let _ = holder.append_child(&row);
    }
    if app.scene.lights.len() > MOST_LIGHTS_LISTED {
        let more = document.create_element("p").map_err(|e| super::dom::js_message(&e))?;
        more.set_text_content(Some(&format!("and {} more", app.scene.lights.len() - MOST_LIGHTS_LISTED)));
        let _ = holder.append_child(&more);
    }
    Ok(())
}

/// PCSS's light size, within what the importer accepts: a radius no larger than the
/// light's range, a disc narrower than 180 degrees.
fn set_light_size(light: &mut Light, size: f32) {
    match light.kind {
        LightKind::Directional => light.shadow.angular_diameter_deg = size.min(179.0),
        _ => light.shadow.light_radius = light.range.map_or(size, |range| size.min(range)),
    }
}

fn scene_info(scene: &Scene) -> String {
    let name = scene.source.as_ref().map_or("the demo".to_string(), |p| p.display().to_string());
    format!(
        "{name}: {} triangles, {} lights, {} cameras",
        scene.triangle_count(),
        scene.lights.len(),
        scene.cameras.len()
    )
}

/// Wires the panel's controls to `app`.
pub fn listen(app: &Rc<RefCell<App>>) -> Result<(), String> {
    let camera: HtmlSelectElement = by_id("chiaro-camera")?;
    {
        let (app, select) = (app.clone(), camera.clone());
        super::dom::listen(camera.as_ref(), "change", move |_: web_sys::Event| {
            let index = select.value().parse::<usize>().ok();
            app.borrow_mut().use_camera(index);
        });
    }
    let navigation: HtmlSelectElement = by_id("chiaro-navigation")?;
    {
        let (app, select) = (app.clone(), navigation.clone());
        super::dom::listen(navigation.as_ref(), "change", move |_: web_sys::Event| {
            app.borrow_mut().navigation = if select.value() == "fly" { Navigation::Fly } else { Navigation::Orbit };
        });
    }
    let debug: HtmlSelectElement = by_id("chiaro-debug")?;
    {
        let (app, select) = (app.clone(), debug.clone());
        super::dom::listen(debug.as_ref(), "change", move |_: web_sys::Event| {
            let mut app = app.borrow_mut();
            let views = page_debug_views(app.scene.lights.len());
            app.debug = select.value().parse::<usize>().ok().and_then(|i| views.get(i).copied());
            app.dirty = true;
        });
    }
    let lights: web_sys::HtmlElement = by_id("chiaro-lights")?;
    {
        let app = app.clone();
        // One listener for every row: the select that changed says which light it is.
        super::dom::listen(lights.as_ref(), "change", move |event: web_sys::Event| {
            let Some(target) = event.target() else { return };
            let mut app = app.borrow_mut();
            if let Ok(select) = target.clone().dyn_into::<HtmlSelectElement>() {
                let index = select.get_attribute("data-light").and_then(|i| i.parse::<usize>().ok());
                let mode = SHADOW_MODES.iter().copied().find(|m| m.name() == select.value());
                if let (Some(i), Some(mode)) = (index, mode)
                    && let Some(light) = app.scene.lights.get_mut(i)
                {
                    light.shadow.mode = mode;
                    app.dirty = true;
                }
            } else if let Ok(input) = target.dyn_into::<HtmlInputElement>() {
                let index = input.get_attribute("data-light-size").and_then(|i| i.parse::<usize>().ok());
                let size = input.value().parse::<f32>().ok().filter(|v| v.is_finite() && *v >= 0.0);
                if let (Some(i), Some(size)) = (index, size)
                    && let Some(light) = app.scene.lights.get_mut(i)
                {
                    set_light_size(light, size);
                    app.dirty = true;
                }
            }
        });
    }
    let apply: HtmlButtonElement = by_id("chiaro-apply")?;
    {
        let app = app.clone();
        super::dom::listen(apply.as_ref(), "click", move |_: web_sys::Event| {
            let result = by_id::<HtmlTextAreaElement>("chiaro-settings")
                .and_then(|text| Settings::parse(&text.value()))
                .and_then(|settings| app.borrow_mut().set_settings(settings));
            set_text("chiaro-settings-error", result.err().as_deref().unwrap_or(""));
        });
    }
    let open: HtmlInputElement = by_id("chiaro-open")?;
    {
        let (app, input) = (app.clone(), open.clone());
        super::dom::listen(open.as_ref(), "change", move |_: web_sys::Event| {
            if let Some(files) = input.files() {
                let app = app.clone();
                wasm_bindgen_futures::spawn_local(async move { open_files(&app, files).await });
            }
        });
    }
    let demo: HtmlButtonElement = by_id("chiaro-demo")?;
    {
        let app = app.clone();
        super::dom::listen(demo.as_ref(), "click", move |_: web_sys::Event| show_scene(&app, Ok(load::demo())));
    }
    fill(&app.borrow())
}

/// Opens the scene among `files` (dropped or chosen), with its buffers and images.
pub async fn open_files(app: &Rc<RefCell<App>>, files: web_sys::FileList) {
    let mut names = Vec::new();
    let mut contents = Vec::new();
    for i in 0..files.length() {
        let Some(file) = files.get(i) else { continue };
        match file_bytes(&file).await {
            Ok(bytes) => {
                names.push(file.name());
                contents.push(bytes);
            }
            Err(e) => return report_error(&e),
        }
    }
    show_scene(app, load::scene_from_dropped(&names, &contents));
}

fn show_scene(app: &Rc<RefCell<App>>, scene: Result<Scene, String>) {
    let mut app = app.borrow_mut();
    let result = scene.and_then(|s| load::with_variant(s, &app.settings)).and_then(|s| app.set_scene(s));
    match result.and_then(|()| fill(&app)) {
        Ok(()) => {
            super::dom::publish("scene_frames", &0.into());
            clear_error();
            super::dom::document().set_title("chiaro");
        }
        Err(e) => report_error(&e),
    }
}

/// Shows the last frame's time.
pub fn show_frame_time(ms: f64) {
    set_text("chiaro-frame-time", &format!("{ms:.1} ms a frame (to GPU completion)"));
}
