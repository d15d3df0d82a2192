//! Debug views computed from read-backs (AOVs, clusters, the shadow atlases), drawn into 2D
//! canvases in place of the 3D view, as the native viewer's panel shows them.

use super::dom::{by_id, document, js_message};
use chiaro_render::debug_images::DebugImage;
use wasm_bindgen::{Clamped, JsCast};

/// Shows `images` (none: the 3D view again).
pub fn show(images: &[DebugImage]) -> Result<(), String> {
    let holder: web_sys::HtmlElement = by_id("chiaro-debug-images")?;
    let view: web_sys::HtmlElement = by_id("chiaro-canvas")?;
    holder.set_inner_html("");
    view.set_hidden(!images.is_empty());
    holder.set_hidden(images.is_empty());
    for ([width, height], pixels) in images {
        let canvas: web_sys::HtmlCanvasElement = document()
            .create_element("canvas")
            .map_err(|e| js_message(&e))?
            .dyn_into()
            .map_err(|_| "a canvas element is not a canvas".to_string())?;
        canvas.set_width(*width as u32);
        canvas.set_height(*height as u32);
        let context: web_sys::CanvasRenderingContext2d = canvas
            .get_context("2d")
            .map_err(|e| js_message(&e))?
            .ok_or("no 2D context for a debug image")?
            .dyn_into()
            .map_err(|_| "the 2D context is not one".to_string())?;
        let bytes: &[u8] = pixels.as_flattened();
        let image = web_sys::ImageData::new_with_u8_clamped_array_and_sh(Clamped(bytes), *width as u32, *height as u32)
            .map_err(|e| js_message(&e))?;
        context.put_image_data(&image, 0.0, 0.0).map_err(|e| js_message(&e))?;
        holder.append_child(&canvas).map_err(|e| js_message(&e))?;
    }
    Ok(())
}
