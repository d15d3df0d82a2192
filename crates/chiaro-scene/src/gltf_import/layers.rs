//! A material's KHR_materials_* extensions (ior, specular, clearcoat, sheen, transmission,
//! volume, iridescence, anisotropy, dispersion, diffuse transmission) into
//! [`MaterialLayers`], read from the raw JSON. A factor outside its schema's range, or
//! not a number, is an error naming the material, the extension and the key
//! (docs/gltf.md lists each): a value a validator refuses has no meaning to guess.

use super::Loader;
use crate::error::SceneError;
use crate::layers::{LayerTexture, MaterialLayers};
use glam::Vec3;
use serde_json::Value;

/// The extensions this module reads.
pub const EXTENSIONS: [&str; 10] = [
    "KHR_materials_ior",
    "KHR_materials_specular",
    "KHR_materials_clearcoat",
    "KHR_materials_sheen",
    "KHR_materials_transmission",
    "KHR_materials_volume",
    "KHR_materials_iridescence",
    "KHR_materials_anisotropy",
    "KHR_materials_dispersion",
    "KHR_materials_diffuse_transmission",
];

/// One extension object of one material, with the label its messages start with.
struct Extension<'a> {
    label: String,
    json: &'a Value,
}

/// A number's allowed range, both ends included.
#[derive(Clone, Copy)]
struct Range {
    min: f32,
    max: f32,
}

const UNIT: Range = Range { min: 0.0, max: 1.0 };
const NON_NEGATIVE: Range = Range { min: 0.0, max: f32::INFINITY };

impl Extension<'_> {
    /// `key` as a number in `range`, `default` where absent.
    fn number(&self, key: &str, default: f32, range: Range) -> Result<f32, String> {
        let Some(value) = self.json.get(key) else { return Ok(default) };
        let number = value
            .as_f64()
            .map(|v| v as f32)
            .filter(|v| v.is_finite())
            .ok_or_else(|| format!("{}.{key} is {value}, not a finite number", self.label))?;
        if number < range.min || number > range.max {
            let bounds = if range.max.is_infinite() {
                format!("at least {}", range.min)
            } else {
                format!("within [{}, {}]", range.min, range.max)
            };
            return Err(format!("{}.{key} is {number}, but must be {bounds}", self.label));
        }
        Ok(number)
    }

    /// `key` as an RGB triple whose channels are in `range`.
    fn color(&self, key: &str, default: Vec3, range: Range) -> Result<Vec3, String> {
        let Some(value) = self.json.get(key) else { return Ok(default) };
        let channels: Option<Vec<f32>> = value
            .as_array()
            .filter(|a| a.len() == 3)
            .map(|a| a.iter().filter_map(Value::as_f64).map(|v| v as f32).filter(|v| v.is_finite()).collect());
        match channels {
            Some(c) if c.len() == 3 => {
                if c.iter().any(|&v| v < range.min || v > range.max) {
                    let bounds =
                        if range.max.is_infinite() { "at least 0".to_string() } else { "within [0, 1]".into() };
                    return Err(format!("{}.{key} is {value}: every channel must be {bounds}", self.label));
                }
                Ok(Vec3::new(c[0], c[1], c[2]))
            }
            _ => Err(format!("{}.{key} is {value}, not three finite numbers", self.label)),
        }
    }
}

impl Loader<'_> {
    /// The extensions of material `index` (whose raw JSON is `raw` and whose messages
    /// start with `label`).
    pub(super) fn material_layers(&mut self, label: &str, raw: &Value) -> Result<MaterialLayers, SceneError> {
        let mut layers = MaterialLayers::default();
        let extension = |name: &str| {
            raw.pointer(&format!("/extensions/{name}"))
                .map(|json| Extension { label: format!("{label}: {name}"), json })
        };
        let mut fields = || -> Result<(), String> {
            if let Some(e) = extension("KHR_materials_ior") {
                // Schema: ior >= 1, or exactly 0, which the spec allows for an infinite
                // ior: ((ior - 1) / (ior + 1))^2 gives F0 = 1 for it as it stands.
                layers.ior = match e.json.get("ior").and_then(Value::as_f64) {
                    Some(0.0) => 0.0,
                    _ => e.number("ior", 1.5, Range { min: 1.0, max: f32::INFINITY })?,
                };
            }
            if let Some(e) = extension("KHR_materials_specular") {
                layers.specular = e.number("specularFactor", 1.0, UNIT)?;
                layers.specular_color = e.color("specularColorFactor", Vec3::ONE, NON_NEGATIVE)?;
            }
            if let Some(e) = extension("KHR_materials_clearcoat") {
                layers.clearcoat = e.number("clearcoatFactor", 0.0, UNIT)?;
                layers.clearcoat_roughness = e.number("clearcoatRoughnessFactor", 0.0, UNIT)?;
                if let Some(normal) = e.json.get("clearcoatNormalTexture") {
                    let scale = Extension { label: format!("{}.clearcoatNormalTexture", e.label), json: normal };
                    layers.clearcoat_normal_scale =
                        scale.number("scale", 1.0, Range { min: f32::NEG_INFINITY, max: f32::INFINITY })?;
                }
            }
            if let Some(e) = extension("KHR_materials_sheen") {
                layers.sheen_color = e.color("sheenColorFactor", Vec3::ZERO, UNIT)?;
                layers.sheen_roughness = e.number("sheenRoughnessFactor", 0.0, UNIT)?;
            }
            if let Some(e) = extension("KHR_materials_transmission") {
                layers.transmission = e.number("transmissionFactor", 0.0, UNIT)?;
            }
            if let Some(e) = extension("KHR_materials_volume") {
                layers.thickness = e.number("thicknessFactor", 0.0, NON_NEGATIVE)?;
                let distance = e.number("attenuationDistance", f32::INFINITY, NON_NEGATIVE)?;
                if distance == 0.0 {
                    return Err(format!("{}.attenuationDistance is 0, but must be above 0", e.label));
                }
                layers.attenuation_distance = distance;
                layers.attenuation_color = e.color("attenuationColor", Vec3::ONE, UNIT)?;
            }
            if let Some(e) = extension("KHR_materials_iridescence") {
                layers.iridescence = e.number("iridescenceFactor", 0.0, UNIT)?;
                layers.iridescence_ior = e.number("iridescenceIor", 1.3, Range { min: 1.0, max: f32::INFINITY })?;
                layers.iridescence_thickness_min = e.number("iridescenceThicknessMinimum", 100.0, NON_NEGATIVE)?;
                layers.iridescence_thickness_max = e.number("iridescenceThicknessMaximum", 400.0, NON_NEGATIVE)?;
            }
            if let Some(e) = extension("KHR_materials_anisotropy") {
                layers.anisotropy_strength = e.number("anisotropyStrength", 0.0, UNIT)?;
                layers.anisotropy_rotation =
                    e.number("anisotropyRotation", 0.0, Range { min: f32::NEG_INFINITY, max: f32::INFINITY })?;
            }
            if let Some(e) = extension("KHR_materials_dispersion") {
                layers.dispersion = e.number("dispersion", 0.0, NON_NEGATIVE)?;
            }
            if let Some(e) = extension("KHR_materials_diffuse_transmission") {
                layers.diffuse_transmission = e.number("diffuseTransmissionFactor", 0.0, UNIT)?;
                layers.diffuse_transmission_color = e.color("diffuseTransmissionColorFactor", Vec3::ONE, UNIT)?;
            }
            Ok(())
        };
        fields().map_err(|message| self.invalid(message))?;

        for slot in LayerTexture::ALL {
            let (name, key) = slot.json_key();
            let Some(info) = raw.pointer(&format!("/extensions/{name}/{key}")) else { continue };
            let slot_label = format!("{label}: {name}.{key}");
            let index = info.get("index").and_then(Value::as_u64).map(|i| i as usize);
            let texture = match index {
                Some(i) if i < self.root.textures.len() => i,
                _ => {
                    return Err(self.invalid(format!(
                        "{slot_label}: index {} names no texture (the file has {})",
                        info.get("index").map_or("(missing)".to_string(), Value::to_string),
                        self.root.textures.len()
                    )));
                }
            };
            let tex_coord = match info.get("texCoord") {
                None => 0,
                Some(v) => v.as_u64().filter(|&s| s < 8).map(|s| s as u32).ok_or_else(|| {
                    self.invalid(format!("{slot_label}: texCoord {v} is not a texture coordinate set"))
                })?,
            };
            layers.textures[slot.index()] = self.texture_ref(&slot_label, texture, tex_coord, Some(info))?;
        }
        Ok(layers)
    }
}
