//! `chiaro._chiaro`, the extension module under the `chiaro` Python package: scenes,
//! lights and cameras as Python objects, a renderer that returns numpy arrays, job lists
//! rendered into folders, the device list, and Chiaro's errors as Python exceptions.
//! `python/chiaro/__init__.py` adds the parts that are plain Python (device choice by
//! name, `doctor`, docstrings).

mod arrays;
mod camera;
mod comparison;
mod devices;
mod errors;
mod jobs;
mod light;
mod outputs;
mod renderer;
mod scene;

use pyo3::prelude::*;

#[pymodule]
fn _chiaro(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add("ChiaroError", py.get_type::<errors::ChiaroError>())?;
    m.add("SceneError", py.get_type::<errors::SceneError>())?;
    m.add("SettingsError", py.get_type::<errors::SettingsError>())?;
    m.add("DeviceError", py.get_type::<errors::DeviceError>())?;
    m.add("RenderError", py.get_type::<errors::RenderError>())?;
    m.add_class::<scene::Scene>()?;
    m.add_class::<light::Light>()?;
    m.add_class::<camera::Camera>()?;
    m.add_class::<renderer::RendererCore>()?;
    m.add_function(wrap_pyfunction!(scene::load, m)?)?;
    m.add_function(wrap_pyfunction!(devices::adapters, m)?)?;
    m.add_function(wrap_pyfunction!(jobs::render_jobs, m)?)?;
    m.add("OUTPUTS", outputs::Output::NAMES.to_vec())?;
    Ok(())
}
