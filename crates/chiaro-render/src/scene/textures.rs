//! Scene images to GPU textures with a full mip chain (the file's levels where it stores
//! them, else box-filtered ones), and samplers shared by description.

use chiaro_scene::{ColorSpace, Image, SamplerDesc, WrapMode};
use std::collections::HashMap;

/// Each texel of a line of `to` texels averages the `from / to` source texels it covers,
/// partial texels by their covered share: a box filter that, unlike picking two texels
/// per output, never drops the last texel of an odd size. Returns (first source texel,
/// weights) per output texel.
fn box_weights(from: u32, to: u32) -> Vec<(u32, Vec<f32>)> {
    let scale = from as f32 / to as f32;
    (0..to)
        .map(|i| {
            let (start, end) = (i as f32 * scale, (i + 1) as f32 * scale);
            let first = start.floor() as u32;
            let last = (end.ceil() as u32).min(from);
            let weights =
                (first..last).map(|s| ((s + 1) as f32).min(end) - (s as f32).max(start)).map(|w| w / scale).collect();
            (first, weights)
        })
        .collect()
}

/// Halves an RGBA8 image (each side to at least 1) with a box filter over every source
/// texel; even sizes average 2x2 blocks.
pub(super) fn downsample(rgba: &[u8], width: u32, height: u32) -> (Vec<u8>, u32, u32) {
    let (w, h) = ((width / 2).max(1), (height / 2).max(1));
    let (across, down) = (box_weights(width, w), box_weights(height, h));
    // Rows first, into floats, then columns.
    let mut rows = vec![0f32; (w * height * 4) as usize];
    for y in 0..height {
        for (x, (first, weights)) in across.iter().enumerate() {
            for (k, weight) in weights.iter().enumerate() {
                let src = ((y * width + first + k as u32) * 4) as usize;
                let dst = ((y * w + x as u32) * 4) as usize;
                for c in 0..4 {
                    rows[dst + c] += weight * rgba[src + c] as f32;
                }
            }
        }
    }
    let mut out = vec![0u8; (w * h * 4) as usize];
    for (y, (first, weights)) in down.iter().enumerate() {
        for x in 0..w {
            for c in 0..4 {
                let sum: f32 = weights
                    .iter()
                    .enumerate()
                    .map(|(k, weight)| weight * rows[(((first + k as u32) * w + x) * 4) as usize + c])
                    .sum();
                out[((y as u32 * w + x) * 4) as usize + c] = sum.round().clamp(0.0, 255.0) as u8;
            }
        }
    }
    (out, w, h)
}

/// A scene image as a texture: BC7 where it is a Basis Universal KTX2 image, the device
/// samples BC, its size is whole 4x4 blocks (as BC textures must be) and the file holds
/// the whole mip chain (a BC7 texture cannot have the renderer make the rest); else
/// RGBA8. Returns the view and whether it is BC7.
pub fn upload_scene_image(device: &wgpu::Device, queue: &wgpu::Queue, image: &Image) -> (wgpu::TextureView, bool) {
    let blocks_whole = image.width.is_multiple_of(4) && image.height.is_multiple_of(4);
    if device.features().contains(wgpu::Features::TEXTURE_COMPRESSION_BC) && blocks_whole {
        match image.bc7_levels() {
            Some(Ok(levels)) if levels.len() == full_mip_chain(image.width, image.height) as usize => {
                return (upload_bc7(device, queue, image, levels), true);
            }
            // It transcoded to RGBA8 when the file loaded; that serves.
            Some(Err(e)) => tracing::warn!("{}: BC7: {e}; uploaded as RGBA8", image.name),
            _ => {}
        }
    }
    (upload_image(device, queue, image), false)
}

/// Mip levels from `width` x `height` down to 1 x 1.
fn full_mip_chain(width: u32, height: u32) -> u32 {
    32 - width.max(height).max(1).leading_zeros()
}

/// A texture of the file's BC7 levels (`Image::bc7_levels`), as many mips as it stores.
fn upload_bc7(device: &wgpu::Device, queue: &wgpu::Queue, image: &Image, levels: &[Vec<u8>]) -> wgpu::TextureView {
    let format = match image.color_space {
        ColorSpace::Srgb => wgpu::TextureFormat::Bc7RgbaUnormSrgb,
        ColorSpace::Linear => wgpu::TextureFormat::Bc7RgbaUnorm,
    };
    let texture = device.create_texture(&wgpu::TextureDescriptor {
        label: Some(&image.name),
        size: wgpu::Extent3d { width: image.width, height: image.height, depth_or_array_layers: 1 },
        mip_level_count: levels.len() as u32,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    });
    for (level, blocks) in levels.iter().enumerate() {
        // A level smaller than a block still fills one: copies cover whole blocks.
        let (w, h) = ((image.width >> level).max(1), (image.height >> level).max(1));
        let (across, down) = (w.div_ceil(4), h.div_ceil(4));
        queue.write_texture(
            wgpu::TexelCopyTextureInfo {
                texture: &texture,
                mip_level: level as u32,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::All,
            },
            blocks,
            wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(across * 16), rows_per_image: Some(down) },
            wgpu::Extent3d { width: across * 4, height: down * 4, depth_or_array_layers: 1 },
        );
    }
    texture.create_view(&wgpu::TextureViewDescriptor::default())
}

pub fn upload_image(device: &wgpu::Device, queue: &wgpu::Queue, image: &Image) -> wgpu::TextureView {
    let format = match image.color_space {
        ColorSpace::Srgb => wgpu::TextureFormat::Rgba8UnormSrgb,
        ColorSpace::Linear => wgpu::TextureFormat::Rgba8Unorm,
    };
    let mip_level_count = full_mip_chain(image.width, image.height);
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
            // The file's own level where it has one (KTX2), else made from the last.
            let (next_w, next_h) = ((w / 2).max(1), (h / 2).max(1));
            match image.file_mips.get(level as usize - 1) {
                Some(stored) if stored.len() == (next_w * next_h * 4) as usize => {
                    (data, w, h) = (stored.clone(), next_w, next_h);
                }
                _ => (data, w, h) = downsample(&data, w, h),
            }
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

/// An RGBA8 (linear) texture array of `layers`, each `width` x `height` texels already,
/// with box-filtered mip chains, seen as `dimension` (2D array or cube array): the cookie
/// arrays and the materials' extension arrays.
pub fn upload_rgba8_layers(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    label: &str,
    (width, height): (u32, u32),
    layers: Vec<Vec<u8>>,
    dimension: wgpu::TextureViewDimension,
) -> wgpu::TextureView {
    let mip_level_count = full_mip_chain(width, height);
    let texture = device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d { width, height, depth_or_array_layers: layers.len() as u32 },
        mip_level_count,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: wgpu::TextureFormat::Rgba8Unorm,
        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    });
    for (layer, rgba8) in layers.into_iter().enumerate() {
        debug_assert_eq!(rgba8.len(), (width * height * 4) as usize, "layer {layer} of {label}");
        let (mut data, mut w, mut h) = (rgba8, width, height);
        for level in 0..mip_level_count {
            if level > 0 {
                (data, w, h) = downsample(&data, w, h);
            }
            queue.write_texture(
                wgpu::TexelCopyTextureInfo {
                    texture: &texture,
                    mip_level: level,
                    origin: wgpu::Origin3d { x: 0, y: 0, z: layer as u32 },
                    aspect: wgpu::TextureAspect::All,
                },
                &data,
                wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(w * 4), rows_per_image: Some(h) },
                wgpu::Extent3d { width: w, height: h, depth_or_array_layers: 1 },
            );
        }
    }
    texture.create_view(&wgpu::TextureViewDescriptor { dimension: Some(dimension), ..Default::default() })
}

/// A 1x1 texture of one colour, standing in for a texture a material does not have.
pub fn solid(device: &wgpu::Device, queue: &wgpu::Queue, name: &str, rgba: [u8; 4]) -> wgpu::TextureView {
    upload_image(
        device,
        queue,
        &Image {
            name: name.into(),
            width: 1,
            height: 1,
            rgba8: rgba.to_vec(),
            file_mips: Vec::new(),
            basis_source: None,
            color_space: ColorSpace::Linear,
        },
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

    fn grey(values: &[u8]) -> Vec<u8> {
        values.iter().flat_map(|&v| [v, v, v, 255]).collect()
    }

    #[test]
    fn even_sizes_average_two_by_two_blocks() {
        let (out, w, h) = downsample(&grey(&[0, 100, 200, 255]), 2, 2);
        assert_eq!((w, h), (1, 1));
        assert_eq!(out, vec![139, 139, 139, 255]); // (0 + 100 + 200 + 255) / 4 = 138.75
        let (out, w, h) = downsample(&grey(&[0, 40, 100, 200, 8, 40, 100, 200]), 4, 2);
        assert_eq!((w, h), (2, 1));
        assert_eq!(out, [grey(&[22]), grey(&[150])].concat());
    }

    #[test]
    fn odd_sizes_keep_their_last_column_and_row() {
        // A 3-wide ramp: the last column counts as much as the others.
        let (out, w, h) = downsample(&grey(&[0, 90, 180]), 3, 1);
        assert_eq!((w, h), (1, 1));
        assert_eq!(out, grey(&[90]));
        // 5 wide: output texels cover 2.5 texels each.
        let (out, _, _) = downsample(&grey(&[0, 0, 100, 200, 200]), 5, 1);
        assert_eq!(out, grey(&[20, 180]));
        // 1x3 column: the bottom row is not lost either.
        let (out, w, h) = downsample(&grey(&[30, 60, 255]), 1, 3);
        assert_eq!((w, h), (1, 1));
        assert_eq!(out, grey(&[115]));
    }

    #[test]
    fn box_weights_cover_every_source_texel_once() {
        for (from, to) in [(2, 1), (3, 1), (5, 2), (7, 3), (1024, 512), (1, 1)] {
            let mut coverage = vec![0f32; from as usize];
            for (first, weights) in box_weights(from, to) {
                assert!(((weights.iter().sum::<f32>()) - 1.0).abs() < 1e-5, "{from} -> {to}");
                for (k, w) in weights.iter().enumerate() {
                    coverage[first as usize + k] += w * from as f32 / to as f32;
                }
            }
            assert!(coverage.iter().all(|c| (c - 1.0).abs() < 1e-5), "{from} -> {to}: {coverage:?}");
        }
    }
}
