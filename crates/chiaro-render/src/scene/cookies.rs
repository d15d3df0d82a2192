//! Light cookies on the GPU: every directional and spot cookie a layer of one 2D array,
//! every point cookie a cube of one cube array (layers as `plan::cookies::cookie_slots`
//! numbers them), Rgba8Unorm so that the stored values are read as they are, each with
//! a full mip chain. An array's layers share one size, so a cookie of another size is
//! resampled to the largest; with no cookie of a kind, a 1x1 white stand-in is bound.

use super::textures::upload_rgba8_layers;
use crate::plan::cookies::{CookieArray, cookie_slots};
use chiaro_scene::{Image, Scene};

/// The cookie arrays bound in group 0.
pub struct CookieTextures {
    /// Directional and spot cookies: layers of a 2D array.
    pub flat: wgpu::TextureView,
    /// Point cookies: cubes of a cube array.
    pub cube: wgpu::TextureView,
}

/// One RGBA8 picture of `width` x `height` texels.
#[derive(Clone, Debug, PartialEq)]
pub struct Texels {
    /// Width in texels.
    pub width: u32,
    /// Height in texels.
    pub height: u32,
    /// Four bytes per texel, row-major.
    pub rgba8: Vec<u8>,
}

impl Texels {
    fn white() -> Texels {
        Texels { width: 1, height: 1, rgba8: vec![255; 4] }
    }

    /// The texels of columns `x0 .. x0 + width` of `image`.
    fn crop(image: &Image, x0: u32, width: u32) -> Texels {
        let mut rgba8 = Vec::with_capacity((width * image.height * 4) as usize);
        for y in 0..image.height {
            let row = ((y * image.width + x0) * 4) as usize;
            rgba8.extend_from_slice(&image.rgba8[row..row + (width * 4) as usize]);
        }
        Texels { width, height: image.height, rgba8 }
    }

    /// Bilinear resampling to `width` x `height`, texel centres to texel centres, edges
    /// clamped.
    pub fn resized(&self, width: u32, height: u32) -> Texels {
        if (width, height) == (self.width, self.height) {
            return self.clone();
        }
        let fetch = |x: i64, y: i64, c: usize| {
            let x = x.clamp(0, self.width as i64 - 1) as u32;
            let y = y.clamp(0, self.height as i64 - 1) as u32;
            self.rgba8[((y * self.width + x) * 4) as usize + c] as f32
        };
        let mut rgba8 = Vec::with_capacity((width * height * 4) as usize);
        for y in 0..height {
            let sy = (y as f32 + 0.5) * self.height as f32 / height as f32 - 0.5;
            let (y0, fy) = (sy.floor() as i64, sy - sy.floor());
            for x in 0..width {
                let sx = (x as f32 + 0.5) * self.width as f32 / width as f32 - 0.5;
                let (x0, fx) = (sx.floor() as i64, sx - sx.floor());
                for c in 0..4 {
                    let top = fetch(x0, y0, c) * (1.0 - fx) + fetch(x0 + 1, y0, c) * fx;
                    let bottom = fetch(x0, y0 + 1, c) * (1.0 - fx) + fetch(x0 + 1, y0 + 1, c) * fx;
                    rgba8.push((top * (1.0 - fy) + bottom * fy).round().clamp(0.0, 255.0) as u8);
                }
            }
        }
        Texels { width, height, rgba8 }
    }
}

/// The layers of each array: flat cookies whole, point cookies as six faces each.
pub fn cookie_layers(scene: &Scene) -> (Vec<Texels>, Vec<Texels>) {
    let (mut flat, mut cube) = (Vec::new(), Vec::new());
    for (light, slot) in scene.lights.iter().zip(cookie_slots(scene)) {
        let (Some(cookie), Some((array, _))) = (light.cookie, slot) else { continue };
        let image = &scene.images[cookie.image];
        match array {
            CookieArray::Flat => flat.push(Texels::crop(image, 0, image.width)),
            CookieArray::Cube => {
                let face = image.height;
                cube.extend((0..6).map(|k| Texels::crop(image, k * face, face)));
            }
        }
    }
    (flat, cube)
}

impl CookieTextures {
    /// Uploads every cookie of `scene` with its mip chain (white stand-ins where none).
    pub fn upload(device: &wgpu::Device, queue: &wgpu::Queue, scene: &Scene) -> CookieTextures {
        let (mut flat, mut cube) = cookie_layers(scene);
        if flat.is_empty() {
            flat.push(Texels::white());
        }
        if cube.is_empty() {
            cube.extend((0..6).map(|_| Texels::white()));
        }
        CookieTextures {
            flat: upload_array(device, queue, "flat cookies", &flat, wgpu::TextureViewDimension::D2Array),
            cube: upload_array(device, queue, "cube cookies", &cube, wgpu::TextureViewDimension::CubeArray),
        }
    }
}

fn upload_array(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    label: &str,
    layers: &[Texels],
    dimension: wgpu::TextureViewDimension,
) -> wgpu::TextureView {
    let width = layers.iter().map(|l| l.width).max().unwrap_or(1);
    let height = layers.iter().map(|l| l.height).max().unwrap_or(1);
    let (width, height) = if dimension == wgpu::TextureViewDimension::CubeArray {
        (width.max(height), width.max(height))
    } else {
        (width, height)
    };
    let resized = layers.iter().map(|texels| texels.resized(width, height).rgba8).collect();
    upload_rgba8_layers(device, queue, label, (width, height), resized, dimension)
}

#[cfg(test)]
mod tests {
    use super::*;
    use chiaro_scene::{ColorSpace, Cookie, Light, LightKind};
    use glam::{Vec2, Vec3};

    fn grey(width: u32, height: u32, values: &[u8]) -> Texels {
        Texels { width, height, rgba8: values.iter().flat_map(|&v| [v, v, v, 255]).collect() }
    }

    #[test]
    fn resampling_keeps_the_same_size_and_interpolates_between_texel_centres() {
        let ramp = grey(2, 1, &[0, 200]);
        assert_eq!(ramp.resized(2, 1), ramp);
        // Four texels across two: centres at -0.25, 0.25, 0.75, 1.25 source texels.
        assert_eq!(ramp.resized(4, 1), grey(4, 1, &[0, 50, 150, 200]));
        assert_eq!(grey(4, 1, &[0, 100, 100, 200]).resized(2, 1), grey(2, 1, &[50, 150]));
    }

    #[test]
    fn point_cookies_split_into_six_faces_in_order() {
        // A 12x2 strip: face k is filled with 10 k.
        let rgba8 = (0..2).flat_map(|_| (0..12).flat_map(|x| [(x / 2 * 10) as u8, 0, 0, 255])).collect();
        let image = Image {
            name: "strip".into(),
            width: 12,
            height: 2,
            rgba8,
            file_mips: Vec::new(),
            basis_source: None,
            color_space: ColorSpace::Linear,
        };
        let cookie = Some(Cookie { image: 0, size_m: Vec2::ONE });
        let scene = Scene {
            images: vec![image],
            lights: vec![Light { cookie, ..Light::new(LightKind::Point, Vec3::ZERO, Vec3::NEG_Y) }],
            ..Scene::default()
        };
        let (flat, cube) = cookie_layers(&scene);
        assert!(flat.is_empty());
        assert_eq!(cube.len(), 6);
        for (k, face) in cube.iter().enumerate() {
            assert_eq!((face.width, face.height), (2, 2));
            assert!(face.rgba8.chunks_exact(4).all(|t| t[0] == 10 * k as u8), "face {k}");
        }
    }
}
