//! Scene images to GPU textures with a full mip chain, and samplers shared by description.

use chiaro_scene::{ColorSpace, Image, SamplerDesc, WrapMode};
use std::collections::HashMap;

/// Halves an RGBA8 image with a 2x2 box filter (clamping odd edges).
fn downsample(rgba: &[u8], width: u32, height: u32) -> (Vec<u8>, u32, u32) {
    let (w, h) = ((width / 2).max(1), (height / 2).max(1));
    let mut out = vec![0u8; (w * h * 4) as usize];
    for y in 0..h {
        for x in 0..w {
            for c in 0..4 {
                let mut sum = 0u32;
                for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                    let sx = (x * 2 + dx).min(width - 1);
                    let sy = (y * 2 + dy).min(height - 1);
                    sum += rgba[((sy * width + sx) * 4 + c) as usize] as u32;
                }
                out[((y * w + x) * 4 + c) as usize] = ((sum + 2) / 4) as u8;
            }
        }
    }
    (out, w, h)
}

pub fn upload_image(device: &wgpu::Device, queue: &wgpu::Queue, image: &Image) -> wgpu::TextureView {
    let format = match image.color_space {
        ColorSpace::Srgb => wgpu::TextureFormat::Rgba8UnormSrgb,
        ColorSpace::Linear => wgpu::TextureFormat::Rgba8Unorm,
    };
    let mip_level_count = 32 - image.width.max(image.height).max(1).leading_zeros();
    let texture = device.create_texture(&wgpu::TextureDescriptor {
        label: Some(&image.name),
        size: wgpu::Extent3d { width: image.width, height: image.height, depth_or_array_layers: 1 },
        mip_level_count,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    });
    let (mut data, mut w, mut h) = (image.rgba8.clone(), image.width, image.height);
    for level in 0..mip_level_count {
        if level > 0 {
            (data, w, h) = downsample(&data, w, h);
        }
        queue.write_texture(
            wgpu::TexelCopyTextureInfo {
                texture: &texture,
                mip_level: level,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::All,
            },
            &data,
            wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(w * 4), rows_per_image: Some(h) },
            wgpu::Extent3d { width: w, height: h, depth_or_array_layers: 1 },
        );
    }
    texture.create_view(&wgpu::TextureViewDescriptor::default())
}

/// A 1x1 texture of one colour, standing in for a texture a material does not have.
pub fn solid(device: &wgpu::Device, queue: &wgpu::Queue, name: &str, rgba: [u8; 4]) -> wgpu::TextureView {
    upload_image(
        device,
        queue,
        &Image { name: name.into(), width: 1, height: 1, rgba8: rgba.to_vec(), color_space: ColorSpace::Linear },
    )
}

fn address_mode(mode: WrapMode) -> wgpu::AddressMode {
    match mode {
        WrapMode::Repeat => wgpu::AddressMode::Repeat,
        WrapMode::MirroredRepeat => wgpu::AddressMode::MirrorRepeat,
        WrapMode::ClampToEdge => wgpu::AddressMode::ClampToEdge,
    }
}

fn filter(linear: bool) -> wgpu::FilterMode {
    if linear { wgpu::FilterMode::Linear } else { wgpu::FilterMode::Nearest }
}

/// Samplers keyed by their glTF description, so equal samplers are created once.
#[derive(Default)]
pub struct SamplerCache {
    samplers: HashMap<(WrapMode, WrapMode, bool, bool, bool), wgpu::Sampler>,
}

impl SamplerCache {
    pub fn get(&mut self, device: &wgpu::Device, d: &SamplerDesc) -> wgpu::Sampler {
        let key = (d.wrap_u, d.wrap_v, d.mag_linear, d.min_linear, d.mipmaps);
        self.samplers
            .entry(key)
            .or_insert_with(|| {
                device.create_sampler(&wgpu::SamplerDescriptor {
                    label: Some("material sampler"),
                    address_mode_u: address_mode(d.wrap_u),
                    address_mode_v: address_mode(d.wrap_v),
                    mag_filter: filter(d.mag_linear),
                    min_filter: filter(d.min_linear),
                    mipmap_filter: if d.mipmaps {
                        wgpu::MipmapFilterMode::Linear
                    } else {
                        wgpu::MipmapFilterMode::Nearest
                    },
                    anisotropy_clamp: if d.mipmaps && d.mag_linear && d.min_linear { 8 } else { 1 },
                    ..Default::default()
                })
            })
            .clone()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn downsample_averages_and_handles_odd_sizes() {
        let rgba: Vec<u8> = [0u8, 100, 200, 255].iter().flat_map(|&v| [v, v, v, 255]).collect();
        let (out, w, h) = downsample(&rgba, 2, 2);
        assert_eq!((w, h), (1, 1));
        assert_eq!(out[0], 139); // (0 + 100 + 200 + 255 + 2) / 4
        let (out, w, h) = downsample(&[7; 12], 3, 1);
        assert_eq!((w, h), (1, 1));
        assert_eq!(out, vec![7; 4]);
    }
}
