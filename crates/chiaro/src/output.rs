//! Image files, written atomically: each goes to a temporary file beside its target and
//! is renamed over it only when complete, so a failure never leaves half an image.

use anyhow::{Context, Result, bail};
use std::path::{Path, PathBuf};

/// Writes through `write` into a temporary file in `path`'s folder, then renames it.
fn write_atomically(path: &Path, write: impl FnOnce(&Path) -> Result<()>) -> Result<()> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let tmp = tempfile::Builder::new()
        .prefix(".chiaro-")
        .suffix(".tmp")
        .tempfile_in(dir)
        .with_context(|| format!("{}: cannot create a file in {}", path.display(), dir.display()))?;
    write(tmp.path()).with_context(|| format!("{}: cannot write image", path.display()))?;
    // Temporary files are private (0600); a finished image is an ordinary file.
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(tmp.path(), std::fs::Permissions::from_mode(0o644))
            .with_context(|| format!("{}: cannot set permissions", path.display()))?;
    }
    tmp.persist(path).with_context(|| format!("{}: cannot move the finished image into place", path.display()))?;
    Ok(())
}

pub fn write_png(path: &Path, width: u32, height: u32, rgba8: &[u8]) -> Result<()> {
    write_atomically(path, |tmp| {
        image::save_buffer_with_format(
            tmp,
            rgba8,
            width,
            height,
            image::ExtendedColorType::Rgba8,
            image::ImageFormat::Png,
        )?;
        Ok(())
    })
}

/// Linear RGB float32.
pub fn write_exr_rgb(path: &Path, width: u32, height: u32, rgb: &[[f32; 3]]) -> Result<()> {
    write_atomically(path, |tmp| {
        exr::prelude::write_rgb_file(tmp, width as usize, height as usize, |x, y| {
            let p = rgb[y * width as usize + x];
            (p[0], p[1], p[2])
        })?;
        Ok(())
    })
}

/// One float32 channel named `Y`.
pub fn write_exr_single(path: &Path, width: u32, height: u32, values: &[f32]) -> Result<()> {
    use exr::prelude::*;
    write_atomically(path, |tmp| {
        let pixels = SpecificChannels::build()
            .with_channel("Y")
            .with_pixel_fn(|p: Vec2<usize>| (values[p.1 * width as usize + p.0],));
        Image::from_channels((width as usize, height as usize), pixels).write().to_file(tmp)?;
        Ok(())
    })
}

/// The output kinds Chiaro writes, chosen by extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OutputFormat {
    Png,
    Exr,
}

pub fn output_format(path: &Path) -> Result<OutputFormat> {
    match path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase).as_deref() {
        Some("png") => Ok(OutputFormat::Png),
        Some("exr") => Ok(OutputFormat::Exr),
        other => bail!(
            "{}: unsupported output format {} (use .png or .exr)",
            path.display(),
            other.map(|e| format!("'.{e}'")).unwrap_or_else(|| "(no extension)".into())
        ),
    }
}

/// `<stem>.<kind>.exr` beside `output`.
pub fn aov_path(output: &Path, kind: &str) -> PathBuf {
    sibling_path(output, &format!("{kind}.exr"))
}

/// `<stem>.<suffix>` beside `output`.
pub fn sibling_path(output: &Path, suffix: &str) -> PathBuf {
    let stem = output.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_else(|| "chiaro".into());
    output.with_file_name(format!("{stem}.{suffix}"))
}
