//! `chiaro._Renderer`, under `chiaro.Renderer`: one device, its pipelines and the scene it
//! last uploaded. Frames are rendered without the GIL, one caller at a time (a mutex), and
//! `render_many` keeps two frames in flight, reading one back while the next renders.

use crate::arrays::FrameArrays;
use crate::camera::CameraChoice;
use crate::comparison::LightVerdict;
use crate::devices::device_type_name;
use crate::errors::{SettingsError, render_error};
use crate::outputs::{Output, Outputs, extract_outputs};
use crate::scene::{Scene, SceneState, SharedScene, read};
use chiaro_compare::{CompareOptions, EDGE_BAND_PX, MAX_EDGE_BAND_PX, compare_shadows_with};
use chiaro_render::{GpuContext, PreparedScene, RenderError, Renderer, View};
use chiaro_scene::Settings;
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::PathBuf;
use std::sync::{Mutex, MutexGuard};

/// The widest side a render may ask for before the device is asked (its own limit may be
/// lower, and is checked per frame).
const MAX_SIDE: i64 = 16384;
/// The most views one `render_many` call takes.
const MAX_VIEWS: usize = 100_000;

/// A scene uploaded to the device, and which version of which scene it is.
struct Uploaded {
    scene_id: u64,
    geometry_version: u64,
    gpu: PreparedScene,
}

struct Inner {
    renderer: Renderer,
    uploaded: Option<Uploaded>,
}

/// Why a frame failed, made into a Python exception once the GIL is held again.
enum Failure {
    Value(String),
    Render(RenderError),
}

impl From<RenderError> for Failure {
    fn from(e: RenderError) -> Self {
        Failure::Render(e)
    }
}

impl From<Failure> for PyErr {
    fn from(f: Failure) -> PyErr {
        match f {
            Failure::Value(message) => PyValueError::new_err(message),
            Failure::Render(RenderError::OutputSize { width, height, reason }) => {
                PyValueError::new_err(format!("output size {width}x{height} is invalid: {reason}"))
            }
            Failure::Render(e) => render_error(e),
        }
    }
}

/// The renderer behind `chiaro.Renderer` (which chooses the adapter and reads settings).
#[pyclass(module = "chiaro", name = "_Renderer", frozen)]
pub struct RendererCore {
    inner: Mutex<Inner>,
    settings: Settings,
    adapter_info: chiaro_render::wgpu::AdapterInfo,
    /// The device's texture array layers: the shadow output's most lights.
    max_shadow_layers: u32,
}

fn size(value: Option<i64>, default: u32, name: &str) -> PyResult<u32> {
    match value {
        None => Ok(default),
        Some(v) if (1..=MAX_SIDE).contains(&v) => Ok(v as u32),
        Some(v) => Err(PyValueError::new_err(format!("{name}: {v} is not between 1 and {MAX_SIDE} pixels"))),
    }
}

impl RendererCore {
    fn lock(&self) -> MutexGuard<'_, Inner> {
        self.inner.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// Renders one frame per view of the scene, two in flight, each read back into arrays.
    fn frames(
        &self,
        state: &SharedScene,
        cameras: &[CameraChoice],
        (width, height): (u32, u32),
        outputs: &Outputs,
    ) -> Result<Vec<FrameArrays>, Failure> {
        let guard = read(state);
        let lights = guard.scene.lights.len();
        if outputs.wants(Output::Shadow) && lights > self.max_shadow_layers as usize {
            return Err(Failure::Value(format!(
                "outputs: 'shadow' takes one layer per light, and this device holds at most {} (the scene has {lights} \
                 lights)",
                self.max_shadow_layers
            )));
        }
        let views: Vec<View> = cameras
            .iter()
            .map(|c| c.view(&guard.scene, &self.settings, width, height))
            .collect::<Result<_, _>>()
            .map_err(Failure::Value)?;
        let mut inner = self.lock();
        upload(&mut inner, &guard)?;
        let Inner { renderer, uploaded } = &mut *inner;
        let gpu = &uploaded.as_ref().expect("uploaded").gpu;
        let scene = &guard.scene;
        let options = outputs.frame_options();
        let shadow_nodes: Vec<usize> = scene.lights.iter().map(|l| l.node).collect();
        let mut arrays = Vec::with_capacity(views.len());
        let mut in_flight = None;
        for view in &views {
            // Each frame as on a new renderer: its arrays do not depend on the frames
            // before it, in this call or earlier ones.
            renderer.forget_history();
            let submitted = renderer.submit(scene, gpu, view, &self.settings, options)?;
            if let Some(previous) = in_flight.replace(submitted) {
                arrays.push(FrameArrays::new(renderer.finish(previous)?, outputs, shadow_nodes.clone()));
            }
        }
        if let Some(last) = in_flight {
            arrays.push(FrameArrays::new(renderer.finish(last)?, outputs, shadow_nodes));
        }
        Ok(arrays)
    }
}

impl RendererCore {
    /// Lends the renderer and its settings to `work` (a job list, which uploads its own
    /// scenes) under the lock. The scene this renderer uploaded is forgotten first, so the
    /// next frame here uploads again.
    pub(crate) fn lend<R>(&self, work: impl FnOnce(&mut Renderer, &Settings) -> R) -> R {
        let mut inner = self.lock();
        inner.uploaded = None;
        work(&mut inner.renderer, &self.settings)
    }
}

/// Uploads the scene unless the renderer holds this version of it; true when it uploaded.
fn upload(inner: &mut Inner, state: &SceneState) -> Result<bool, RenderError> {
    let current =
        inner.uploaded.as_ref().is_some_and(|u| u.scene_id == state.id && u.geometry_version == state.geometry_version);
    if current {
        return Ok(false);
    }
    inner.uploaded = None;
    let gpu = inner.renderer.prepare(&state.scene)?;
    inner.uploaded = Some(Uploaded { scene_id: state.id, geometry_version: state.geometry_version, gpu });
    Ok(true)
}

/// Settings from a dict (as JSON text) shaped like settings.toml: sections of keys.
fn settings_from_json(json: &str) -> Result<Settings, String> {
    let value: serde_json::Value = serde_json::from_str(json).map_err(|e| format!("settings: {e}"))?;
    let text = toml::to_string(&value).map_err(|e| format!("settings: cannot be written as TOML: {e}"))?;
    Settings::parse(&text).map_err(|e| format!("settings: {e}"))
}

#[pymethods]
impl RendererCore {
    /// Opens adapter `adapter` (an index into `chiaro.devices()`; None for wgpu's best)
    /// with settings from a TOML file, or from the JSON text of a dict shaped like that
    /// file (neither: the defaults).
    #[new]
    #[pyo3(signature = (adapter = None, settings_path = None, settings_json = None))]
    fn new(
        py: Python<'_>,
        adapter: Option<usize>,
        settings_path: Option<PathBuf>,
        settings_json: Option<String>,
    ) -> PyResult<RendererCore> {
        let settings = match (&settings_path, &settings_json) {
            (Some(path), _) => Settings::load(path).map_err(|e| SettingsError::new_err(e.to_string()))?,
            (None, Some(json)) => settings_from_json(json).map_err(SettingsError::new_err)?,
            (None, None) => Settings::default(),
        };
        let opened = py.detach(|| -> Result<Renderer, Failure> {
            let ctx = match adapter {
                None => GpuContext::new()?,
                Some(index) => {
                    let adapters = GpuContext::adapters();
                    let chosen = adapters.get(index).ok_or_else(|| {
                        Failure::Render(RenderError::NoAdapter(format!(
                            "device {index}: there are {} devices (chiaro.devices())",
                            adapters.len()
                        )))
                    })?;
                    GpuContext::with_adapter(chosen)?
                }
            };
            Ok(Renderer::new(ctx)?)
        });
        let renderer = opened?;
        chiaro_io::device::check_msaa(&renderer.ctx, &settings, None, settings_path.as_deref())
            .map_err(|e| SettingsError::new_err(format!("{e:#}")))?;
        let adapter_info = renderer.ctx.adapter_info.clone();
        let max_shadow_layers = renderer.ctx.device.limits().max_texture_array_layers;
        Ok(RendererCore {
            inner: Mutex::new(Inner { renderer, uploaded: None }),
            settings,
            adapter_info,
            max_shadow_layers,
        })
    }

    /// The adapter rendering: name, backend, device_type, driver, pci_bus_id.
    #[getter]
    fn device<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let info = &self.adapter_info;
        let d = PyDict::new(py);
        d.set_item("name", &info.name)?;
        d.set_item("backend", info.backend.to_str())?;
        d.set_item("device_type", device_type_name(info.device_type))?;
        d.set_item("driver", &info.driver)?;
        d.set_item("pci_bus_id", &info.device_pci_bus_id)?;
        Ok(d)
    }

    /// The settings in use, as TOML that `chiaro render --settings` reads.
    #[getter]
    fn settings_toml(&self) -> String {
        self.settings.to_toml()
    }

    /// Renders one frame; see `chiaro.Renderer.render`.
    #[pyo3(signature = (scene, camera = None, width = None, height = None, outputs = None))]
    fn render<'py>(
        &self,
        py: Python<'py>,
        scene: &Bound<'py, Scene>,
        camera: Option<&Bound<'py, PyAny>>,
        width: Option<i64>,
        height: Option<i64>,
        outputs: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let cameras = [CameraChoice::extract(camera)?];
        let outputs = extract_outputs(outputs)?;
        let size =
            (size(width, self.settings.render.width, "width")?, size(height, self.settings.render.height, "height")?);
        let state = scene.get().state.clone();
        let frames = py.detach(|| self.frames(&state, &cameras, size, &outputs))?;
        frames.into_iter().next().expect("one frame").into_dict(py)
    }

    /// Renders one frame per camera; see `chiaro.Renderer.render_many`.
    #[pyo3(signature = (scene, cameras, width = None, height = None, outputs = None))]
    fn render_many<'py>(
        &self,
        py: Python<'py>,
        scene: &Bound<'py, Scene>,
        cameras: &Bound<'py, PyAny>,
        width: Option<i64>,
        height: Option<i64>,
        outputs: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Vec<Bound<'py, PyDict>>> {
        if cameras.is_instance_of::<pyo3::types::PyString>() {
            return Err(PyTypeError::new_err("cameras: expected a sequence of cameras, not a string"));
        }
        let mut choices = Vec::new();
        for item in cameras.try_iter().map_err(|_| PyTypeError::new_err("cameras: expected a sequence of cameras"))? {
            choices.push(CameraChoice::extract(Some(&item?))?);
            if choices.len() > MAX_VIEWS {
                return Err(PyValueError::new_err(format!("cameras: more than {MAX_VIEWS} in one call")));
            }
        }
        let outputs = extract_outputs(outputs)?;
        let size =
            (size(width, self.settings.render.width, "width")?, size(height, self.settings.render.height, "height")?);
        let state = scene.get().state.clone();
        let frames = py.detach(|| self.frames(&state, &choices, size, &outputs))?;
        frames.into_iter().map(|f| f.into_dict(py)).collect()
    }

    /// Realtime shadows against the ray-traced reference, per light; see `chiaro.compare`.
    #[pyo3(signature = (scene, camera = None, width = 256, height = 256, edge_band = None))]
    fn compare<'py>(
        &self,
        py: Python<'py>,
        scene: &Bound<'py, Scene>,
        camera: Option<&Bound<'py, PyAny>>,
        width: i64,
        height: i64,
        edge_band: Option<i64>,
    ) -> PyResult<Vec<Bound<'py, PyDict>>> {
        let choice = CameraChoice::extract(camera)?;
        let edge_band = edge_band.unwrap_or(EDGE_BAND_PX as i64);
        let edge_band_px = usize::try_from(edge_band).ok().filter(|&b| b <= MAX_EDGE_BAND_PX).ok_or_else(|| {
            PyValueError::new_err(format!(
                "compare: edge_band {edge_band} is not a pixel count from 0 to {MAX_EDGE_BAND_PX}"
            ))
        })?;
        let size = (size(Some(width), 0, "width")?, size(Some(height), 0, "height")?);
        let state = scene.get().state.clone();
        let verdicts = py.detach(|| -> Result<Vec<LightVerdict>, Failure> {
            let guard = read(&state);
            let view = choice.view(&guard.scene, &self.settings, size.0, size.1).map_err(Failure::Value)?;
            let mut inner = self.lock();
            upload(&mut inner, &guard)?;
            let Inner { renderer, uploaded } = &mut *inner;
            let gpu = &uploaded.as_ref().expect("uploaded").gpu;
            renderer.forget_history();
            let options = CompareOptions { edge_band_px };
            let result = compare_shadows_with(renderer, &guard.scene, gpu, &view, &self.settings, options)?;
            Ok(LightVerdict::all(&guard.scene, &result))
        })?;
        verdicts.into_iter().map(|v| v.into_dict(py)).collect()
    }

    fn __reduce__(&self) -> PyResult<()> {
        Err(PyTypeError::new_err("a chiaro.Renderer cannot be pickled (it holds a GPU device): make one per process"))
    }
}
