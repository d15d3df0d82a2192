//! The colour space each glTF image is used in flows in, decoded RGBA8 [`Image`]s out:
//! only images a drawn material uses are decoded, each once (sRGB if it is colour
//! anywhere), and the materials' texture references are renumbered into `Scene::images`.
//! PNG, JPEG and WebP (EXT_texture_webp) are read, from a buffer view or a URI, and KTX2
//! (KHR_texture_basisu) for material textures, with the mip levels the file stores;
//! anything else names the image.

use super::{Loader, ktx2_image, object_label, uri};
use crate::error::SceneError;
use crate::types::{ColorSpace, Image, Light, LightKind, Material, Mesh};
use std::borrow::Cow;

/// An image's bytes, its MIME type if known, and its label for messages.
type ImageBytes<'a> = (Cow<'a, [u8]>, Option<String>, String);

/// The colour space each glTF image is sampled in by the materials the drawn meshes use;
/// `None` for images nothing drawn uses, which are not read.
pub(super) fn image_uses(
    materials: &[Material],
    meshes: &[Mesh],
    variant_materials: impl Iterator<Item = usize>,
) -> Vec<Option<ColorSpace>> {
    let mut drawn = vec![false; materials.len()];
    // Points and lines read their material's textures too.
    let primitive_materials = meshes.iter().flat_map(|m| m.drawn_parts()).filter_map(|(_, p)| p.material);
    for material in primitive_materials.chain(variant_materials) {
        if let Some(drawn) = drawn.get_mut(material) {
            *drawn = true;
        }
    }
    let mut uses: Vec<Option<ColorSpace>> = Vec::new();
    for material in materials.iter().zip(drawn).filter(|(_, drawn)| *drawn).map(|(m, _)| m) {
        for (texture, color_space) in material.textures_in_color_spaces() {
            if uses.len() <= texture.image {
                uses.resize(texture.image + 1, None);
            }
            let used = &mut uses[texture.image];
            if *used != Some(ColorSpace::Srgb) {
                *used = Some(color_space);
            }
        }
    }
    uses
}

impl Loader<'_> {
    /// Decodes each image a material or a light's cookie uses, once, and points the
    /// materials' texture references and the cookies at `Scene::images`. An image used as
    /// colour anywhere is sRGB (cookies read the stored values whatever it is marked).
    /// A cookie image that fails to decode, or a point light's cookie that is not six
    /// square faces side by side, is an error naming the light.
    pub(super) fn decode_images(
        &self,
        material_uses: &[Option<ColorSpace>],
        materials: &mut [Material],
        lights: &mut [Light],
    ) -> Result<Vec<Image>, SceneError> {
        let mut uses = material_uses.to_vec();
        uses.resize(self.root.images.len(), None);
        let mut cookie_user: Vec<Option<String>> = vec![None; uses.len()];
        for light in lights.iter() {
            if let Some(cookie) = light.cookie {
                uses[cookie.image].get_or_insert(ColorSpace::Linear);
                cookie_user[cookie.image].get_or_insert_with(|| format!("light '{}'", light.name));
            }
        }
        let mut images = Vec::new();
        let mut scene_index = vec![usize::MAX; uses.len()];
        for (index, color_space) in uses.iter().enumerate() {
            if let Some(color_space) = color_space {
                scene_index[index] = images.len();
                let decoded = self.decode_image(index, *color_space).map_err(|e| match &cookie_user[index] {
                    Some(light) if material_uses.get(index).copied().flatten().is_none() => {
                        e.in_context(&format!("{light}: extras.cookie"))
                    }
                    _ => e,
                })?;
                images.push(decoded);
            }
        }
        for light in lights.iter_mut() {
            if let Some(cookie) = &mut light.cookie {
                cookie.image = scene_index[cookie.image];
                let image = &images[cookie.image];
                if light.kind == LightKind::Point && image.width != 6 * image.height {
                    return Err(self.invalid(format!(
                        "light '{}': extras.cookie: a point light's cookie must be six square faces side by side \
                         (6:1), but its image is {}x{}",
                        light.name, image.width, image.height
                    )));
                }
            }
        }
        for material in materials {
            for texture in material.textures_mut().into_iter().flatten() {
                texture.image = scene_index[texture.image];
            }
            // A material nothing draws keeps no reference to images that were not read.
            for texture in material.textures_mut() {
                if texture.is_some_and(|t| t.image >= images.len()) {
                    *texture = None;
                }
            }
        }
        Ok(images)
    }

    fn decode_image(&self, index: usize, color_space: ColorSpace) -> Result<Image, SceneError> {
        let image = &self.root.images[index];
        let name = image
            .name
            .clone()
            .or_else(|| image.uri.clone().filter(|u| !u.starts_with("data:")))
            .unwrap_or_else(|| format!("image {index}"));
        let (bytes, mime, label) = self.image_bytes(index)?;
        if ktx2_image::is_ktx2(&bytes) || mime.as_deref() == Some("image/ktx2") {
            let levels = ktx2_image::decode(&bytes).map_err(|e| self.invalid(format!("{label}: {e}")))?;
            let mut rgba8 = levels.rgba8.into_iter();
            let base = rgba8.next().ok_or_else(|| self.invalid(format!("{label}: the KTX2 file has no levels")))?;
            return Ok(Image {
                name,
                width: levels.width,
                height: levels.height,
                rgba8: base,
                file_mips: rgba8.collect(),
                color_space,
                basis_source: levels.basis.then(|| std::sync::Arc::new(crate::types::BasisSource::new(bytes.to_vec()))),
            });
        }
        let rgba = self.pixels(&bytes, mime.as_deref(), &label, None)?.into_rgba8();
        Ok(Image {
            name,
            width: rgba.width(),
            height: rgba.height(),
            rgba8: rgba.into_raw(),
            file_mips: Vec::new(),
            color_space,
            basis_source: None,
        })
    }

    /// The pixels of image `index` as the file stores them (channels and bit depth kept),
    /// read from its buffer view or URI; an error names the image. An image wider or
    /// taller than `max_side` is refused from its header, before it is decoded.
    pub(super) fn decode_pixels(&self, index: usize, max_side: Option<u32>) -> Result<image::DynamicImage, SceneError> {
        let (bytes, mime, label) = self.image_bytes(index)?;
        self.pixels(&bytes, mime.as_deref(), &label, max_side)
    }

    /// Image `index`'s bytes, from its buffer view or URI, with its MIME type (the
    /// image's, else a data URI's) and its label for messages.
    fn image_bytes(&self, index: usize) -> Result<ImageBytes<'_>, SceneError> {
        let image = &self.root.images[index];
        let label = object_label("image", index, image.uri.as_deref(), image.name.as_deref());
        let (bytes, mime): (Cow<[u8]>, Option<String>) = match (&image.buffer_view, &image.uri) {
            (Some(view), _) => (
                Cow::Borrowed(self.view_bytes(view.value())?.0),
                image.mime_type.as_ref().map(|m| m.0.to_ascii_lowercase()),
            ),
            (None, Some(uri)) => {
                let data = uri::read_uri(self.base_dir, self.given_files, uri)
                    .map_err(|e| self.invalid(format!("{label}: {e}")))?;
                self.inputs.borrow_mut().extend(data.file.clone());
                let mime = image
                    .mime_type
                    .as_ref()
                    .map(|m| m.0.to_ascii_lowercase())
                    .or(data.mime.filter(|m| m.starts_with("image/")));
                (Cow::Owned(data.bytes), mime)
            }
            (None, None) => {
                return Err(self.invalid(format!("{label} has neither a uri nor a bufferView")));
            }
        };
        Ok((bytes, mime, label))
    }

    /// PNG, JPEG or WebP `bytes` decoded; `max_side` as for `decode_pixels`.
    fn pixels(
        &self,
        bytes: &[u8],
        mime: Option<&str>,
        label: &str,
        max_side: Option<u32>,
    ) -> Result<image::DynamicImage, SceneError> {
        if let Some(mime) = mime
            && !matches!(mime, "image/png" | "image/jpeg" | "image/jpg" | "image/webp")
        {
            return Err(
                self.invalid(format!("{label}: unsupported image format {mime}; Chiaro reads PNG, JPEG and WebP"))
            );
        }
        let format = match image::guess_format(bytes) {
            Ok(format @ (image::ImageFormat::Png | image::ImageFormat::Jpeg | image::ImageFormat::WebP)) => format,
            Ok(other) => {
                return Err(self.invalid(format!(
                    "{label}: unsupported image format ({other:?}); Chiaro reads PNG, JPEG and WebP"
                )));
            }
            Err(_) => {
                return Err(self.invalid(format!("{label}: unsupported image format; Chiaro reads PNG, JPEG and WebP")));
            }
        };
        let cannot_decode = |e: image::ImageError| self.invalid(format!("{label}: cannot decode: {e}"));
        if let Some(max_side) = max_side {
            let reader = image::ImageReader::with_format(std::io::Cursor::new(bytes), format);
            let (width, height) = reader.into_dimensions().map_err(cannot_decode)?;
            if width.max(height) > max_side {
                return Err(self.invalid(format!(
                    "{label} is {width} x {height}, larger than the {max_side} x {max_side} allowed here"
                )));
            }
        }
        image::load_from_memory_with_format(bytes, format).map_err(cannot_decode)
    }
}
