//! `[scene]`: choices about the scene file itself. TOML values flow in; `SceneSettings`
//! flows out. Which variant a file has is only known once it is loaded, so a name is
//! checked against the file when it is applied (`Scene::select_variant`).

use serde::{Deserialize, Serialize};

/// The `[scene]` section.
#[derive(Clone, Debug, Default, Deserialize, Serialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct SceneSettings {
    /// The KHR_materials_variants variant to render, by name; unset, the file's default
    /// materials. `--variant` overrides it.
    pub variant: Option<String>,
}

impl SceneSettings {
    /// Checks the section; the message starts with the dotted key.
    pub fn validate(&self) -> Result<(), String> {
        match &self.variant {
            Some(name) if name.trim().is_empty() => Err("scene.variant: an empty name names no variant".into()),
            _ => Ok(()),
        }
    }
}
