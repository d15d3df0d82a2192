//! `[camera]`: the camera Chiaro makes for a scene that has none. TOML values flow in;
//! `CameraSettings` and its validation flow out.

use super::bound::Bound;
use serde::{Deserialize, Serialize};

/// The `[camera]` section.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct CameraSettings {
    /// Vertical field of view (degrees, 1 to 179) of the camera made when a scene has none.
    pub auto_yfov_deg: f32,
}

impl Default for CameraSettings {
    fn default() -> Self {
        CameraSettings { auto_yfov_deg: 45.0 }
    }
}

/// The interval of `camera.auto_yfov_deg`.
pub const AUTO_YFOV_DEG: Bound = Bound::new("camera.auto_yfov_deg", 1.0, 179.0);

/// Every interval of the section.
pub(super) const BOUNDS: &[Bound] = &[AUTO_YFOV_DEG];

impl CameraSettings {
    /// Checks every value of the section; the message starts with the dotted key.
    pub fn validate(&self) -> Result<(), String> {
        AUTO_YFOV_DEG.check(self.auto_yfov_deg)
    }
}
