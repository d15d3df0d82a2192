//! `chiaro.Camera`: a perspective or orthographic camera placed in the world, and how a render's `camera=`
//! argument (a Camera, a glTF camera's name or index, or None) becomes the frame's view.

use crate::scene::matrix_rows;
use chiaro_math::camera::{LookAt, Projection};
use chiaro_render::View;
use chiaro_scene::{Scene, Settings};
use glam::{Mat4, Vec3};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;

/// A camera: where it is (its node looks down -Z with +Y up), its vertical field of view
/// (perspective) or half height (orthographic) and its clip planes in metres. The aspect
/// ratio is the image's.
#[pyclass(module = "chiaro", frozen)]
#[derive(Clone)]
pub struct Camera {
    pub world_from_view: Mat4,
    pub projection: Projection,
    pub znear: f32,
    pub zfar: Option<f32>,
    pub name: Option<String>,
}

impl Camera {
    /// A glTF camera of a scene, as a Camera.
    pub fn from_scene_camera(c: &chiaro_scene::Camera) -> Camera {
        Camera {
            world_from_view: c.world_from_view,
            projection: c.projection,
            znear: c.znear,
            zfar: c.zfar,
            name: Some(c.name.clone()),
        }
    }

    /// The view of this camera for a `width` x `height` image.
    pub fn view(&self, width: u32, height: u32) -> View {
        View::projected(self.world_from_view, self.projection, self.znear, self.zfar, width, height)
    }
}

fn vec3(v: [f64; 3]) -> Vec3 {
    Vec3::new(v[0] as f32, v[1] as f32, v[2] as f32)
}

#[pymethods]
impl Camera {
    /// A camera at `eye` looking at `target` (metres, world space), `up` giving the
    /// image's up direction, with a vertical field of view of `yfov_deg` degrees and clip
    /// planes at `znear` and `zfar` metres (None: no far plane).
    #[staticmethod]
    #[pyo3(signature = (eye, target, up = [0.0, 1.0, 0.0], yfov_deg = 45.0, znear = 0.05, zfar = None))]
    fn look_at(
        eye: [f64; 3],
        target: [f64; 3],
        up: [f64; 3],
        yfov_deg: f32,
        znear: f32,
        zfar: Option<f32>,
    ) -> PyResult<Camera> {
        let placed = LookAt { eye: vec3(eye), target: vec3(target), up: vec3(up), yfov_deg, ymag: None, znear, zfar };
        placed_camera(&placed)
    }

    /// An orthographic camera at `eye` looking at `target`: parallel rays over a view
    /// `2 * ymag` metres high (its width follows the image's aspect), clip planes at
    /// `znear` and `zfar` metres.
    #[staticmethod]
    #[pyo3(signature = (eye, target, up = [0.0, 1.0, 0.0], ymag = 1.0, znear = 0.05, zfar = 100.0))]
    fn orthographic(
        eye: [f64; 3],
        target: [f64; 3],
        up: [f64; 3],
        ymag: f32,
        znear: f32,
        zfar: f32,
    ) -> PyResult<Camera> {
        let placed = LookAt {
            eye: vec3(eye),
            target: vec3(target),
            up: vec3(up),
            yfov_deg: 0.0,
            ymag: Some(ymag),
            znear,
            zfar: Some(zfar),
        };
        placed_camera(&placed)
    }

    /// Whether the camera's rays are parallel.
    #[getter]
    fn is_orthographic(&self) -> bool {
        self.projection.is_orthographic()
    }

    /// An orthographic camera's half height in metres, or None for a perspective one.
    #[getter]
    fn ymag(&self) -> Option<f32> {
        match self.projection {
            Projection::Orthographic { ymag } => Some(ymag),
            Projection::Perspective { .. } => None,
        }
    }

    /// The camera's position, metres.
    #[getter]
    fn eye(&self) -> [f32; 3] {
        self.world_from_view.w_axis.truncate().to_array()
    }

    /// The unit direction the camera looks along (its -Z).
    #[getter]
    fn forward(&self) -> [f32; 3] {
        (-self.world_from_view.z_axis.truncate()).normalize().to_array()
    }

    /// Vertical field of view in degrees, or None for an orthographic camera.
    #[getter]
    fn yfov_deg(&self) -> Option<f32> {
        self.projection.yfov_rad().map(f32::to_degrees)
    }

    /// Near clip plane, metres.
    #[getter]
    fn znear(&self) -> f32 {
        self.znear
    }

    /// Far clip plane in metres, or None.
    #[getter]
    fn zfar(&self) -> Option<f32> {
        self.zfar
    }

    /// The glTF camera's name, or None for a camera made with `look_at`.
    #[getter]
    fn name(&self) -> Option<String> {
        self.name.clone()
    }

    /// The camera's world transform as a row-major 4x4 list (`M @ [x, y, z, 1]` takes view
    /// space to world space).
    #[getter]
    fn world_from_view(&self) -> [[f32; 4]; 4] {
        matrix_rows(self.world_from_view)
    }

    fn __repr__(&self) -> String {
        let e = self.eye();
        let lens = match self.projection {
            Projection::Perspective { yfov_rad } => format!("yfov {:.1} deg", yfov_rad.to_degrees()),
            Projection::Orthographic { ymag } => format!("orthographic, ymag {ymag:.3} m"),
        };
        format!(
            "<chiaro.Camera{} at ({:.3}, {:.3}, {:.3}), {lens}>",
            self.name.as_ref().map_or(String::new(), |n| format!(" {n:?}")),
            e[0],
            e[1],
            e[2],
        )
    }
}

/// A camera made by `look_at` or `orthographic`, once `placed` is checked.
fn placed_camera(placed: &LookAt) -> PyResult<Camera> {
    let world_from_view = placed.world_from_view().map_err(|e| PyValueError::new_err(e.to_string()))?;
    Ok(Camera { world_from_view, projection: placed.projection(), znear: placed.znear, zfar: placed.zfar, name: None })
}

/// A render's `camera=` argument.
pub enum CameraChoice {
    /// A Camera object.
    Given(Camera),
    /// A glTF camera by index into the scene's cameras.
    Index(usize),
    /// A glTF camera by name (its camera's or node's).
    Named(String),
    /// The scene's first camera, or one that frames its bounds.
    Default,
}

impl CameraChoice {
    /// Reads `camera=`: a Camera, a str, an int, or None.
    pub fn extract(value: Option<&Bound<'_, PyAny>>) -> PyResult<CameraChoice> {
        let Some(value) = value.filter(|v| !v.is_none()) else { return Ok(CameraChoice::Default) };
        if let Ok(camera) = value.cast::<Camera>() {
            return Ok(CameraChoice::Given(camera.get().clone()));
        }
        if value.is_instance_of::<pyo3::types::PyBool>() {
            return Err(PyTypeError::new_err("camera: expected a chiaro.Camera, a camera name or index, or None"));
        }
        if let Ok(index) = value.extract::<i64>() {
            if index < 0 {
                return Err(PyValueError::new_err(format!("camera: index {index} is negative")));
            }
            return Ok(CameraChoice::Index(index as usize));
        }
        if let Ok(name) = value.extract::<String>() {
            return Ok(CameraChoice::Named(name));
        }
        Err(PyTypeError::new_err(format!(
            "camera: expected a chiaro.Camera, a camera name or index, or None, not {}",
            value.get_type().name()?
        )))
    }

    /// The frame's view, chosen as `chiaro render` chooses it; an unknown camera names the
    /// scene's cameras.
    pub fn view(&self, scene: &Scene, settings: &Settings, width: u32, height: u32) -> Result<View, String> {
        match self {
            CameraChoice::Given(camera) => Ok(camera.view(width, height)),
            // The CLI's lookup takes digits for an index; a name is looked up as a name first.
            CameraChoice::Named(name) => {
                let key = match scene.cameras.iter().position(|c| &c.name == name) {
                    Some(index) => index.to_string(),
                    None => name.clone(),
                };
                chiaro_io::scenes::choose_view(scene, Some(&key), settings, width, height).map_err(|e| format!("{e:#}"))
            }
            CameraChoice::Index(index) => {
                chiaro_io::scenes::choose_view(scene, Some(&index.to_string()), settings, width, height)
                    .map_err(|e| format!("{e:#}"))
            }
            CameraChoice::Default => {
                chiaro_io::scenes::choose_view(scene, None, settings, width, height).map_err(|e| format!("{e:#}"))
            }
        }
    }
}
