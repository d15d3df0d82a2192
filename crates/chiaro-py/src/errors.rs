//! Chiaro's exceptions, and the conversions from the Rust crates' errors into them. Every
//! message is the one the CLI prints for the same failure.

use pyo3::exceptions::PyException;
use pyo3::{PyErr, create_exception};

create_exception!(chiaro, ChiaroError, PyException, "Every error Chiaro raises derives from this one.");
create_exception!(chiaro, SceneError, ChiaroError, "A scene file that cannot be read: the file and the problem.");
create_exception!(chiaro, SettingsError, ChiaroError, "Settings that cannot be used: the file or key, and why.");
create_exception!(chiaro, DeviceError, ChiaroError, "No device to render with, or not the one asked for.");
create_exception!(chiaro, RenderError, ChiaroError, "The GPU failed while rendering (a validation or device error).");

/// A renderer error as the exception that fits it: no adapter or device is a
/// `DeviceError`, anything else a `RenderError`.
pub fn render_error(e: chiaro_render::RenderError) -> PyErr {
    match e {
        chiaro_render::RenderError::NoAdapter(_) | chiaro_render::RenderError::Device(_) => {
            DeviceError::new_err(e.to_string())
        }
        other => RenderError::new_err(other.to_string()),
    }
}
