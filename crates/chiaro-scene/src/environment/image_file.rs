//! Environment images from disk: equirectangular Radiance `.hdr` or OpenEXR, checked
//! (regular file, 2:1, not too large, radiance finite and not negative) before use. The
//! size is read from the header, so a huge image is refused before it is decoded.

use super::{EnvironmentError, EnvironmentMap};
use glam::Vec3;
use std::path::Path;

/// The widest image accepted: 8192 x 4096 texels (384 MiB as 32-bit floats) is more than
/// the prefiltered cube can use.
pub const MAX_WIDTH: u32 = 8192;
/// The tallest image accepted.
pub const MAX_HEIGHT: u32 = MAX_WIDTH / 2;

type Reader = image::ImageReader<std::io::BufReader<std::fs::File>>;

/// An image whose header passed the checks.
struct CheckedImage {
    width: u32,
    height: u32,
    format: image::ImageFormat,
}

/// Checks what the header of the environment image at `path` says (a regular .hdr or
/// .exr file, 2:1, within the size limit) without decoding it: its width and height.
pub fn check_image(path: &Path) -> Result<(u32, u32), EnvironmentError> {
    check_header(path).map(|c| (c.width, c.height))
}

fn open(path: &Path, format: image::ImageFormat) -> Result<Reader, EnvironmentError> {
    let mut reader = image::ImageReader::open(path)
        .map_err(|e| EnvironmentError::Io { path: path.to_path_buf(), message: e.to_string() })?;
    reader.set_format(format);
    Ok(reader)
}

fn invalid(path: &Path, message: String) -> EnvironmentError {
    EnvironmentError::Invalid { path: path.to_path_buf(), message }
}

fn check_header(path: &Path) -> Result<CheckedImage, EnvironmentError> {
    let io = |message: String| EnvironmentError::Io { path: path.to_path_buf(), message };
    let kind = std::fs::metadata(path).map_err(|e| io(e.to_string()))?.file_type();
    if !kind.is_file() {
        return Err(io("not a regular file".into()));
    }
    let format = match path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase).as_deref() {
        Some("hdr") => image::ImageFormat::Hdr,
        Some("exr") => image::ImageFormat::OpenExr,
        _ => return Err(invalid(path, "not a .hdr or .exr image".into())),
    };
    let (width, height) =
        open(path, format)?.into_dimensions().map_err(|e| invalid(path, format!("not a readable image: {e}")))?;
    if width > MAX_WIDTH || height > MAX_HEIGHT {
        return Err(invalid(
            path,
            format!("{width} x {height} texels is larger than the {MAX_WIDTH} x {MAX_HEIGHT} an environment may be"),
        ));
    }
    if width != 2 * height || height == 0 {
        return Err(invalid(
            path,
            format!("{width} x {height} texels is not equirectangular (the width must be twice the height)"),
        ));
    }
    Ok(CheckedImage { width, height, format })
}

/// Reads and checks the environment image at `path`.
pub fn load_image(path: &Path) -> Result<EnvironmentMap, EnvironmentError> {
    let CheckedImage { width, height, format } = check_header(path)?;
    let image =
        open(path, format)?.decode().map_err(|e| invalid(path, format!("not a readable image: {e}")))?.into_rgb32f();
    let texels: Vec<Vec3> = image.pixels().map(|p| Vec3::from(p.0)).collect();
    if let Some(i) = texels.iter().position(|t| !t.is_finite() || t.min_element() < 0.0) {
        let (x, y) = (i as u32 % width, i as u32 / width);
        return Err(invalid(
            path,
            format!("texel ({x}, {y}) holds radiance {} (radiance must be finite and not negative)", texels[i]),
        ));
    }
    Ok(EnvironmentMap { width, height, texels })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::PathBuf;

    fn temp_dir() -> PathBuf {
        let dir = std::env::temp_dir().join(format!("chiaro-env-image-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    fn write_hdr(path: &Path, width: u32, height: u32, value: [f32; 3]) {
        let texels = vec![Vec3::from(value); (width * height) as usize];
        EnvironmentMap { width, height, texels }.write_hdr(path).unwrap();
    }

    fn write_exr(path: &Path, width: u32, height: u32, value: [f32; 3]) {
        let pixels: Vec<f32> = (0..width * height).flat_map(|_| value).collect();
        image::save_buffer(path, bytemuck::cast_slice(&pixels), width, height, image::ColorType::Rgb32F).unwrap();
    }

    fn message(path: &Path) -> String {
        load_image(path).unwrap_err().to_string()
    }

    #[test]
    fn hdr_and_exr_images_are_read_as_radiance() {
        let dir = temp_dir();
        let hdr = dir.join("half.hdr");
        write_hdr(&hdr, 16, 8, [0.5, 0.25, 2.0]);
        let map = load_image(&hdr).unwrap();
        assert_eq!((map.width, map.height, map.texels[77]), (16, 8, Vec3::new(0.5, 0.25, 2.0)));
        let exr = dir.join("bright.exr");
        write_exr(&exr, 8, 4, [3.0, 1e5, 0.125]);
        let map = load_image(&exr).unwrap();
        assert_eq!((map.width, map.height, map.texels[5]), (8, 4, Vec3::new(3.0, 1e5, 0.125)));
    }

    #[test]
    fn bad_images_are_refused_naming_the_file_and_the_problem() {
        let dir = temp_dir();
        let missing = dir.join("missing.hdr");
        assert!(message(&missing).starts_with(&format!("{}: cannot read environment image", missing.display())));
        let square = dir.join("square.hdr");
        write_hdr(&square, 8, 8, [1.0; 3]);
        assert!(message(&square).ends_with("8 x 8 texels is not equirectangular (the width must be twice the height)"));
        let negative = dir.join("negative.exr");
        write_exr(&negative, 8, 4, [1.0, -2.0, 1.0]);
        let e = message(&negative);
        assert!(e.starts_with(&negative.display().to_string()) && e.contains("texel (0, 0) holds radiance"), "{e}");
        let nan = dir.join("nan.exr");
        write_exr(&nan, 8, 4, [f32::NAN, 0.0, 0.0]);
        assert!(message(&nan).contains("must be finite and not negative"));
        let text = dir.join("text.hdr");
        std::fs::write(&text, "not an image").unwrap();
        assert!(message(&text).contains("not a readable image"), "{}", message(&text));
        let folder = dir.join("folder.hdr");
        std::fs::create_dir_all(&folder).unwrap();
        assert!(message(&folder).contains("not a regular file"));
    }

    #[test]
    fn a_huge_image_is_refused_from_its_header() {
        // A header claiming 20000 x 10000 texels over a few bytes: refused by its size, not
        // by running out of data (which would mean it was being decoded).
        let path = temp_dir().join("huge.hdr");
        std::fs::write(&path, "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 10000 +X 20000\n\u{1}\u{2}").unwrap();
        let e = message(&path);
        assert!(e.ends_with("20000 x 10000 texels is larger than the 8192 x 4096 an environment may be"), "{e}");
    }
}
