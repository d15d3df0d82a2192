//! A material's KHR_materials_* textures as one RGBA8 texture array, each distinct image
//! a layer, resampled to the largest of their sizes: fourteen more textures per material
//! would overrun the 16 sampled textures a shader stage may bind (WebGPU's limit, which
//! the frame's group already nearly fills). The layers hold the files' bytes as they are;
//! the shader decodes the colour slots from sRGB. One sampler serves the array: the
//! first slot's (the slots' own wrap and filter modes are not kept apart).

use super::textures::upload_rgba8_layers;
use chiaro_scene::{LayerTexture, Material, SamplerDesc};

/// Side of the largest layer: bigger images are scaled down to it.
const MAX_LAYER_SIDE: u32 = 2048;

/// Which images a material's extension textures use, in layer order, and each slot's
/// layer (-1 where the material has no texture there).
#[derive(Clone, Debug, PartialEq)]
pub struct LayerPlan {
    /// `Scene::images` indices, one per layer.
    pub images: Vec<usize>,
    /// Each `LayerTexture` slot's layer, -1 where the material has no texture there.
    pub slots: [i32; LayerTexture::ALL.len()],
    /// The sampler the array is read with.
    pub sampler: SamplerDesc,
}

/// The layers material `m` needs; `image_count` bounds the image indices it may use.
pub fn layer_plan(m: &Material, image_count: usize) -> LayerPlan {
    let mut plan =
        LayerPlan { images: Vec::new(), slots: [-1; LayerTexture::ALL.len()], sampler: SamplerDesc::default() };
    for slot in LayerTexture::ALL {
        let Some(texture) = m.layers.texture(slot).filter(|t| t.image < image_count) else { continue };
        if plan.images.is_empty() {
            plan.sampler = texture.sampler;
        }
        let layer = match plan.images.iter().position(|&i| i == texture.image) {
            Some(layer) => layer,
            None => {
                plan.images.push(texture.image);
                plan.images.len() - 1
            }
        };
        plan.slots[slot.index()] = layer as i32;
    }
    plan
}

/// The array's size: the largest width and height among the images, at most
/// `MAX_LAYER_SIDE` on a side (at least 1).
pub fn array_size(sizes: &[(u32, u32)]) -> (u32, u32) {
    let width = sizes.iter().map(|s| s.0).max().unwrap_or(1).clamp(1, MAX_LAYER_SIDE);
    let height = sizes.iter().map(|s| s.1).max().unwrap_or(1).clamp(1, MAX_LAYER_SIDE);
    (width, height)
}

/// Uploads the images `plan` lists (from `images`) as a mipmapped texture array; a 1x1
/// white layer where the plan has none.
pub fn upload_layers(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    label: &str,
    plan: &LayerPlan,
    images: &[chiaro_scene::Image],
) -> wgpu::TextureView {
    let sources: Vec<&chiaro_scene::Image> = plan.images.iter().map(|&i| &images[i]).collect();
    let (width, height) = array_size(&sources.iter().map(|i| (i.width, i.height)).collect::<Vec<_>>());
    let layers: Vec<Vec<u8>> = if sources.is_empty() {
        vec![vec![255; 4]]
    } else {
        sources.iter().map(|image| resampled(image, width, height)).collect()
    };
    upload_rgba8_layers(device, queue, label, (width, height), layers, wgpu::TextureViewDimension::D2Array)
}

/// The image's RGBA8 texels at `width` x `height`: as they are where the size matches,
/// else resampled with a triangle (bilinear) filter.
fn resampled(image: &chiaro_scene::Image, width: u32, height: u32) -> Vec<u8> {
    if (image.width, image.height) == (width, height) {
        return image.rgba8.clone();
    }
    match image::RgbaImage::from_raw(image.width, image.height, image.rgba8.clone()) {
        Some(source) => {
            image::imageops::resize(&source, width, height, image::imageops::FilterType::Triangle).into_raw()
        }
        // A malformed image (never from the loader): white, the factors alone.
        None => vec![255; (width * height * 4) as usize],
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use chiaro_scene::{TextureRef, UvTransform, WrapMode};

    fn texture(image: usize, wrap: WrapMode) -> Option<TextureRef> {
        let sampler = SamplerDesc { wrap_u: wrap, ..SamplerDesc::default() };
        Some(TextureRef { image, sampler, tex_coord: 0, transform: UvTransform::default() })
    }

    #[test]
    fn each_distinct_image_is_one_layer_and_slots_point_at_theirs() {
        let mut m = Material::default();
        m.layers.textures[LayerTexture::Clearcoat.index()] = texture(4, WrapMode::ClampToEdge);
        m.layers.textures[LayerTexture::ClearcoatRoughness.index()] = texture(4, WrapMode::Repeat);
        m.layers.textures[LayerTexture::SheenColor.index()] = texture(1, WrapMode::Repeat);
        // An index past the images (a material nothing draws) is left out.
        m.layers.textures[LayerTexture::Anisotropy.index()] = texture(9, WrapMode::Repeat);
        let plan = layer_plan(&m, 5);
        assert_eq!(plan.images, vec![4, 1]);
        let mut expected = [-1; 14];
        expected[LayerTexture::Clearcoat.index()] = 0;
        expected[LayerTexture::ClearcoatRoughness.index()] = 0;
        expected[LayerTexture::SheenColor.index()] = 1;
        assert_eq!(plan.slots, expected);
        // The first slot's sampler serves the array.
        assert_eq!(plan.sampler.wrap_u, WrapMode::ClampToEdge);
        assert_eq!(layer_plan(&Material::default(), 5).images, Vec::<usize>::new());
    }

    #[test]
    fn the_array_takes_the_largest_sides_within_the_cap() {
        assert_eq!(array_size(&[(64, 16), (32, 128)]), (64, 128));
        assert_eq!(array_size(&[(8192, 4096)]), (2048, 2048));
        assert_eq!(array_size(&[]), (1, 1));
    }

    #[test]
    fn resampling_keeps_a_uniform_image_and_stretches_to_the_size() {
        let image = chiaro_scene::Image {
            name: "flat".into(),
            width: 2,
            height: 1,
            rgba8: [10, 20, 30, 40].repeat(2),
            file_mips: Vec::new(),
            basis_source: None,
            color_space: chiaro_scene::ColorSpace::Linear,
        };
        let out = resampled(&image, 4, 4);
        assert_eq!(out, [10, 20, 30, 40].repeat(16));
        assert_eq!(resampled(&image, 2, 1), image.rgba8);
    }
}
