//! The arrays a render can return, by name: chiaro-batch's outputs (job lists name them
//! the same way), read here from a render's `outputs=` argument.

pub use chiaro_batch::outputs::{Output, Outputs};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;

/// Reads `outputs=`: a string or a sequence of strings naming outputs (None: rgb).
pub fn extract_outputs(value: Option<&Bound<'_, PyAny>>) -> PyResult<Outputs> {
    let Some(value) = value.filter(|v| !v.is_none()) else { return Ok(Outputs::default()) };
    let names: Vec<String> = if let Ok(one) = value.extract::<String>() {
        vec![one]
    } else {
        value.extract::<Vec<String>>().map_err(|_| {
            PyTypeError::new_err("outputs: expected a sequence of output names such as ('rgb', 'depth')")
        })?
    };
    Outputs::from_names(&names).map_err(PyValueError::new_err)
}
