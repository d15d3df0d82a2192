//! EXT_lights_image_based: the environment a file carries. The light the scene names, and
//! the six faces of its first specular mip, flow in; a `SceneEnvironment` (an
//! equirectangular map with the light's intensity and rotation applied) flows out, or an
//! error naming the file and the JSON path.
//!
//! Only mip 0 is read: the renderer prefilters its own mips and projects its own
//! irradiance from it, so the supplied mips and spherical harmonics (whose convention the
//! extension leaves open) are not needed. Faces with an alpha channel are RGBD, the others
//! low dynamic range, both gamma 2.2 (as the writers encode them); the cube is read as
//! Babylon.js reads it (mirrored in x, turned, in `chiaro_math::cube_map`'s layout).

use super::Loader;
use crate::environment::{
    CubeFaces, MAX_WIDTH, SceneEnvironment, image_based_light_direction, ldr_radiance, rgbd_radiance,
};
use crate::error::SceneError;
use glam::{Quat, Vec3, Vec4};
use serde_json::Value;

/// The extension's name, as files spell it.
pub const EXTENSION: &str = "EXT_lights_image_based";
/// The largest face accepted: four texels across per face texel makes the widest map an
/// environment image may be.
const MAX_FACE_SIZE: u32 = MAX_WIDTH / 4;
/// The brightest multiplier accepted, as for `environment.intensity`.
const MAX_INTENSITY: f64 = 1.0e6;

impl Loader<'_> {
    /// The environment the displayed scene (`scene`, a valid index) names, if any.
    pub(super) fn scene_environment(&mut self, scene: Option<usize>) -> Result<Option<SceneEnvironment>, SceneError> {
        let lights = self.raw.pointer(&format!("/extensions/{EXTENSION}/lights"));
        let Some(scene) = scene else { return Ok(None) };
        let reference_path = format!("scenes[{scene}].extensions.{EXTENSION}.light");
        let Some(reference) = self.raw.pointer(&format!("/scenes/{scene}/extensions/{EXTENSION}/light")) else {
            if lights.is_some() {
                self.ignored.push(format!("extension {EXTENSION}: scenes[{scene}] names none of its lights, unused"));
            }
            return Ok(None);
        };
        let lights_path = format!("extensions.{EXTENSION}.lights");
        let lights = lights
            .and_then(Value::as_array)
            .ok_or_else(|| self.invalid(format!("{reference_path} names a light, but {lights_path} is not a list")))?;
        let index = reference.as_u64().map(|i| i as usize).filter(|&i| i < lights.len()).ok_or_else(|| {
            self.invalid(format!(
                "{reference_path}: {reference} is not one of the {} lights of {lights_path}",
                lights.len()
            ))
        })?;
        let path = format!("{lights_path}[{index}]");
        let light = &lights[index];
        let field = |key: &str| light.get(key);
        let intensity = match field("intensity") {
            None => 1.0,
            Some(v) => v.as_f64().filter(|i| (0.0..=MAX_INTENSITY).contains(i)).ok_or_else(|| {
                self.invalid(format!("{path}.intensity: {v} is not a number from 0 to {MAX_INTENSITY}"))
            })? as f32,
        };
        let rotation = match field("rotation") {
            None => Quat::IDENTITY,
            Some(v) => unit_quaternion(v)
                .ok_or_else(|| self.invalid(format!("{path}.rotation: {v} is not a quaternion [x, y, z, w]")))?,
        };
        let faces = field("specularImages")
            .and_then(Value::as_array)
            .and_then(|mips| mips.first())
            .and_then(Value::as_array)
            .filter(|faces| faces.len() == 6)
            .ok_or_else(|| self.invalid(format!("{path}.specularImages: its first mip is not a list of six images")))?;
        let mut cube = CubeFaces { size: 0, faces: Default::default() };
        for (face, image) in faces.iter().enumerate() {
            let face_path = format!("{path}.specularImages[0][{face}]");
            let image = image
                .as_u64()
                .map(|i| i as usize)
                .filter(|&i| i < self.root.images.len())
                .ok_or_else(|| self.invalid(format!("{face_path}: {image} is not an image of the file")))?;
            let pixels = self.decode_pixels(image, Some(MAX_FACE_SIZE)).map_err(|e| e.in_context(&face_path))?;
            let (width, height) = (pixels.width(), pixels.height());
            let expected = if face == 0 { width } else { cube.size };
            // (Faces over MAX_FACE_SIZE were refused from their headers.)
            if width != height || width != expected || width == 0 {
                return Err(self.invalid(format!(
                    "{face_path}: image {image} is {width} x {height}; each face must be square and as large as the \
                     first ({expected})"
                )));
            }
            cube.size = width;
            cube.faces[face] = face_radiance(pixels);
        }
        if let Some(size) = field("specularImageSize")
            && size.as_u64() != Some(u64::from(cube.size))
        {
            return Err(self.invalid(format!(
                "{path}.specularImageSize: {size}, but its first mip's faces are {0} x {0}",
                cube.size
            )));
        }
        self.ignored.push(format!(
            "{path}: irradianceCoefficients and specular mips after the first not read; Chiaro makes both from the \
             first mip"
        ));
        let mut map = cube.to_equirect(|d| image_based_light_direction(d, rotation));
        map.texels.iter_mut().for_each(|t| *t *= intensity);
        let label = match light.get("name").and_then(Value::as_str) {
            Some(name) => format!("{EXTENSION} light {index} ({name})"),
            None => format!("{EXTENSION} light {index}"),
        };
        Ok(Some(SceneEnvironment::new(label, map)))
    }
}

/// A rotation from a glTF `[x, y, z, w]` array, normalised; `None` unless four finite
/// numbers of non-zero length.
fn unit_quaternion(value: &Value) -> Option<Quat> {
    let numbers: Vec<f32> = value.as_array()?.iter().map(|v| v.as_f64().map(|f| f as f32)).collect::<Option<_>>()?;
    let q = Quat::from_slice(numbers.get(..4).filter(|_| numbers.len() == 4)?);
    let length = q.length();
    (length.is_finite() && length > 1e-6).then(|| q / length)
}

/// Linear radiance of a face's pixels: RGBD where the image has alpha, else LDR.
fn face_radiance(pixels: image::DynamicImage) -> Vec<Vec3> {
    let rgbd = pixels.color().has_alpha();
    pixels
        .into_rgba32f()
        .pixels()
        .map(|p| {
            let p = Vec4::from_array(p.0);
            if rgbd { rgbd_radiance(p) } else { ldr_radiance(p.truncate()) }
        })
        .collect()
}
