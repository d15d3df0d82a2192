//! Where the viewer looks from: the view it opened with, the glTF camera in use, and the
//! rig (camera.rs) once the user moves. In: camera choices, drags, wheel steps, fly keys,
//! "frame selected" and the view's size from the settings. Out: the view to render.

use crate::camera::{CameraRig, FlyInput, Navigation};
use crate::pick;
use crate::state::Selection;
use anyhow::Result;
use chiaro_io::scenes::choose_view;
use chiaro_render::View;
use chiaro_scene::{LightKind, Scene, Settings};

pub struct CameraState {
    /// The view the rig starts from: the chosen camera's, at the view's size.
    pub start_view: View,
    /// The view the window opened with, for "reset view".
    pub opening_view: View,
    /// The glTF camera in use, if one was chosen in the viewer.
    pub camera: Option<usize>,
    /// `--camera`, while the file it names is open.
    pub camera_key: Option<String>,
    /// The view's size and automatic field of view the start view was made for.
    pub view_settings: (u32, u32, f32),
    pub rig: Option<CameraRig>,
    pub navigation: Navigation,
}

impl CameraState {
    pub fn new(start_view: View, camera_key: Option<String>, settings: &Settings) -> CameraState {
        CameraState {
            start_view,
            opening_view: start_view,
            camera: None,
            camera_key,
            view_settings: (start_view.width, start_view.height, settings.camera.auto_yfov_deg),
            rig: None,
            navigation: Navigation::default(),
        }
    }

    /// The 3D view's size in pixels.
    pub fn view_size(&self) -> (u32, u32) {
        (self.start_view.width, self.start_view.height)
    }

    pub fn current_view(&self, scene: &Scene) -> View {
        self.rig.map_or(self.start_view, |r| r.view(&self.start_view, scene.bounds().bounding_sphere()))
    }

    /// The rig, made from the start view on the first move.
    pub fn rig(&mut self, scene: &Scene) -> &mut CameraRig {
        let (start, center) = (self.start_view, scene.bounds().center());
        self.rig.get_or_insert_with(|| CameraRig::from_view(&start, center))
    }

    /// Starts the view again from glTF camera `index`, or from the view it opened with.
    pub fn use_camera(&mut self, scene: &Scene, index: Option<usize>) {
        let (w, h) = self.view_size();
        self.start_view = match index {
            Some(i) if i < scene.cameras.len() => View::from_camera(scene, i, w, h),
            _ => self.opening_view,
        };
        self.camera = index;
        self.rig = None;
    }

    /// The glTF camera after the one in use (the first if none is), if the scene has any.
    pub fn next_camera(&self, scene: &Scene) -> Option<usize> {
        let count = scene.cameras.len();
        (count > 0).then(|| self.camera.map_or(0, |i| (i + 1) % count))
    }

    /// Looks at the selected light (its range, at most the scene's size), the selected
    /// object, or the whole scene.
    pub fn frame_selected(&mut self, scene: &Scene, selected: Option<Selection>) {
        let scene_sphere = scene.bounds().bounding_sphere();
        let (center, radius) = match selected {
            Some(Selection::Light(i)) if scene.lights.get(i).is_some_and(|l| l.kind != LightKind::Directional) => {
                let light = &scene.lights[i];
                let reach = light.range.unwrap_or(scene_sphere.radius).min(scene_sphere.radius);
                (light.position(), reach.max(0.05))
            }
            Some(Selection::Object(i)) if i < scene.instances.len() => {
                let sphere = pick::instance_bounds(scene, i).bounding_sphere();
                (sphere.center, sphere.radius.max(0.05))
            }
            _ => (scene_sphere.center, scene_sphere.radius),
        };
        let projection = self.start_view.projection;
        self.rig(scene).frame(center, radius, projection);
    }

    /// Moves a flying camera by `input` (camera axes) for `seconds`, four times as fast
    /// when `fast`.
    pub fn fly(&mut self, scene: &Scene, input: FlyInput, fast: bool, seconds: f32) {
        let radius = scene.bounds().bounding_sphere().radius;
        self.rig(scene).fly_for(input, fast, seconds, radius);
    }

    /// The view of glTF camera `camera` (or the one the viewer opened with) at `w` x `h`.
    fn base_view(&self, scene: &Scene, settings: &Settings, camera: Option<usize>, w: u32, h: u32) -> Result<View> {
        match camera {
            Some(i) if i < scene.cameras.len() => Ok(View::from_camera(scene, i, w, h)),
            _ => choose_view(scene, self.camera_key.as_deref(), settings, w, h),
        }
    }

    /// Follows render.width and height and camera.auto_yfov_deg (the framing camera's
    /// field of view). Returns whether the view changed.
    pub fn follow_settings(&mut self, scene: &Scene, settings: &Settings) -> Result<bool> {
        let (w, h) = (settings.render.width, settings.render.height);
        let yfov = settings.camera.auto_yfov_deg;
        if (w, h, yfov) == self.view_settings {
            return Ok(false);
        }
        self.view_settings = (w, h, yfov);
        self.start_view = self.base_view(scene, settings, self.camera, w, h)?;
        self.opening_view = self.base_view(scene, settings, None, w, h)?;
        Ok(true)
    }

    /// Opens a new scene's view: its own camera or a framing one, at the view's size.
    pub fn open_scene(&mut self, scene: &Scene, settings: &Settings) -> Result<()> {
        let (w, h) = self.view_size();
        self.camera = None;
        let view = choose_view(scene, None, settings, w, h)?;
        self.start_view = view;
        self.opening_view = view;
        self.rig = None;
        Ok(())
    }
}
