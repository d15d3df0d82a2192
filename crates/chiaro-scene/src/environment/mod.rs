//! Environment maps: the radiance arriving from every direction, as an equirectangular
//! image in glTF's physical units (nits). A source and the scene flow in (a studio made
//! here, a daylight sky from the first directional light, an `.hdr`/`.exr` file, or the
//! glTF file's own EXT_lights_image_based cube, read by the importer); an
//! `EnvironmentMap` or an error naming the file flows out. The renderer turns the map
//! into irradiance and a prefiltered cube; the baker and the reference trace it.

mod cube_faces;
mod image_file;
mod neutral;
mod sky;

pub use cube_faces::{
    CubeFaces, MAX_EQUIRECT_WIDTH, image_based_light_direction, ldr_radiance, rgbd_encode, rgbd_radiance,
};
pub use image_file::{MAX_HEIGHT, MAX_WIDTH, check_image, load_image};
pub use neutral::{STUDIO_TO_SUN_ILLUMINANCE, neutral};
pub use sky::{SKY_TO_SUN_ILLUMINANCE, sky};

use crate::settings::EnvironmentSource;
use crate::types::{LightKind, Scene};
use chiaro_math::environment::{environment_direction, equirect_direction, equirect_texel_solid_angle, equirect_uv};
use glam::{Vec2, Vec3};
use std::borrow::Cow;
use std::hash::{Hash, Hasher};
use std::path::PathBuf;
use std::sync::Arc;

/// Radiance over the sphere, equirectangular: `width` = 2 x `height`, rows from +Y down.
#[derive(Clone, Debug, PartialEq)]
pub struct EnvironmentMap {
    /// Texels across: twice `height`.
    pub width: u32,
    /// Texels down.
    pub height: u32,
    /// Linear RGB radiance, row by row from the top.
    pub texels: Vec<Vec3>,
}

/// Why an environment could not be made; names the file.
#[derive(Debug, thiserror::Error)]
pub enum EnvironmentError {
    /// The file could not be read.
    #[error("{path}: cannot read environment image: {message}")]
    Io {
        /// The image.
        path: PathBuf,
        /// What the file system or decoder said.
        message: String,
    },
    /// The file is not an environment Chiaro can use.
    #[error("{path}: {message}")]
    Invalid {
        /// The image.
        path: PathBuf,
        /// What is wrong with it.
        message: String,
    },
}

impl EnvironmentMap {
    /// A map of `width` x `width / 2` texels with radiance `f(direction)` at each centre.
    pub fn from_fn(width: u32, f: impl Fn(Vec3) -> Vec3) -> EnvironmentMap {
        let height = width / 2;
        let mut texels = Vec::with_capacity((width * height) as usize);
        for y in 0..height {
            for x in 0..width {
                let uv = Vec2::new((x as f32 + 0.5) / width as f32, (y as f32 + 0.5) / height as f32);
                texels.push(f(equirect_direction(uv)));
            }
        }
        EnvironmentMap { width, height, texels }
    }

    /// The same radiance everywhere: the furnace of the tests.
    pub fn uniform(radiance: Vec3) -> EnvironmentMap {
        EnvironmentMap { width: 8, height: 4, texels: vec![radiance; 32] }
    }

    /// The radiance the nearest texel holds for unit direction `d` (in the map's frame).
    pub fn radiance(&self, d: Vec3) -> Vec3 {
        let uv = equirect_uv(d);
        let x = ((uv.x.rem_euclid(1.0) * self.width as f32) as u32).min(self.width - 1);
        let y = ((uv.y * self.height as f32) as u32).min(self.height - 1);
        self.texels[(y * self.width + x) as usize]
    }

    /// The radiance at texture coordinate `uv`, bilinear between texel centres, wrapping
    /// across u and clamped in v.
    pub fn bilinear(&self, uv: Vec2) -> Vec3 {
        let x = uv.x * self.width as f32 - 0.5;
        let y = (uv.y * self.height as f32 - 0.5).clamp(0.0, (self.height - 1) as f32);
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        let at = |x: f32, y: f32| {
            let x = (x as i64).rem_euclid(self.width as i64) as u32;
            let y = (y as u32).min(self.height - 1);
            self.texels[(y * self.width + x) as usize]
        };
        let top = at(x0, y0).lerp(at(x0 + 1.0, y0), fx);
        let bottom = at(x0, y0 + 1.0).lerp(at(x0 + 1.0, y0 + 1.0), fx);
        top.lerp(bottom, fy)
    }

    /// Writes the map to `path` as an equirectangular Radiance .hdr file, which
    /// `load_image` (and `--environment`) read back.
    pub fn write_hdr(&self, path: &std::path::Path) -> Result<(), image::ImageError> {
        let pixels: Vec<image::Rgb<f32>> = self.texels.iter().map(|t| image::Rgb(t.to_array())).collect();
        let file = std::io::BufWriter::new(std::fs::File::create(path).map_err(image::ImageError::IoError)?);
        image::codecs::hdr::HdrEncoder::new(file).encode(&pixels, self.width as usize, self.height as usize)
    }

    /// Irradiance on a surface facing +Y from the upper half, lux: what a sky gives the
    /// ground.
    pub fn upward_irradiance(&self) -> Vec3 {
        let mut e = Vec3::ZERO;
        for y in 0..self.height {
            let weight = equirect_texel_solid_angle(y, self.width, self.height);
            let up = equirect_direction(Vec2::new(0.5, (y as f32 + 0.5) / self.height as f32)).y;
            if up <= 0.0 {
                continue;
            }
            let row = &self.texels[(y * self.width) as usize..((y + 1) * self.width) as usize];
            e += row.iter().copied().sum::<Vec3>() * weight * up;
        }
        e
    }
}

/// An environment as the CPU tracers see it (the baker and the reference): the map,
/// scaled by `intensity` and turned by `rotation_deg` about +Y, sampled bilinearly as
/// the renderer's background is.
#[derive(Clone, Debug, PartialEq)]
pub struct EnvironmentLight {
    /// The radiance over the sphere, in the image's frame.
    pub map: EnvironmentMap,
    /// `environment.intensity`.
    pub intensity: f32,
    /// `environment.rotation_deg`.
    pub rotation_deg: f32,
}

impl EnvironmentLight {
    /// The environment the settings give `scene` (its own under `none`), or `None` where
    /// the constant ambient term lights it.
    pub fn from_settings(
        settings: &crate::settings::EnvironmentSettings,
        scene: &Scene,
    ) -> Result<Option<EnvironmentLight>, EnvironmentError> {
        Ok(environment_map(&settings.source, scene)?.map(|map| EnvironmentLight {
            map: map.into_owned(),
            intensity: settings.intensity,
            rotation_deg: settings.rotation_deg,
        }))
    }

    /// Radiance arriving from world direction `d` (unit).
    pub fn radiance(&self, d: Vec3) -> Vec3 {
        let uv = equirect_uv(environment_direction(d, self.rotation_deg));
        self.map.bilinear(uv) * self.intensity
    }
}

/// The direction towards the sun and its illuminance (lux, weighted by its colour's
/// luminance): the scene's first directional light, or none.
pub fn scene_sun(scene: &Scene) -> Option<(Vec3, f32)> {
    let light = scene.lights.iter().find(|l| matches!(l.kind, LightKind::Directional))?;
    let luminance = light.color.dot(Vec3::new(0.2126, 0.7152, 0.0722));
    Some((-light.direction(), light.intensity * luminance))
}

/// The environment a glTF file carries, made into a map at import (its intensity and
/// rotation already applied).
#[derive(Clone, Debug)]
pub struct SceneEnvironment {
    /// Where it came from, for messages: `EXT_lights_image_based light 0 (name)`.
    pub label: String,
    /// The radiance, in the world's frame.
    pub map: Arc<EnvironmentMap>,
    /// A hash of the texels: the renderer makes its maps again when it changes.
    pub fingerprint: u64,
}

impl SceneEnvironment {
    /// The scene's environment `map`, named `label`.
    pub fn new(label: String, map: EnvironmentMap) -> SceneEnvironment {
        let mut hasher = std::collections::hash_map::DefaultHasher::new();
        (map.width, map.height).hash(&mut hasher);
        for texel in &map.texels {
            texel.to_array().map(f32::to_bits).hash(&mut hasher);
        }
        SceneEnvironment { label, map: Arc::new(map), fingerprint: hasher.finish() }
    }
}

/// The map a source names for `scene`, or `None` where the constant ambient term lights
/// it (`ambient`, or `none` for a scene without an environment of its own). The scene's
/// own map is lent, not copied.
pub fn environment_map<'a>(
    source: &EnvironmentSource,
    scene: &'a Scene,
) -> Result<Option<Cow<'a, EnvironmentMap>>, EnvironmentError> {
    Ok(match source {
        EnvironmentSource::None => scene.environment.as_ref().map(|own| Cow::Borrowed(&*own.map)),
        EnvironmentSource::Ambient => None,
        EnvironmentSource::Neutral => Some(Cow::Owned(neutral(scene_sun(scene).map(|(_, lux)| lux)))),
        EnvironmentSource::Sky => Some(Cow::Owned(sky(scene_sun(scene)))),
        EnvironmentSource::File(path) => Some(Cow::Owned(load_image(path)?)),
    })
}
