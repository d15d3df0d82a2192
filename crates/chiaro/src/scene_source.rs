//! Turns command-line arguments into a scene, settings and a view (chiaro-io reads the
//! files; the flags that make the demo scene are here).

use anyhow::Result;
use chiaro_io::scenes::DemoScene;
pub use chiaro_io::scenes::{choose_view, load_settings};
use chiaro_scene::Scene;
use chiaro_scene::demo::{DEMO_LOCAL_LIGHTS, DEMO_SHADOWED_POINTS, DEMO_SHADOWED_SPOTS};
use std::path::Path;

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
