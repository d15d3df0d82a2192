//! `chiaro.render_jobs`: a job list rendered into one folder per job, on a Renderer's
//! device, as `chiaro batch` renders it (chiaro-batch does the work for both). Job lines
//! (JSON text), an output folder, a shard and a renderer flow in; counts of done, skipped
//! and failed jobs, with each failure's message, flow out.

use crate::renderer::RendererCore;
use chiaro_batch::{BatchError, BatchRunner, Shard, parse_jobs, prepare_output, shard_jobs};
use pyo3::exceptions::{PyOSError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::PathBuf;

/// Reads `shard=`: None, an (index, count) pair, or "I/N".
fn extract_shard(value: Option<&Bound<'_, PyAny>>) -> PyResult<Option<Shard>> {
    let Some(value) = value.filter(|v| !v.is_none()) else { return Ok(None) };
    let shard = if let Ok(text) = value.extract::<String>() {
        Shard::parse(&text)
    } else if let Ok((index, count)) = value.extract::<(i64, i64)>() {
        if index < 0 || count < 0 {
            return Err(PyValueError::new_err(format!("shard: ({index}, {count}) has a negative number")));
        }
        Shard::new(index as usize, count as usize, &format!("shard ({index}, {count})"))
    } else {
        return Err(PyTypeError::new_err("shard: expected None, an (index, count) pair or an 'I/N' string"));
    };
    shard.map(Some).map_err(|e| PyValueError::new_err(e.to_string()))
}

fn batch_error(e: BatchError) -> PyErr {
    match e {
        BatchError::Output { .. } => PyOSError::new_err(e.to_string()),
        other => PyValueError::new_err(other.to_string()),
    }
}

/// Renders the jobs of `lines` (one job's JSON text each; `source` names them in
/// messages, with the 1-based item as the line) that `shard` selects into `output`, on
/// `renderer`'s device and over its settings; see `chiaro.render_jobs`.
#[pyfunction]
#[pyo3(signature = (lines, output, source, shard, renderer))]
pub fn render_jobs<'py>(
    py: Python<'py>,
    lines: Vec<String>,
    output: PathBuf,
    source: String,
    shard: Option<&Bound<'py, PyAny>>,
    renderer: &Bound<'py, RendererCore>,
) -> PyResult<Bound<'py, PyDict>> {
    let shard = extract_shard(shard)?;
    let jobs = parse_jobs(lines.iter().map(String::as_str), &source).map_err(|e| batch_error(e.into()))?;
    let jobs = shard_jobs(jobs, shard);
    prepare_output(&output).map_err(batch_error)?;
    let core = renderer.get();
    let summary = py.detach(|| {
        core.lend(|renderer, settings| BatchRunner::new(renderer, settings.clone()).run_all(&jobs, &output, |_| {}))
    });
    let errors = PyDict::new(py);
    for (id, message) in &summary.failed {
        errors.set_item(id, message)?;
    }
    let result = PyDict::new(py);
    result.set_item("done", summary.done)?;
    result.set_item("skipped", summary.skipped)?;
    result.set_item("failed", summary.failed.len())?;
    result.set_item("errors", errors)?;
    Ok(result)
}
