//! The bake directory's atlas images: a lightmap (RGB irradiance in lux, A the texel's
//! coverage) or a shadow mask (four channels' visibility) as an RGBA float32 EXR. Texels
//! flow out to a file and back; the header is checked before the pixels are read.

use super::BakeDirError;
use chiaro_scene::baked::Lightmap;
use std::path::Path;

/// Writes `width` x `height` texels of four channels to `path`.
pub fn write_exr(path: &Path, width: u32, height: u32, texels: &[[f32; 4]]) -> Result<(), BakeDirError> {
    use exr::prelude::*;
    let w = width as usize;
    let pixels = SpecificChannels::rgba(|p: Vec2<usize>| {
        let t = texels[p.1 * w + p.0];
        (t[0], t[1], t[2], t[3])
    });
    Image::from_channels((w, height as usize), pixels)
        .write()
        .to_file(path)
        .map_err(|source| BakeDirError::Exr { path: path.to_path_buf(), source })
}

/// Reads an atlas of `size` x `size` texels; the header is checked first, so a file
/// cannot make the reader allocate more than that.
pub fn read_exr(path: &Path, size: u32) -> Result<Lightmap, BakeDirError> {
    use exr::prelude::*;
    let exr_error = |source| BakeDirError::Exr { path: path.to_path_buf(), source };
    let meta = exr::meta::MetaData::read_from_file(path, false).map_err(exr_error)?;
    let declared = meta.headers.first().map(|h| h.layer_size);
    if declared.is_none_or(|s| s.width() != size as usize || s.height() != size as usize) {
        return Err(BakeDirError::AtlasSize { path: path.to_path_buf(), size });
    }
    let image = read_first_rgba_layer_from_file(
        path,
        |resolution, _| (resolution.width(), vec![[0.0f32; 4]; resolution.width() * resolution.height()]),
        |(width, texels), position, (r, g, b, a): (f32, f32, f32, f32)| {
            texels[position.y() * *width + position.x()] = [r, g, b, a];
        },
    )
    .map_err(exr_error)?;
    let size = image.layer_data.size;
    let (_, texels) = image.layer_data.channel_data.pixels;
    Ok(Lightmap { width: size.width() as u32, height: size.height() as u32, texels })
}
