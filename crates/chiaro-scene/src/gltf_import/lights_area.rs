//! EXT_lights_area (a proposed extension: KhronosGroup/glTF pull request 2525): rect and
//! disk lights, listed in the root's `extensions.EXT_lights_area.lights` and placed by a
//! node's `extensions.EXT_lights_area.light`. Read from the raw JSON, since the gltf crate
//! drops extensions it does not know. Each light has a `type` ("rect" or "disk"), an
//! `intensity` (the surface's luminance in nits; 1000 if absent), a linear `color`, a
//! `size` (a rect's height along local Y, a disk's diameter; 1 m if absent) and a rect's
//! `rect.aspect` (width over height; 1 if absent); the node's largest world scale scales
//! the size. Extras as on punctual lights, with `pcss` shadows where they name none.

use super::Loader;
use super::nodes::Placement;
use super::object_label;
use crate::error::SceneError;
use crate::light::ShadowMode;
use crate::types::{Light, LightKind};
use glam::Vec3;
use serde_json::Value;

/// The extension's name.
pub const EXTENSION: &str = "EXT_lights_area";
/// `intensity` where a light gives none: nits.
const DEFAULT_INTENSITY_NITS: f32 = 1000.0;

impl Loader<'_> {
    /// The rect or disk light node `placement` carries, if any.
    pub(super) fn area_light(&self, placement: &Placement) -> Result<Option<Light>, SceneError> {
        let Some(reference) = self.raw.pointer(&format!("/nodes/{}/extensions/{EXTENSION}", placement.node)) else {
            return Ok(None);
        };
        let index = reference.get("light").and_then(Value::as_u64).ok_or_else(|| {
            self.invalid(format!("node {}: extensions.{EXTENSION}.light must be the index of a light", placement.node))
        })? as usize;
        let lights = self.raw.pointer(&format!("/extensions/{EXTENSION}/lights")).and_then(Value::as_array);
        let Some(light) = lights.and_then(|l| l.get(index)) else {
            return Err(self.invalid(format!(
                "node {}: {EXTENSION} light {index} is out of range (the file lists {})",
                placement.node,
                lights.map_or(0, Vec::len)
            )));
        };
        let name = light.get("name").and_then(Value::as_str);
        let label = object_label(&format!("{EXTENSION} light"), index, None, name);
        let number = |value: Option<&Value>, key: &str, default: f32| -> Result<f32, SceneError> {
            match value {
                None => Ok(default),
                Some(v) => v
                    .as_f64()
                    .map(|x| x as f32)
                    .filter(|x| x.is_finite())
                    .ok_or_else(|| self.invalid(format!("{label}: {key} must be a finite number, not {v}"))),
            }
        };
        let positive = |value: Option<&Value>, key: &str, default: f32| -> Result<f32, SceneError> {
            let x = number(value, key, default)?;
            if x <= 0.0 {
                return Err(self.invalid(format!("{label}: {key} {x} must be positive")));
            }
            Ok(x)
        };
        let intensity = number(light.get("intensity"), "intensity", DEFAULT_INTENSITY_NITS)?;
        let color = match light.get("color") {
            None => Vec3::ONE,
            Some(Value::Array(c)) if c.len() == 3 => Vec3::new(
                number(Some(&c[0]), "color", 0.0)?,
                number(Some(&c[1]), "color", 0.0)?,
                number(Some(&c[2]), "color", 0.0)?,
            ),
            Some(other) => return Err(self.invalid(format!("{label}: color must be three numbers, not {other}"))),
        };
        let size = positive(light.get("size"), "size", 1.0)?;
        let scale = max_scale(placement.world_from_local);
        if !(scale.is_finite() && scale > 0.0) {
            return Err(self.invalid(format!("{label}: node {} has no scale to size it by", placement.node)));
        }
        let kind = match light.get("type").and_then(Value::as_str) {
            Some("rect") => {
                let aspect = positive(light.pointer("/rect/aspect"), "rect.aspect", 1.0)?;
                LightKind::Rect { width: size * aspect * scale, height: size * scale }
            }
            Some("disk") => LightKind::Disk { diameter: size * scale },
            Some(other) => return Err(self.invalid(format!("{label}: type '{other}' is not rect or disk"))),
            None => return Err(self.invalid(format!("{label}: type is missing (rect or disk)"))),
        };
        // The luminance must be a light's; luminance times area is its peak intensity.
        self.check_light_strength(&label, color, intensity, None)?;
        let area = kind.area_shape().map_or(1.0, |s| s.area());
        self.check_light_strength(&label, color, intensity * area, None)?;
        let extras = light
            .get("extras")
            .map(serde_json::value::to_raw_value)
            .transpose()
            .map_err(|e| self.invalid(format!("{label}: extras: {e}")))?;
        let extras = extras.as_deref();
        let mut shadow = super::extras::light_shadow(extras).map_err(|e| self.invalid(format!("{label}: {e}")))?;
        if light.pointer("/extras/shadows").is_none() {
            shadow.mode = ShadowMode::Pcss;
        }
        let mode = super::extras::light_mode(extras).map_err(|e| self.invalid(format!("{label}: {e}")))?;
        if super::extras::light_cookie(extras).map_err(|e| self.invalid(format!("{label}: {e}")))?.is_some() {
            return Err(self.invalid(format!("{label}: extras.cookie: area lights take no cookie")));
        }
        let node = &self.root.nodes[placement.node];
        Ok(Some(Light {
            name: name
                .map(str::to_owned)
                .or_else(|| node.name.clone())
                .unwrap_or_else(|| format!("area light {index}")),
            node: placement.node,
            kind,
            color,
            intensity,
            range: None,
            world_from_light: super::lights_cameras::light_frame(placement.world_from_local),
            shadow,
            cookie: None,
            mode,
        }))
    }
}

/// The largest length a unit vector of the node's frame takes in the world.
fn max_scale(world_from_local: glam::Mat4) -> f32 {
    [world_from_local.x_axis, world_from_local.y_axis, world_from_local.z_axis]
        .iter()
        .map(|axis| axis.truncate().length())
        .fold(0.0, f32::max)
}
