//! Baked light on the GPU: the lightmaps as layers of one `Rgba16Float` 2D array (RGB
//! irradiance, sampled bilinearly), and the probe grid as a storage buffer (a header,
//! then nine RGB coefficients per probe). Without a bake, 1x1 stand-ins are bound.

use crate::gpu::GpuProbeGridHeader;
use chiaro_math::sh::SH_COEFFICIENTS;
use chiaro_scene::baked::BakedLighting;
use glam::Vec4;
use wgpu::util::DeviceExt;

pub struct BakedTextures {
    pub lightmaps: wgpu::TextureView,
    pub probes: wgpu::Buffer,
}

impl BakedTextures {
    pub fn upload(device: &wgpu::Device, queue: &wgpu::Queue, baked: Option<&BakedLighting>) -> BakedTextures {
        let maps = baked.map(|b| b.lightmaps.as_slice()).unwrap_or_default();
        let (width, height) = maps.first().map_or((1, 1), |m| (m.width, m.height));
        let layers = maps.len().max(1) as u32;
        let texture = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("lightmaps"),
            size: wgpu::Extent3d { width, height, depth_or_array_layers: layers },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::Rgba16Float,
            usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
            view_formats: &[],
        });
        for (layer, map) in maps.iter().enumerate() {
            let halves: Vec<u16> =
                map.texels.iter().flat_map(|t| t.map(|v| half::f16::from_f32(v).to_bits())).collect();
            queue.write_texture(
                wgpu::TexelCopyTextureInfo {
                    texture: &texture,
                    mip_level: 0,
                    origin: wgpu::Origin3d { x: 0, y: 0, z: layer as u32 },
                    aspect: wgpu::TextureAspect::All,
                },
                bytemuck::cast_slice(&halves),
                wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(width * 8), rows_per_image: Some(height) },
                wgpu::Extent3d { width, height, depth_or_array_layers: 1 },
            );
        }
        let lightmaps = texture.create_view(&wgpu::TextureViewDescriptor {
            dimension: Some(wgpu::TextureViewDimension::D2Array),
            ..Default::default()
        });

        let grid = baked.and_then(|b| b.probes.as_ref());
        let header = match grid {
            Some(g) => GpuProbeGridHeader {
                origin: g.origin,
                _pad0: 0.0,
                spacing: g.spacing,
                _pad1: 0.0,
                counts: g.counts.to_array(),
                _pad2: 0,
            },
            None => GpuProbeGridHeader { counts: [1; 3], spacing: glam::Vec3::ONE, ..bytemuck::Zeroable::zeroed() },
        };
        let mut bytes = bytemuck::bytes_of(&header).to_vec();
        let coefficients: Vec<Vec4> = match grid {
            Some(g) => g.probes.iter().flat_map(|p| p.coefficients.map(|c| c.extend(0.0))).collect(),
            None => vec![Vec4::ZERO; SH_COEFFICIENTS],
        };
        bytes.extend_from_slice(bytemuck::cast_slice(&coefficients));
        let probes = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("light probes"),
            contents: &bytes,
            usage: wgpu::BufferUsages::STORAGE,
        });
        BakedTextures { lightmaps, probes }
    }
}
