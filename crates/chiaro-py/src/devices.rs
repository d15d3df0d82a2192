//! The adapters wgpu finds, described for `chiaro.devices()`; the package chooses among
//! them by name, type, index or PCI bus id.

use chiaro_render::GpuContext;
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// wgpu's device type as a lower-case name (as job records name it).
pub use chiaro_batch::meta::device_type_name;

/// One dict per adapter, in wgpu's order (the `index` a Renderer takes): index, name,
/// backend, device_type, driver, driver_info, vendor_id, device_id, pci_bus_id.
#[pyfunction]
pub fn adapters(py: Python<'_>) -> PyResult<Vec<Bound<'_, PyDict>>> {
    let infos: Vec<_> = py.detach(|| GpuContext::adapters().iter().map(|a| a.get_info()).collect());
    infos
        .into_iter()
        .enumerate()
        .map(|(index, info)| {
            let d = PyDict::new(py);
            d.set_item("index", index)?;
            d.set_item("name", &info.name)?;
            d.set_item("backend", info.backend.to_str())?;
            d.set_item("device_type", device_type_name(info.device_type))?;
            d.set_item("driver", &info.driver)?;
            d.set_item("driver_info", &info.driver_info)?;
            d.set_item("vendor_id", info.vendor)?;
            d.set_item("device_id", info.device)?;
            d.set_item("pci_bus_id", &info.device_pci_bus_id)?;
            Ok(d)
        })
        .collect()
}
