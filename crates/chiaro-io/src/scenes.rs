//! Scenes, settings and the opening view: a settings file (or the defaults), a glTF file
//! (or the built-in demo, made as `DemoScene` says) and the camera to look through.

use anyhow::{Context, Result, bail};
use chiaro_math::camera::can_frame;
use chiaro_render::View;
use chiaro_scene::demo::demo_scene_in_studio;
use chiaro_scene::{Scene, Settings, load_gltf};
use std::path::Path;

/// The settings file's settings, or the defaults without one.
pub fn load_settings(path: Option<&Path>) -> Result<Settings> {
    match path {
        Some(p) => Ok(Settings::load(p)?),
        None => Ok(Settings::default()),
    }
}

/// How the built-in demo is made when no scene file is given.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct DemoScene {
    /// Point and spot lights (alternating, spots first).
    pub lights: usize,
    pub shadowed_spots: usize,
    pub shadowed_points: usize,
}

/// The file's scene, or the built-in demo.
pub fn load_scene(path: Option<&Path>, demo: &DemoScene) -> Result<Scene> {
    match path {
        Some(p) => {
            let scene = load_gltf(p)?;
            for reason in &scene.ignored {
                tracing::info!("{}: ignored {reason}", p.display());
            }
            // An empty picture is the spec's answer to a file without a scene, but rarely the
            // user's intent, so it is said at the default log level.
            if scene.instances.is_empty() {
                let why = scene.ignored.iter().find(|r| r.ends_with("nothing to draw"));
                tracing::warn!("{}: {}", p.display(), why.map_or("the scene draws nothing", String::as_str));
            }
            Ok(scene)
        }
        None => Ok(demo_scene_in_studio(demo.lights, demo.shadowed_spots, demo.shadowed_points)),
    }
}

pub fn check_size(width: u32, height: u32) -> Result<()> {
    if width == 0 || height == 0 {
        bail!("output size {width}x{height} is invalid: width and height must be at least 1");
    }
    Ok(())
}

/// The requested camera (name or index), the scene's first camera, or a framing camera.
pub fn choose_view(scene: &Scene, camera: Option<&str>, settings: &Settings, width: u32, height: u32) -> Result<View> {
    check_size(width, height)?;
    match camera {
        Some(key) => {
            let index = scene.find_camera(key).with_context(|| {
                let names: Vec<String> =
                    scene.cameras.iter().enumerate().map(|(i, c)| format!("{i}: {}", c.name)).collect();
                format!(
                    "no camera '{key}' in the scene (cameras: {})",
                    if names.is_empty() { "none".to_string() } else { names.join(", ") }
                )
            })?;
            Ok(View::from_camera(scene, index, width, height))
        }
        None if !scene.cameras.is_empty() => Ok(View::from_camera(scene, 0, width, height)),
        None => {
            let bounds = scene.bounds();
            if !can_frame(&bounds) {
                let s = bounds.bounding_sphere();
                bail!(
                    "{}: the scene's bounding sphere (radius {:e} m around {}) is beyond what the automatic \
                     camera frames (radius 1e-6 to 1e15 m, within 1e15 m of the origin); give the file a camera",
                    scene.source.as_ref().map_or("scene".into(), |p| p.display().to_string()),
                    s.radius,
                    s.center
                );
            }
            Ok(View::framing(scene, settings.camera.auto_yfov_deg.to_radians(), width, height))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_demo_is_made_as_asked_and_an_unknown_camera_names_the_cameras() {
        let demo = DemoScene { lights: 4, shadowed_spots: 1, shadowed_points: 1 };
        let scene = load_scene(None, &demo).unwrap();
        let made = chiaro_scene::demo::demo_scene_with_shadows(4, 1, 1);
        assert_eq!(scene.lights.len(), made.lights.len());
        assert!(scene.environment.is_some(), "the demo shows in its studio");
        let settings = Settings::default();
        let error = choose_view(&scene, Some("nope"), &settings, 64, 64).unwrap_err().to_string();
        assert!(error.starts_with("no camera 'nope' in the scene (cameras: 0: "), "{error}");
        let error = choose_view(&scene, None, &settings, 0, 64).unwrap_err().to_string();
        assert_eq!(error, "output size 0x64 is invalid: width and height must be at least 1");
    }
}
