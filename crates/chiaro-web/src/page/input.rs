//! Mouse and keys on the canvas, as in the native viewer: drag turns (about the target when
//! orbiting, about the eye when flying), the wheel zooms, W/A/S/D/Q/E fly (Shift: faster);
//! files dropped on the canvas open.

use super::app::App;
use super::dom::{js_message, listen, report_error};
use super::panel;
use chiaro_render::camera_rig::FlyInput;
use std::cell::{Cell, RefCell};
use std::collections::HashSet;
use std::rc::Rc;
use wasm_bindgen::JsCast;

/// The keys held down, for flying each frame.
#[derive(Clone, Default)]
pub struct Keys(Rc<RefCell<HashSet<String>>>);

impl Keys {
    /// The fly direction the held keys ask for (camera axes: x right, y up, z back), and
    /// whether Shift is held.
    pub fn fly_input(&self) -> (FlyInput, bool) {
        let keys = self.0.borrow();
        let held = |k: &str| if keys.contains(k) { 1.0 } else { 0.0 };
        let input =
            FlyInput::new(held("KeyD") - held("KeyA"), held("KeyE") - held("KeyQ"), held("KeyS") - held("KeyW"));
        (input, keys.contains("ShiftLeft") || keys.contains("ShiftRight"))
    }
}

/// Listens on `canvas` (mouse, wheel, drops) and the window (keys); returns the held keys.
pub fn listen_all(app: &Rc<RefCell<App>>, canvas: &web_sys::HtmlCanvasElement) -> Keys {
    let dragging = Rc::new(Cell::new(None::<(i32, i32)>));
    let keys = Keys::default();
    let canvas_target: &web_sys::EventTarget = canvas.as_ref();
    {
        let dragging = dragging.clone();
        listen(canvas_target, "mousedown", move |e: web_sys::MouseEvent| {
            dragging.set(Some((e.client_x(), e.client_y())));
        });
    }
    {
        let (app, dragging) = (app.clone(), dragging.clone());
        listen(canvas_target, "mousemove", move |e: web_sys::MouseEvent| {
            let Some((x, y)) = dragging.get() else { return };
            let (nx, ny) = (e.client_x(), e.client_y());
            dragging.set(Some((nx, ny)));
            let mut app = app.borrow_mut();
            let navigation = app.navigation;
            app.rig.drag(navigation, (nx - x) as f32, (ny - y) as f32);
            app.dirty = true;
        });
    }
    let window = super::dom::window();
    {
        let dragging = dragging.clone();
        listen(window.as_ref(), "mouseup", move |_: web_sys::MouseEvent| dragging.set(None));
    }
    {
        let app = app.clone();
        listen(canvas_target, "wheel", move |e: web_sys::WheelEvent| {
            e.prevent_default();
            let mut app = app.borrow_mut();
            // One notch of a wheel is about 100 pixels of deltaY.
            app.rig.zoom((-e.delta_y() / 100.0) as f32);
            app.dirty = true;
        });
    }
    {
        let keys = keys.clone();
        listen(window.as_ref(), "keydown", move |e: web_sys::KeyboardEvent| {
            if !is_typing(&e) {
                keys.0.borrow_mut().insert(e.code());
            }
        });
    }
    {
        let keys = keys.clone();
        listen(window.as_ref(), "keyup", move |e: web_sys::KeyboardEvent| {
            keys.0.borrow_mut().remove(&e.code());
        });
    }
    {
        // Keys released while the window had no focus send no keyup: forget them all.
        let keys = keys.clone();
        listen(window.as_ref(), "blur", move |_: web_sys::FocusEvent| keys.0.borrow_mut().clear());
    }
    listen(canvas_target, "dragover", move |e: web_sys::DragEvent| e.prevent_default());
    {
        let app = app.clone();
        listen(canvas_target, "drop", move |e: web_sys::DragEvent| {
            e.prevent_default();
            let Some(files) = e.data_transfer().and_then(|d| d.files()) else {
                report_error("the drop carried no files");
                return;
            };
            let app = app.clone();
            wasm_bindgen_futures::spawn_local(async move { panel::open_files(&app, files).await });
        });
    }
    keys
}

/// Keys typed into the panel's fields do not fly the camera.
fn is_typing(e: &web_sys::KeyboardEvent) -> bool {
    e.target()
        .and_then(|t| t.dyn_into::<web_sys::Element>().ok())
        .is_some_and(|el| matches!(el.tag_name().as_str(), "INPUT" | "TEXTAREA" | "SELECT"))
}

/// The bytes of a browser `File`.
pub async fn file_bytes(file: &web_sys::File) -> Result<Vec<u8>, String> {
    let buffer = wasm_bindgen_futures::JsFuture::from(file.array_buffer())
        .await
        .map_err(|e| format!("{}: {}", file.name(), js_message(&e)))?;
    Ok(js_sys::Uint8Array::new(&buffer).to_vec())
}
