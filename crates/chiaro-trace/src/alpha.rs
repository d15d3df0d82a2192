//! Base colour alpha on the CPU, as the renderer reads it: the material's factor times its
//! base colour texture's alpha at the texture's UV set and KHR_texture_transform, filtered
//! as its sampler says (bilinear or nearest, with its wrap modes) from the full-resolution
//! image. The GPU's passes sample mip levels too, which only softens alpha near edges.

use chiaro_scene::{AlphaMode, Image, Material, Scene, ShadowCasting, WrapMode};
use glam::{Vec2, Vec3};

/// One image's alpha channel.
#[derive(Clone, Debug)]
pub struct AlphaImage {
    width: u32,
    height: u32,
    alpha: Vec<u8>,
}

impl AlphaImage {
    pub fn new(image: &Image) -> AlphaImage {
        AlphaImage {
            width: image.width,
            height: image.height,
            alpha: image.rgba8.chunks_exact(4).map(|p| p[3]).collect(),
        }
    }

    fn texel(&self, x: i64, y: i64) -> f32 {
        let index = y as usize * self.width as usize + x as usize;
        self.alpha.get(index).map_or(1.0, |&a| f32::from(a) / 255.0)
    }
}

/// Where a texel coordinate lands for a wrap mode, on an axis of `size` texels.
fn wrap(coordinate: i64, size: u32, mode: WrapMode) -> i64 {
    let n = i64::from(size.max(1));
    match mode {
        WrapMode::Repeat => coordinate.rem_euclid(n),
        WrapMode::MirroredRepeat => {
            let period = coordinate.rem_euclid(2 * n);
            if period < n { period } else { 2 * n - 1 - period }
        }
        WrapMode::ClampToEdge => coordinate.clamp(0, n - 1),
    }
}

/// How a material's alpha is tested, for the triangles that need it.
#[derive(Clone, Debug)]
pub struct AlphaMaterial {
    pub alpha_mode: AlphaMode,
    pub cutoff: f32,
    pub casting: ShadowCasting,
    /// What a solid caster lets through per crossing (`Material::shadow_transmittance`):
    /// a coloured shadow; `None` for an ordinary one.
    pub transmittance: Option<Vec3>,
    factor: f32,
    /// Index into the images kept beside, the UV set, the transform's columns, and the
    /// sampler's wrap and filter.
    texture: Option<(usize, u32, [Vec2; 3], WrapMode, WrapMode, bool)>,
}

impl AlphaMaterial {
    /// Whether surfaces of `material` ever need their alpha or material: MASK for the
    /// camera, clipped or dithered for shadows, or letting light through (a solid caster
    /// with a shadow transmittance).
    pub fn needed(material: &Material) -> bool {
        material.alpha_mode == AlphaMode::Mask
            || matches!(material.shadow_casting, ShadowCasting::Clip | ShadowCasting::Dither)
            || (material.shadow_casting == ShadowCasting::On && material.shadow_transmittance().is_some())
    }

    pub fn new(material: &Material) -> AlphaMaterial {
        AlphaMaterial {
            alpha_mode: material.alpha_mode,
            cutoff: material.alpha_cutoff,
            casting: material.shadow_casting,
            transmittance: material.shadow_transmittance(),
            factor: material.base_color.w,
            texture: material.base_color_texture.map(|t| {
                (
                    t.image,
                    t.tex_coord.min(1),
                    t.transform.matrix(),
                    t.sampler.wrap_u,
                    t.sampler.wrap_v,
                    t.sampler.mag_linear,
                )
            }),
        }
    }

    /// The UV set its texture reads (0 without a texture).
    pub fn uv_set(&self) -> u32 {
        self.texture.map_or(0, |t| t.1)
    }

    /// Alpha at texture coordinates `uv` (of `uv_set`), before the transform.
    pub fn alpha(&self, images: &[AlphaImage], uv: Vec2) -> f32 {
        let Some((image, _, m, wrap_u, wrap_v, linear)) = self.texture else {
            return self.factor;
        };
        let Some(image) = images.get(image) else {
            return self.factor;
        };
        let uv = m[0] * uv.x + m[1] * uv.y + m[2];
        let texel = |x: i64, y: i64| image.texel(wrap(x, image.width, wrap_u), wrap(y, image.height, wrap_v));
        let p = uv * Vec2::new(image.width as f32, image.height as f32);
        let sampled = if linear {
            let p = p - 0.5;
            let (x0, y0) = (p.x.floor(), p.y.floor());
            let (fx, fy) = (p.x - x0, p.y - y0);
            let (x0, y0) = (x0 as i64, y0 as i64);
            let top = texel(x0, y0) * (1.0 - fx) + texel(x0 + 1, y0) * fx;
            let bottom = texel(x0, y0 + 1) * (1.0 - fx) + texel(x0 + 1, y0 + 1) * fx;
            top * (1.0 - fy) + bottom * fy
        } else {
            texel(p.x.floor() as i64, p.y.floor() as i64)
        };
        self.factor * sampled
    }
}

/// The alpha images of a scene (every image, alpha only; unused ones are empty).
pub fn alpha_images(scene: &Scene) -> Vec<AlphaImage> {
    let used: Vec<bool> = (0..scene.images.len())
        .map(|i| {
            scene
                .materials
                .iter()
                .any(|m| AlphaMaterial::needed(m) && m.base_color_texture.is_some_and(|t| t.image == i))
        })
        .collect();
    scene
        .images
        .iter()
        .zip(used)
        .map(
            |(image, used)| {
                if used { AlphaImage::new(image) } else { AlphaImage { width: 0, height: 0, alpha: Vec::new() } }
            },
        )
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use chiaro_scene::{ColorSpace, SamplerDesc, TextureRef, UvTransform};

    fn checker() -> Image {
        // 2x2: opaque top-left and bottom-right.
        let a = [255u8, 0, 0, 255];
        Image {
            name: "checker".into(),
            width: 2,
            height: 2,
            rgba8: [[255, 255, 255, a[0]], [255, 255, 255, a[1]], [255, 255, 255, a[2]], [255, 255, 255, a[3]]]
                .concat(),
            file_mips: Vec::new(),
            basis_source: None,
            color_space: ColorSpace::Srgb,
        }
    }

    fn material(linear: bool, transform: UvTransform) -> Material {
        Material {
            alpha_mode: AlphaMode::Mask,
            base_color: glam::Vec4::new(1.0, 1.0, 1.0, 0.8),
            base_color_texture: Some(TextureRef {
                image: 0,
                sampler: SamplerDesc { mag_linear: linear, ..SamplerDesc::default() },
                tex_coord: 0,
                transform,
            }),
            ..Material::default()
        }
    }

    #[test]
    fn nearest_and_bilinear_alpha_with_wrap_and_transform() {
        let images = vec![AlphaImage::new(&checker())];
        let nearest = AlphaMaterial::new(&material(false, UvTransform::default()));
        assert_eq!(nearest.alpha(&images, Vec2::new(0.25, 0.25)), 0.8);
        assert_eq!(nearest.alpha(&images, Vec2::new(0.75, 0.25)), 0.0);
        // Repeat: one tile over is the same.
        assert_eq!(nearest.alpha(&images, Vec2::new(1.25, -0.75)), 0.8);
        // Bilinear at a texel corner averages the four.
        let linear = AlphaMaterial::new(&material(true, UvTransform::default()));
        assert!((linear.alpha(&images, Vec2::new(0.5, 0.5)) - 0.4).abs() < 1e-6);
        assert!((linear.alpha(&images, Vec2::new(0.25, 0.25)) - 0.8).abs() < 1e-6);
        // A transform that doubles the tiling moves the second column to u = 0.375.
        let tiled =
            AlphaMaterial::new(&material(false, UvTransform { scale: Vec2::splat(2.0), ..UvTransform::default() }));
        assert_eq!(tiled.alpha(&images, Vec2::new(0.375, 0.125)), 0.0);
        assert_eq!(tiled.alpha(&images, Vec2::new(0.625, 0.125)), 0.8);
    }

    #[test]
    fn wrap_modes_fold_coordinates() {
        assert_eq!(wrap(-1, 4, WrapMode::Repeat), 3);
        assert_eq!(wrap(5, 4, WrapMode::MirroredRepeat), 2);
        assert_eq!(wrap(-1, 4, WrapMode::MirroredRepeat), 0);
        assert_eq!(wrap(9, 4, WrapMode::ClampToEdge), 3);
    }
}
