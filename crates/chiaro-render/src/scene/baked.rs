//! Baked light on the GPU: the lightmaps as layers of one `Rgba16Float` 2D array (RGB
//! irradiance, sampled bilinearly), the shadow masks likewise in an `Rgba8Unorm` array
//! (one visibility per channel), and the probe grid as a storage buffer (a header, then
//! per probe nine RGB coefficients and its four occlusion values, as ten vec4s). Without
//! a bake, 1x1 stand-ins are bound (a mask of all ones: nothing shadowed).

use crate::gpu::GpuProbeGridHeader;
use chiaro_math::sh::SH_COEFFICIENTS;
use chiaro_scene::baked::BakedLighting;
use glam::Vec4;
use wgpu::util::DeviceExt;

/// The baked light bound in group 0 (1x1 stand-ins without a bake).
pub struct BakedTextures {
    /// The lightmaps, one layer per lightmap of the bake (RGB irradiance).
    pub lightmaps: wgpu::TextureView,
    /// The shadow masks, laid out as the lightmaps: one light's visibility per channel.
    pub shadow_masks: wgpu::TextureView,
    /// The probe grid: `GpuProbeGridHeader`, then ten vec4s per probe.
    pub probes: wgpu::Buffer,
}

/// Brightest irradiance the lightmap array stores as it is; brighter bakes are stored
/// divided by a scale (half floats stop at 65504, and filtering wants headroom).
const LIGHTMAP_HEADROOM: f32 = 16384.0;

/// What the lightmaps are divided by for upload (and multiplied by in the shader).
pub fn lightmap_scale(brightest: f32) -> f32 {
    if brightest.is_finite() && brightest > LIGHTMAP_HEADROOM { brightest / LIGHTMAP_HEADROOM } else { 1.0 }
}

/// Vec4s per probe in the probe buffer: nine coefficients, then the occlusion.
pub const PROBE_STRIDE: usize = SH_COEFFICIENTS + 1;

/// A 2D array texture of `layers` (at least one layer) of `width` x `height` texels.
fn array_texture(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    label: &str,
    format: wgpu::TextureFormat,
    (width, height): (u32, u32),
    layers: &[Vec<u8>],
    fill: &[u8],
) -> wgpu::TextureView {
    let texel_bytes = fill.len() as u32;
    let texture = device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d { width, height, depth_or_array_layers: layers.len().max(1) as u32 },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    });
    let stand_in = [fill.repeat((width * height) as usize)];
    let contents: &[Vec<u8>] = if layers.is_empty() { &stand_in } else { layers };
    for (layer, bytes) in contents.iter().enumerate() {
        queue.write_texture(
            wgpu::TexelCopyTextureInfo {
                texture: &texture,
                mip_level: 0,
                origin: wgpu::Origin3d { x: 0, y: 0, z: layer as u32 },
                aspect: wgpu::TextureAspect::All,
            },
            bytes,
            wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(width * texel_bytes),
                rows_per_image: Some(height),
            },
            wgpu::Extent3d { width, height, depth_or_array_layers: 1 },
        );
    }
    texture.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(wgpu::TextureViewDimension::D2Array),
        ..Default::default()
    })
}

impl BakedTextures {
    /// Uploads `baked` (or the stand-ins) as textures and the probe buffer.
    pub fn upload(device: &wgpu::Device, queue: &wgpu::Queue, baked: Option<&BakedLighting>) -> BakedTextures {
        let maps = baked.map(|b| b.lightmaps.as_slice()).unwrap_or_default();
        let size = maps.first().map_or((1, 1), |m| (m.width, m.height));
        let brightest = maps.iter().flat_map(|m| &m.texels).flat_map(|t| &t[..3]).fold(0.0f32, |a, &v| a.max(v));
        let lightmap_scale = lightmap_scale(brightest);
        let halves: Vec<Vec<u8>> = maps
            .iter()
            .map(|m| {
                let h: Vec<u16> = m
                    .texels
                    .iter()
                    .flat_map(|t| {
                        [t[0] / lightmap_scale, t[1] / lightmap_scale, t[2] / lightmap_scale, t[3]]
                            .map(|v| half::f16::from_f32(v).to_bits())
                    })
                    .collect();
                bytemuck::cast_slice(&h).to_vec()
            })
            .collect();
        let lightmaps =
            array_texture(device, queue, "lightmaps", wgpu::TextureFormat::Rgba16Float, size, &halves, &[0; 8]);
        let masks = baked.map(|b| b.shadow_masks.as_slice()).unwrap_or_default();
        let mask_size = masks.first().map_or((1, 1), |m| (m.width, m.height));
        let unorm: Vec<Vec<u8>> = masks
            .iter()
            .map(|m| m.texels.iter().flat_map(|t| t.map(|v| (v.clamp(0.0, 1.0) * 255.0).round() as u8)).collect())
            .collect();
        let shadow_masks =
            array_texture(device, queue, "shadow masks", wgpu::TextureFormat::Rgba8Unorm, mask_size, &unorm, &[255; 4]);

        let grid = baked.and_then(|b| b.probes.as_ref());
        let header = match grid {
            Some(g) => GpuProbeGridHeader {
                origin: g.origin,
                lightmap_scale,
                spacing: g.spacing,
                _pad1: 0.0,
                counts: g.counts.to_array(),
                _pad2: 0,
            },
            None => GpuProbeGridHeader {
                counts: [1; 3],
                spacing: glam::Vec3::ONE,
                lightmap_scale,
                ..bytemuck::Zeroable::zeroed()
            },
        };
        let mut bytes = bytemuck::bytes_of(&header).to_vec();
        let coefficients: Vec<Vec4> = match grid {
            Some(g) => g
                .probes
                .iter()
                .enumerate()
                .flat_map(|(k, p)| {
                    let occlusion = Vec4::from_array(g.occlusion.get(k).copied().unwrap_or([1.0; 4]));
                    p.coefficients.map(|c| c.extend(0.0)).into_iter().chain(std::iter::once(occlusion))
                })
                .collect(),
            None => [vec![Vec4::ZERO; SH_COEFFICIENTS], vec![Vec4::ONE]].concat(),
        };
        bytes.extend_from_slice(bytemuck::cast_slice(&coefficients));
        let probes = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("light probes"),
            contents: &bytes,
            usage: wgpu::BufferUsages::STORAGE,
        });
        BakedTextures { lightmaps, shadow_masks, probes }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bright_bakes_are_scaled_into_half_float_range() {
        assert_eq!(lightmap_scale(10.0), 1.0);
        assert_eq!(lightmap_scale(f32::NAN), 1.0);
        let sun = 1.0e5;
        let scale = lightmap_scale(sun);
        let stored = half::f16::from_f32(sun / scale).to_f32();
        assert!(stored.is_finite() && (stored * scale - sun).abs() / sun < 1e-3);
    }
}
