//! The environment on the GPU: the equirectangular image (for the background), a
//! GGX-prefiltered cube with a mip per roughness and the split-sum BRDF table (made by
//! compute passes, `bake`), and a uniform with the irradiance's spherical harmonics
//! (projected on the CPU from the full-precision image). Settings and the scene flow in;
//! the maps are made again only when the source (or, for `sky`, the sun; for the file's
//! own environment, its texels) changes, while
//! intensity and rotation are written each frame. Without an environment, 1x1 stand-ins
//! are bound and the shaders compile the environment out; the BRDF table is always the
//! real one (punctual lights' energy compensation and sheen read it).

mod bake;

use crate::error::RenderError;
use crate::gpu::GpuEnvironment;
use chiaro_math::environment::project_equirect;
use chiaro_math::sh::ShRgb;
use chiaro_scene::Scene;
use chiaro_scene::environment::{EnvironmentMap, environment_map, scene_sun};
use chiaro_scene::settings::{EnvironmentMode, EnvironmentSettings, EnvironmentSource};
use glam::Vec3;
use std::borrow::Cow;
use std::path::PathBuf;
use std::time::SystemTime;

/// The widest equirectangular image sent to the device: wider images are averaged down
/// (the background loses detail past this; the irradiance keeps the full image).
const MAX_DEVICE_WIDTH: u32 = 4096;
/// Brightest radiance the half-float maps store as it is; brighter images are stored
/// divided by a scale the shaders multiply back (half floats stop at 65504).
const HALF_HEADROOM: f32 = 16384.0;

/// What the current maps were made from: a different key makes them again.
#[derive(Clone, Debug, PartialEq)]
enum EnvironmentKey {
    /// The sun's illuminance, as bits, which scales the studio.
    Neutral(Option<u32>),
    /// The sun's direction and illuminance, as bits.
    Sky(Option<([u32; 3], u32)>),
    /// The file, its length and modification time (so the viewer sees an edited file).
    File(PathBuf, u64, Option<SystemTime>),
    /// The glTF file's own environment, by its texels' hash.
    Scene(u64),
}

fn key_of(source: &EnvironmentSource, scene: &Scene) -> Option<EnvironmentKey> {
    match source {
        EnvironmentSource::None => scene.environment.as_ref().map(|own| EnvironmentKey::Scene(own.fingerprint)),
        EnvironmentSource::Ambient => None,
        EnvironmentSource::Neutral => Some(EnvironmentKey::Neutral(scene_sun(scene).map(|(_, lux)| lux.to_bits()))),
        EnvironmentSource::Sky => {
            Some(EnvironmentKey::Sky(scene_sun(scene).map(|(d, lux)| (d.to_array().map(f32::to_bits), lux.to_bits()))))
        }
        EnvironmentSource::File(path) => {
            let meta = std::fs::metadata(path).ok();
            let len = meta.as_ref().map_or(0, |m| m.len());
            Some(EnvironmentKey::File(path.clone(), len, meta.and_then(|m| m.modified().ok())))
        }
    }
}

/// The environment's textures and uniform, bound in group 0 (bindings 18 to 21).
pub struct GpuEnvironmentMaps {
    /// `GpuEnvironment`, written each frame.
    pub uniform: wgpu::Buffer,
    /// The prefiltered cube: mip k holds roughness k / last mip.
    pub specular: wgpu::TextureView,
    /// The split-sum table: (scale, bias) at (n.v, roughness).
    pub brdf_table: wgpu::TextureView,
    /// The equirectangular radiance, for the background.
    pub image: wgpu::TextureView,
    radiance_sh: ShRgb,
    specular_last_mip: f32,
    /// What the half-float maps hold is radiance divided by this.
    storage_scale: f32,
}

/// The current environment, made again when its key changes.
pub struct EnvironmentCache {
    key: Option<EnvironmentKey>,
    maps: GpuEnvironmentMaps,
    baker: Option<bake::EnvironmentBaker>,
    /// The BRDF table, made with the cache: bound with or without an environment.
    table: wgpu::Texture,
}

impl EnvironmentCache {
    /// Stand-ins, until a frame asks for an environment.
    pub fn new(device: &wgpu::Device, queue: &wgpu::Queue) -> EnvironmentCache {
        let table = bake::bake_brdf_table(device, queue);
        EnvironmentCache { key: None, maps: stand_ins(device, queue, &table), baker: None, table }
    }

    /// The bound maps.
    pub fn maps(&self) -> &GpuEnvironmentMaps {
        &self.maps
    }

    /// Makes the maps `settings` call for if they changed (then returns true), and writes
    /// this frame's intensity and rotation. Errors name the image file.
    pub fn update(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        settings: &EnvironmentSettings,
        scene: &Scene,
    ) -> Result<bool, RenderError> {
        let key = key_of(&settings.source, scene);
        let changed = key.is_some() && key != self.key;
        if changed {
            let map = environment_map(&settings.source, scene)
                .map_err(|e| RenderError::Environment(e.to_string()))?
                .expect("a source with a key has a map");
            let table = &self.table;
            let baker = self.baker.get_or_insert_with(|| bake::EnvironmentBaker::new(device, table.clone()));
            self.maps = baker.make(device, queue, &map);
            self.key = key;
        }
        queue.write_buffer(&self.maps.uniform, 0, bytemuck::bytes_of(&self.maps.uniform_for(settings)));
        Ok(changed)
    }
}

impl GpuEnvironmentMaps {
    fn uniform_for(&self, settings: &EnvironmentSettings) -> GpuEnvironment {
        let (sin, cos) = (-settings.rotation_deg.to_radians()).sin_cos();
        let sh = self.radiance_sh.scaled(settings.intensity);
        GpuEnvironment {
            radiance_sh: sh.coefficients.map(|c| c.extend(0.0)),
            turn_cos: cos,
            turn_sin: sin,
            intensity: settings.intensity * self.storage_scale,
            specular_last_mip: self.specular_last_mip,
            diffuse_baked: u32::from(settings.mode == EnvironmentMode::Baked),
            _pad: [0; 3],
        }
    }
}

/// The scale a map brightest at `brightest` is stored divided by.
fn storage_scale(brightest: f32) -> f32 {
    if brightest > HALF_HEADROOM { brightest / HALF_HEADROOM } else { 1.0 }
}

/// The map averaged down 2x2 until it is at most `MAX_DEVICE_WIDTH` wide; borrowed as it
/// is when it already fits (an 8192-wide image is 400 MB of texels: no copy for nothing).
fn device_sized(map: &EnvironmentMap) -> Cow<'_, EnvironmentMap> {
    let mut map = Cow::Borrowed(map);
    while map.width > MAX_DEVICE_WIDTH {
        let (w, h) = (map.width / 2, map.height / 2);
        let at = |x: u32, y: u32| map.texels[(y * map.width + x) as usize];
        let texels = (0..w * h)
            .map(|i| {
                let (x, y) = (i % w * 2, i / w * 2);
                (at(x, y) + at(x + 1, y) + at(x, y + 1) + at(x + 1, y + 1)) * 0.25
            })
            .collect();
        map = Cow::Owned(EnvironmentMap { width: w, height: h, texels });
    }
    map
}

/// The radiance of `map` as half-float RGBA texels, divided by `scale`.
fn half_texels(map: &EnvironmentMap, scale: f32) -> Vec<u16> {
    map.texels
        .iter()
        .flat_map(|t| {
            let t = *t / scale;
            [t.x, t.y, t.z, 1.0].map(|v| half::f16::from_f32(v.min(65504.0)).to_bits())
        })
        .collect()
}

fn uniform_buffer(device: &wgpu::Device) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("environment uniform"),
        size: size_of::<GpuEnvironment>() as u64,
        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

/// 1x1 black maps and the BRDF table, bound where no environment is.
fn stand_ins(device: &wgpu::Device, queue: &wgpu::Queue, table: &wgpu::Texture) -> GpuEnvironmentMaps {
    let black = EnvironmentMap { width: 1, height: 1, texels: vec![Vec3::ZERO] };
    let image = bake::upload_equirect(device, queue, &black, 1.0);
    let cube = bake::cube_texture(device, "environment stand-in cube", 1, 1, wgpu::TextureUsages::TEXTURE_BINDING);
    GpuEnvironmentMaps {
        uniform: uniform_buffer(device),
        specular: bake::cube_view(&cube),
        brdf_table: bake::table_view(table),
        image: image.create_view(&Default::default()),
        radiance_sh: ShRgb::default(),
        specular_last_mip: 0.0,
        storage_scale: 1.0,
    }
}

/// The irradiance's coefficients and the storage scale of `map`.
fn map_summary(map: &EnvironmentMap) -> (ShRgb, f32) {
    let brightest = map.texels.iter().fold(0.0f32, |m, t| m.max(t.max_element()));
    (project_equirect(&map.texels, map.width, map.height), storage_scale(brightest))
}
