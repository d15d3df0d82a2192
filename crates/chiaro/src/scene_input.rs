//! What render, bench, compare and view read a scene from, as one group of flags
//! (`SceneInput`): the file or the demo, the settings file and the flags that override it,
//! the camera, the pose and the bake; and the loading they share, in one order: settings,
//! their overrides, the scene, its bake, its pose, the view. chiaro-io reads the files.

use crate::bake_arg::BakeUseArgs;
use crate::environment_arg::EnvironmentArg;
use crate::path_arg::PathArgs;
use crate::shadow_args::ShadowArgs;
use crate::time_arg::TimeArg;
use anyhow::Result;
use chiaro_io::output::Inputs;
use chiaro_io::scenes::DemoScene;
pub use chiaro_io::scenes::load_settings;
use chiaro_render::View;
use chiaro_scene::demo::{DEMO_LOCAL_LIGHTS, DEMO_SHADOWED_POINTS, DEMO_SHADOWED_SPOTS};
use chiaro_scene::{Scene, Settings};
use clap::Args;
use std::path::{Path, PathBuf};

/// The scene a command renders and the settings it renders with.
#[derive(Args, Clone, Debug)]
pub struct SceneInput {
    /// A .gltf or .glb file; without one, the built-in demo scene.
    pub scene: Option<PathBuf>,
    /// Camera by name or index; default: the scene's first camera, or one that frames it.
    #[arg(long)]
    pub camera: Option<String>,
    /// Pipeline settings (TOML, docs/settings.md); the viewer's "Save settings" writes
    /// back to it.
    #[arg(long)]
    pub settings: Option<PathBuf>,
    /// The KHR_materials_variants variant to render, by name (`chiaro info` lists a
    /// file's); overrides the settings' `scene.variant`.
    #[arg(long, value_name = "NAME")]
    pub variant: Option<String>,
    #[command(flatten)]
    pub demo: DemoArgs,
    #[command(flatten)]
    pub time: TimeArg,
    #[command(flatten)]
    pub shadow: ShadowArgs,
    #[command(flatten)]
    pub environment: EnvironmentArg,
    #[command(flatten)]
    pub path: PathArgs,
    #[command(flatten)]
    pub bake: BakeUseArgs,
}

impl SceneInput {
    /// The settings file (or the defaults) with the shadow, environment and path flags
    /// applied, each error naming its flag or key.
    pub fn settings(&self) -> Result<Settings> {
        let mut settings = load_settings(self.settings.as_deref())?;
        self.shadow.apply(&mut settings)?;
        self.environment.apply(&mut settings)?;
        self.path.apply(&mut settings)?;
        Ok(settings)
    }

    /// The scene file (or the demo) in the variant of `--variant` (else the settings'),
    /// with its bake, posed at `--time`.
    pub fn scene(&self, settings: &Settings) -> Result<Scene> {
        let mut scene = load_scene(self.scene.as_deref(), &self.demo)?;
        if let Some(name) = self.variant.as_deref().or(settings.scene.variant.as_deref()) {
            scene.select_variant(Some(name)).map_err(|e| anyhow::anyhow!("{}: {e}", self.name()))?;
        }
        self.bake.apply(&mut scene, self.scene.as_deref(), settings)?;
        self.time.apply(&mut scene)?;
        Ok(scene)
    }

    /// The view of `--camera` (or the scene's first camera, or one framing it) at `width` x
    /// `height`.
    pub fn view(&self, scene: &Scene, settings: &Settings, width: u32, height: u32) -> Result<View> {
        chiaro_io::scenes::choose_view(scene, self.camera.as_deref(), settings, width, height)
    }

    /// What the command reads, which no output may replace.
    pub fn inputs(&self, scene: &Scene) -> Inputs {
        Inputs::new(&scene.inputs, self.settings.as_deref())
    }

    /// The scene's name for reports: its file, or "demo".
    pub fn name(&self) -> String {
        self.scene.as_ref().map_or_else(|| "demo".into(), |p| p.display().to_string())
    }
}

/// Most point and spot lights the demo scene is made with.
pub const MAX_DEMO_LIGHTS: u32 = 65536;

/// How the built-in demo is made when no scene file is given.
#[derive(clap::Args, Clone, Debug)]
pub struct DemoArgs {
    /// Point and spot lights in the demo scene (alternating, spots first; 0 to 65536).
    #[arg(long, default_value_t = DEMO_LOCAL_LIGHTS as u32, value_parser = clap::value_parser!(u32).range(0..=MAX_DEMO_LIGHTS as i64))]
    pub demo_lights: u32,
    /// Demo spot lights that cast realtime shadows (0 to 65536).
    #[arg(long, default_value_t = DEMO_SHADOWED_SPOTS as u32, value_parser = clap::value_parser!(u32).range(0..=MAX_DEMO_LIGHTS as i64))]
    pub demo_shadowed_spots: u32,
    /// Demo point lights that cast realtime shadows (0 to 65536).
    #[arg(long, default_value_t = DEMO_SHADOWED_POINTS as u32, value_parser = clap::value_parser!(u32).range(0..=MAX_DEMO_LIGHTS as i64))]
    pub demo_shadowed_points: u32,
}

impl DemoArgs {
    /// The demo these flags make.
    pub fn scene(&self) -> DemoScene {
        DemoScene {
            lights: self.demo_lights as usize,
            shadowed_spots: self.demo_shadowed_spots as usize,
            shadowed_points: self.demo_shadowed_points as usize,
        }
    }
}

/// The file's scene, or the demo `demo` makes.
pub fn load_scene(path: Option<&Path>, demo: &DemoArgs) -> Result<Scene> {
    chiaro_io::scenes::load_scene(path, &demo.scene())
}
