//! The page's DOM and browser calls the rest of the module uses: elements by id, fetch,
//! the clock, animation frames, and the title and message that report errors.

use wasm_bindgen::closure::Closure;
use wasm_bindgen::{JsCast, JsValue};
use wasm_bindgen_futures::JsFuture;

pub fn window() -> web_sys::Window {
    web_sys::window().expect("the page has a window")
}

pub fn document() -> web_sys::Document {
    window().document().expect("the window has a document")
}

/// The element with `id`, as the type the page's HTML gives it.
pub fn by_id<T: JsCast>(id: &str) -> Result<T, String> {
    document()
        .get_element_by_id(id)
        .ok_or_else(|| format!("the page has no element #{id}"))?
        .dyn_into::<T>()
        .map_err(|_| format!("#{id} is not the kind of element the page expects"))
}

/// A thrown JavaScript value as a message.
pub fn js_message(value: &JsValue) -> String {
    if let Some(error) = value.dyn_ref::<js_sys::Error>() {
        return String::from(error.message());
    }
    value.as_string().unwrap_or_else(|| format!("{value:?}"))
}

/// The response to `url` (relative to the page), refused unless it is a success.
async fn fetch(url: &str) -> Result<web_sys::Response, String> {
    let response =
        JsFuture::from(window().fetch_with_str(url)).await.map_err(|e| format!("{url}: {}", js_message(&e)))?;
    let response: web_sys::Response = response.dyn_into().map_err(|_| format!("{url}: fetch gave no response"))?;
    if !response.ok() {
        return Err(format!("{url}: HTTP {} {}", response.status(), response.status_text()));
    }
    Ok(response)
}

pub async fn fetch_bytes(url: &str) -> Result<Vec<u8>, String> {
    let response = fetch(url).await?;
    let buffer = response.array_buffer().map_err(|e| format!("{url}: {}", js_message(&e)))?;
    let buffer = JsFuture::from(buffer).await.map_err(|e| format!("{url}: {}", js_message(&e)))?;
    Ok(js_sys::Uint8Array::new(&buffer).to_vec())
}

pub async fn fetch_text(url: &str) -> Result<String, String> {
    let response = fetch(url).await?;
    let text = response.text().map_err(|e| format!("{url}: {}", js_message(&e)))?;
    let text = JsFuture::from(text).await.map_err(|e| format!("{url}: {}", js_message(&e)))?;
    text.as_string().ok_or_else(|| format!("{url}: the response is not text"))
}

/// Milliseconds since the page's navigation started.
pub fn now_ms() -> f64 {
    window().performance().map_or(0.0, |p| p.now())
}

/// Resolves at the browser's next animation frame: the page yields so that the browser
/// presents what was drawn and handles input.
pub async fn next_animation_frame() {
    let promise = js_sys::Promise::new(&mut |resolve, _| {
        let _ = window().request_animation_frame(&resolve);
    });
    let _ = JsFuture::from(promise).await;
}

/// Shows `message` on the page and in the title (`chiaro: error: MESSAGE`), which tests
/// wait on.
pub fn report_error(message: &str) {
    document().set_title(&format!("chiaro: error: {message}"));
    web_sys::console::error_1(&JsValue::from_str(&format!("chiaro: {message}")));
    if let Ok(element) = by_id::<web_sys::HtmlElement>("chiaro-error") {
        element.set_text_content(Some(message));
        element.set_hidden(false);
    }
}

/// Hides the error message again (a new scene loaded).
pub fn clear_error() {
    if let Ok(element) = by_id::<web_sys::HtmlElement>("chiaro-error") {
        element.set_hidden(true);
    }
}

/// Sets `window.chiaro[key] = value`, making `window.chiaro` first if need be.
pub fn publish(key: &str, value: &JsValue) {
    let window = window();
    let chiaro = js_sys::Reflect::get(&window, &"chiaro".into()).ok().filter(JsValue::is_object).unwrap_or_else(|| {
        let object = js_sys::Object::new();
        let _ = js_sys::Reflect::set(&window, &"chiaro".into(), &object);
        object.into()
    });
    let _ = js_sys::Reflect::set(&chiaro, &key.into(), value);
}

/// `window.chiaro[key]` as a string (empty if it is not one).
pub fn published_string(key: &str) -> String {
    js_sys::Reflect::get(&window(), &"chiaro".into())
        .and_then(|chiaro| js_sys::Reflect::get(&chiaro, &key.into()))
        .ok()
        .and_then(|v| v.as_string())
        .unwrap_or_default()
}

/// A plain object of `(key, value)` pairs.
pub fn object(pairs: &[(&str, JsValue)]) -> JsValue {
    let object = js_sys::Object::new();
    for (key, value) in pairs {
        let _ = js_sys::Reflect::set(&object, &(*key).into(), value);
    }
    object.into()
}

/// Sets the text of element `id`, if the page has it.
pub fn set_text(id: &str, text: &str) {
    if let Ok(element) = by_id::<web_sys::HtmlElement>(id) {
        element.set_text_content(Some(text));
    }
}

/// Calls `handler` on every `kind` event at `target`.
pub fn listen<E: wasm_bindgen::convert::FromWasmAbi + 'static>(
    target: &web_sys::EventTarget,
    kind: &str,
    handler: impl FnMut(E) + 'static,
) {
    let closure = Closure::<dyn FnMut(E)>::new(handler);
    if target.add_event_listener_with_callback(kind, closure.as_ref().unchecked_ref()).is_ok() {
        // The page lives as long as its listeners: they are never removed.
        closure.forget();
    }
}
