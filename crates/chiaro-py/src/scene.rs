//! `chiaro.Scene` and `chiaro.load`: a loaded scene shared by the Python objects that look
//! into it (its lights) and the renderers that draw it. Every change bumps a version, so a
//! renderer knows when its uploaded copy is stale.

use crate::camera::Camera;
use crate::errors::SceneError;
use crate::light::Light;
use glam::Mat4;
use numpy::{AllowTypeChange, PyArrayLike2};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use std::path::PathBuf;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, RwLock, RwLockReadGuard, RwLockWriteGuard};

/// Scene ids are unique in the process, so a renderer never mistakes one for another.
static NEXT_SCENE_ID: AtomicU64 = AtomicU64::new(1);

/// The scene and what a renderer needs to know of its changes.
pub struct SceneState {
    /// The plain scene the renderer draws.
    pub scene: chiaro_scene::Scene,
    /// Unique per loaded scene.
    pub id: u64,
    /// Bumped when mesh instances move: the renderer's uploaded objects are then stale.
    pub geometry_version: u64,
    /// The animation time the scene is posed at (`None`: the rest pose).
    pub time: Option<f32>,
}

/// Shared between a `Scene` and its `Light`s.
pub type SharedScene = Arc<RwLock<SceneState>>;

/// Reads the scene; a poisoned lock (a panic elsewhere) still holds a whole scene.
pub fn read(state: &SharedScene) -> RwLockReadGuard<'_, SceneState> {
    state.read().unwrap_or_else(|e| e.into_inner())
}

/// Writes the scene.
pub fn write(state: &SharedScene) -> RwLockWriteGuard<'_, SceneState> {
    state.write().unwrap_or_else(|e| e.into_inner())
}

/// Runs `f` on the scene with the GIL released while the lock is awaited and held: a
/// render in another thread holds the scene for a whole frame, and Python's other
/// threads must not stop meanwhile.
pub fn reading<T: Send>(state: &SharedScene, f: impl FnOnce(&SceneState) -> T + Send) -> T {
    Python::attach(|py| py.detach(|| f(&read(state))))
}

/// As `reading`, for a change.
pub fn writing<T: Send>(state: &SharedScene, f: impl FnOnce(&mut SceneState) -> T + Send) -> T {
    Python::attach(|py| py.detach(|| f(&mut write(state))))
}

/// A glTF scene (or the built-in demo) loaded into memory: meshes, materials, lights and
/// cameras in world space (metres). Lights are edited through `scene.lights`, nodes moved
/// with `set_transform`; a renderer picks up every change at its next frame.
#[pyclass(module = "chiaro", frozen)]
pub struct Scene {
    pub state: SharedScene,
}

impl Scene {
    fn new(mut scene: chiaro_scene::Scene) -> Scene {
        scene.ensure_nodes();
        let id = NEXT_SCENE_ID.fetch_add(1, Ordering::Relaxed);
        Scene { state: Arc::new(RwLock::new(SceneState { scene, id, geometry_version: 0, time: None })) }
    }
}

/// Loads a .gltf or .glb file, posed at `time` seconds of its animations (None: the rest
/// pose), in the KHR_materials_variants variant named `variant` (None: the file's default
/// materials). Raises `SceneError` naming the file and the problem (the message `chiaro
/// render` prints), ValueError for a time that is not finite or a variant the file lacks.
#[pyfunction]
#[pyo3(signature = (path, time = None, variant = None))]
pub fn load(py: Python<'_>, path: PathBuf, time: Option<f64>, variant: Option<String>) -> PyResult<Scene> {
    let time = seconds(time)?;
    let loaded = py.detach(|| chiaro_scene::load_gltf(&path));
    let mut scene = loaded.map_err(|e| SceneError::new_err(e.to_string()))?;
    scene
        .select_variant(variant.as_deref())
        .map_err(|e| PyValueError::new_err(format!("{}: variant: {e}", path.display())))?;
    scene.source = Some(path);
    scene.pose(time).map_err(|e| PyValueError::new_err(format!("time: {e}")))?;
    let scene = Scene::new(scene);
    write(&scene.state).time = time;
    Ok(scene)
}

/// A time from Python: finite seconds, or None.
fn seconds(time: Option<f64>) -> PyResult<Option<f32>> {
    match time {
        Some(t) if !t.is_finite() || t.abs() > f64::from(f32::MAX) => {
            Err(PyValueError::new_err(format!("time: {t} is not a finite number of seconds")))
        }
        t => Ok(t.map(|t| t as f32)),
    }
}

/// A node index from Python, where a negative or huge one is a ValueError naming it.
fn node_index(node: i64) -> PyResult<usize> {
    usize::try_from(node).map_err(|_| PyValueError::new_err(format!("node: {node} is not a node index")))
}

/// A row-major 4x4 matrix (numpy's `M @ p` convention) as glam's column-major one.
pub fn matrix_from_rows(rows: &[[f64; 4]; 4]) -> Mat4 {
    Mat4::from_cols_array_2d(&std::array::from_fn(|c| std::array::from_fn(|r| rows[r][c] as f32)))
}

/// glam's matrix as rows, for numpy.
pub fn matrix_rows(m: Mat4) -> [[f32; 4]; 4] {
    let cols = m.to_cols_array_2d();
    std::array::from_fn(|r| std::array::from_fn(|c| cols[c][r]))
}

#[pymethods]
impl Scene {
    /// The built-in demo scene: a floor, boxes and spheres, a sun, and `lights` point and
    /// spot lights (alternating, spots first) of which the first `shadowed_spots` spots and
    /// `shadowed_points` points cast shadows, in a studio environment of its own (as
    /// `chiaro render` shows it; `environment.source = "ambient"` takes it off).
    #[staticmethod]
    #[pyo3(signature = (lights = 8, shadowed_spots = 4, shadowed_points = 2))]
    fn demo(lights: i64, shadowed_spots: i64, shadowed_points: i64) -> PyResult<Scene> {
        const MAX_DEMO_LIGHTS: i64 = 65536;
        for (name, value) in
            [("lights", lights), ("shadowed_spots", shadowed_spots), ("shadowed_points", shadowed_points)]
        {
            if !(0..=MAX_DEMO_LIGHTS).contains(&value) {
                return Err(PyValueError::new_err(format!("{name}: {value} is not between 0 and {MAX_DEMO_LIGHTS}")));
            }
        }
        let scene = chiaro_scene::demo::demo_scene_in_studio(
            lights as usize,
            shadowed_spots as usize,
            shadowed_points as usize,
        );
        Ok(Scene::new(scene))
    }

    /// The file the scene was loaded from, or None for the demo.
    #[getter]
    fn path(&self) -> Option<PathBuf> {
        reading(&self.state, |s| s.scene.source.clone())
    }

    /// The scene's punctual lights, in the file's order. Each one's attributes are live:
    /// setting `scene.lights[0].intensity` changes the scene.
    #[getter]
    fn lights(&self) -> Vec<Light> {
        let count = reading(&self.state, |s| s.scene.lights.len());
        (0..count).map(|index| Light { state: self.state.clone(), index }).collect()
    }

    /// Every node's name, indexed by glTF node index (`node N` where the file gives none).
    #[getter]
    fn node_names(&self) -> Vec<String> {
        reading(&self.state, |s| s.scene.nodes.iter().map(|n| n.name.clone()).collect())
    }

    /// The scene's glTF cameras, as `Camera` objects placed where their nodes are.
    #[getter]
    fn cameras(&self) -> Vec<Camera> {
        reading(&self.state, |s| s.scene.cameras.iter().map(Camera::from_scene_camera).collect())
    }

    /// World-space bounds of every mesh, `((min_x, min_y, min_z), (max_x, max_y, max_z))`
    /// in metres.
    #[getter]
    fn bounds(&self) -> ([f32; 3], [f32; 3]) {
        let b = reading(&self.state, |s| s.scene.bounds());
        (b.min.to_array(), b.max.to_array())
    }

    /// What the file had that Chiaro does not use, one line each, saying why.
    #[getter]
    fn ignored(&self) -> Vec<String> {
        reading(&self.state, |s| s.scene.ignored.clone())
    }

    /// The environment the file carries (EXT_lights_image_based), by name, or None. It
    /// lights the scene unless the settings' `environment.source` names another.
    #[getter]
    fn environment(&self) -> Option<String> {
        reading(&self.state, |s| s.scene.environment.as_ref().map(|own| own.label.clone()))
    }

    /// Triangles drawn.
    #[getter]
    fn triangle_count(&self) -> usize {
        reading(&self.state, |s| s.scene.triangle_count())
    }

    /// Places node `node` (a glTF node index) at `matrix`, a 4x4 world transform in
    /// numpy's row-major convention (`matrix @ [x, y, z, 1]`), metres. Its children and
    /// whatever the moved nodes carry (meshes, lights, cameras) follow. Raises ValueError
    /// for an unknown node or a matrix that is not finite or cannot be inverted.
    fn set_transform(&self, py: Python<'_>, node: i64, matrix: PyArrayLike2<'_, f64, AllowTypeChange>) -> PyResult<()> {
        let node = node_index(node)?;
        let view = matrix.as_array();
        if view.shape() != [4, 4] {
            let shape = view.shape();
            return Err(PyValueError::new_err(format!(
                "matrix: expected shape (4, 4), got ({}, {})",
                shape[0], shape[1]
            )));
        }
        let rows: [[f64; 4]; 4] = std::array::from_fn(|r| std::array::from_fn(|c| view[[r, c]]));
        let world_from_node = matrix_from_rows(&rows);
        let state = self.state.clone();
        py.detach(move || {
            let mut guard = write(&state);
            let moved = guard.scene.set_node_transform(node, world_from_node);
            match moved {
                Ok(m) if m.instances > 0 => {
                    guard.geometry_version += 1;
                    Ok(())
                }
                Ok(_) => Ok(()),
                Err(e) => Err(e.to_string()),
            }
        })
        .map_err(PyValueError::new_err)
    }

    /// Poses the scene at `time` seconds into its glTF animations, all at once (each holds
    /// its first key before it starts and its last after it ends), or at rest for None:
    /// nodes, meshes, lights and cameras move; skinned and morphed meshes deform. Posing
    /// starts from the file's rest state each time, replacing `set_transform` moves.
    /// Raises ValueError for a time that is not finite.
    #[pyo3(signature = (time = None))]
    fn pose(&self, time: Option<f64>) -> PyResult<()> {
        let time = seconds(time)?;
        writing(&self.state, |s| -> Result<(), String> {
            s.scene.pose(time).map_err(|e| format!("time: {e}"))?;
            s.time = time;
            s.geometry_version += 1;
            Ok(())
        })
        .map_err(PyValueError::new_err)
    }

    /// The file's KHR_materials_variants variants, by name, in the file's order.
    #[getter]
    fn variants(&self) -> Vec<String> {
        reading(&self.state, |s| s.scene.variants.names.clone())
    }

    /// The selected material variant's name; None for the file's default materials.
    #[getter]
    fn variant(&self) -> Option<String> {
        reading(&self.state, |s| s.scene.selected_variant().map(str::to_owned))
    }

    /// Gives every primitive the material of the variant named `name` (None: the file's
    /// default materials); the next frame shows it. Raises ValueError, listing the file's
    /// variants, for a name it lacks.
    #[pyo3(signature = (name = None))]
    fn select_variant(&self, name: Option<String>) -> PyResult<()> {
        writing(&self.state, |s| -> Result<(), String> {
            s.scene.select_variant(name.as_deref()).map_err(|e| format!("variant: {e}"))?;
            s.geometry_version += 1;
            Ok(())
        })
        .map_err(PyValueError::new_err)
    }

    /// The animation time the scene is posed at, seconds; None at rest.
    #[getter]
    fn time(&self) -> Option<f32> {
        reading(&self.state, |s| s.time)
    }

    /// How long the scene's animations run, seconds (the latest key of any); None when the
    /// file has no animations.
    #[getter]
    fn duration(&self) -> Option<f32> {
        reading(&self.state, |s| s.scene.animation_duration())
    }

    /// The transform of node `node` as a row-major 4x4 float32 array.
    fn transform<'py>(&self, py: Python<'py>, node: i64) -> PyResult<Bound<'py, numpy::PyArray2<f32>>> {
        let node = node_index(node)?;
        let (found, count) =
            reading(&self.state, |s| (s.scene.nodes.get(node).map(|n| n.world_from_node), s.scene.nodes.len()));
        let world_from_node = found
            .ok_or_else(|| PyValueError::new_err(format!("no node {node} in the scene (it has {count} nodes)")))?;
        let rows = matrix_rows(world_from_node);
        numpy::PyArray2::from_vec2(py, &rows.iter().map(|r| r.to_vec()).collect::<Vec<_>>())
            .map_err(|e| PyValueError::new_err(e.to_string()))
    }

    fn __repr__(&self) -> String {
        reading(&self.state, |state| {
            let s = &state.scene;
            let source = s.source.as_ref().map_or("demo".to_string(), |p| p.display().to_string());
            format!(
                "<chiaro.Scene {source}: {} meshes, {} triangles, {} lights, {} cameras>",
                s.instances.len(),
                s.triangle_count(),
                s.lights.len(),
                s.cameras.len()
            )
        })
    }

    fn __reduce__(&self) -> PyResult<()> {
        Err(pyo3::exceptions::PyTypeError::new_err(
            "a chiaro.Scene cannot be pickled: load it in each process (chiaro.load(path))",
        ))
    }
}
