//! Chiaro in the browser: the viewer page's wasm module. The page (`web/index.html`,
//! built by `scripts/web.sh build` into `target/web/`) loads a scene by URL, by drag and
//! drop or the demo, renders it with chiaro-render on the page's WebGPU, and publishes test
//! hooks (`document.title`, `window.chiaro.stats`). The pure parts (URL parameters,
//! statistics, dropped files) build and test on every target; the page itself only on
//! wasm32.

pub mod dropped;
pub mod params;
pub mod stats;

#[cfg(target_arch = "wasm32")]
mod page;
