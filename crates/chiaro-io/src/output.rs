//! The files a command writes. Before any work, every output path is checked: none may be
//! an input of the command (the scene file, the buffers and images it reads, the settings
//! file), none may be a folder, and each one's folder must take a new file. Afterwards they
//! are written as a group: each to a temporary file beside its target, and only when all
//! are complete is each renamed into place, so a failure leaves no half-written image and
//! no image of a render whose other outputs failed.

use anyhow::{Context, Result, bail};
use std::path::{Path, PathBuf};

/// One image to write.
pub enum Encoded<'a> {
    /// RGBA8, encoded as PNG.
    Png { width: u32, height: u32, rgba8: &'a [u8] },
    /// Linear RGB, float32 OpenEXR.
    ExrRgb { width: u32, height: u32, rgb: &'a [[f32; 3]] },
    /// One float32 channel named `Y`.
    ExrSingle { width: u32, height: u32, values: &'a [f32] },
    /// One uint32 channel named `Y` (ids, exact).
    ExrU32 { width: u32, height: u32, values: &'a [u32] },
}

impl Encoded<'_> {
    /// Encodes the image into `path` directly (no temporary file): for callers that make
    /// a whole folder atomic themselves, as `chiaro batch` does.
    pub fn write(&self, path: &Path) -> Result<()> {
        use exr::prelude::*;
        match self {
            Encoded::Png { width, height, rgba8 } => image::save_buffer_with_format(
                path,
                rgba8,
                *width,
                *height,
                image::ExtendedColorType::Rgba8,
                image::ImageFormat::Png,
            )?,
            Encoded::ExrRgb { width, height, rgb } => {
                let w = *width as usize;
                let pixels = SpecificChannels::rgb(|p: Vec2<usize>| {
                    let c = rgb[p.1 * w + p.0];
                    (c[0], c[1], c[2])
                });
                Image::from_encoded_channels((w, *height as usize), ORDERED_EXR, pixels).write().to_file(path)?
            }
            Encoded::ExrSingle { width, height, values } => {
                let w = *width as usize;
                let pixels = SpecificChannels::build()
                    .with_channel("Y")
                    .with_pixel_fn(|p: Vec2<usize>| (values[p.1 * w + p.0],));
                Image::from_encoded_channels((w, *height as usize), ORDERED_EXR, pixels).write().to_file(path)?
            }
            Encoded::ExrU32 { width, height, values } => {
                let w = *width as usize;
                let pixels = SpecificChannels::build()
                    .with_channel("Y")
                    .with_pixel_fn(|p: Vec2<usize>| (values[p.1 * w + p.0],));
                Image::from_encoded_channels((w, *height as usize), ORDERED_EXR, pixels).write().to_file(path)?
            }
        }
        Ok(())
    }
}

/// exr's default encoding (RLE in 64x64 tiles) with its blocks written in increasing
/// order: with the default unspecified order, blocks compressed in parallel land in the
/// file as they finish, so the same pixels gave different bytes from run to run, and a
/// rerun of a job could not be told equal to the first by its bytes.
const ORDERED_EXR: exr::prelude::Encoding =
    exr::prelude::Encoding { line_order: exr::prelude::LineOrder::Increasing, ..exr::prelude::Encoding::FAST_LOSSLESS };

/// The folder a path's file goes in.
fn folder_of(path: &Path) -> &Path {
    match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    }
}

/// Whether two paths name the same file (the same inode where the platform says so).
fn same_file(a: &Path, b: &Path) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        if let (Ok(a), Ok(b)) = (std::fs::metadata(a), std::fs::metadata(b)) {
            return a.dev() == b.dev() && a.ino() == b.ino();
        }
    }
    matches!((a.canonicalize(), b.canonicalize()), (Ok(a), Ok(b)) if a == b)
}

/// What a command reads, so that no output replaces it.
pub struct Inputs {
    files: Vec<(PathBuf, &'static str)>,
}

impl Inputs {
    /// The scene's files (the document, then what it reads) and the settings file.
    pub fn new(scene_files: &[PathBuf], settings: Option<&Path>) -> Inputs {
        let mut files: Vec<(PathBuf, &'static str)> = scene_files
            .iter()
            .enumerate()
            .map(|(i, f)| (f.clone(), if i == 0 { "the scene file" } else { "a file the scene reads" }))
            .collect();
        files.extend(settings.map(|s| (s.to_path_buf(), "the settings file")));
        Inputs { files }
    }

    /// Whether `path` is one of the inputs.
    pub fn contains(&self, path: &Path) -> bool {
        self.files.iter().any(|(input, _)| same_file(path, input))
    }

    /// An input that lies inside the folder `dir`, at any depth.
    pub fn inside(&self, dir: &Path) -> Option<&Path> {
        let dir = dir.canonicalize().ok()?;
        self.files
            .iter()
            .map(|(input, _)| input.as_path())
            .find(|input| input.canonicalize().is_ok_and(|p| p.starts_with(&dir)))
    }
}

/// Checks, before any work, that each of `outputs` can be written and replaces no input.
pub fn check_outputs(outputs: &[PathBuf], inputs: &Inputs) -> Result<()> {
    for out in outputs {
        if let Ok(meta) = std::fs::metadata(out) {
            if meta.is_dir() {
                bail!("{}: is a folder, not a file to write", out.display());
            }
            if let Some((input, what)) = inputs.files.iter().find(|(input, _)| same_file(out, input)) {
                bail!(
                    "{}: is {what} ({}), an input of this command; choose another output path",
                    out.display(),
                    input.display()
                );
            }
        }
        let folder = folder_of(out);
        match std::fs::metadata(folder) {
            Ok(meta) if meta.is_dir() => {}
            Ok(_) => bail!("{}: cannot write there: {} is not a folder", out.display(), folder.display()),
            Err(e) => bail!("{}: cannot write there: folder {}: {e}", out.display(), folder.display()),
        }
        tempfile::Builder::new()
            .prefix(".chiaro-check-")
            .tempfile_in(folder)
            .with_context(|| format!("{}: cannot write in folder {}", out.display(), folder.display()))?;
    }
    Ok(())
}

/// Writes every file of the group or none: all to temporary files first, then each
/// renamed into place.
pub fn write_group(files: Vec<(PathBuf, Encoded<'_>)>) -> Result<()> {
    let files = files.into_iter().map(|(path, image)| (path, move |tmp: &Path| image.write(tmp))).collect();
    write_group_with(files, "image")
}

/// Writes `bytes` to `path` whole or not at all, as `write_group` writes images.
pub fn write_file(path: &Path, bytes: &[u8]) -> Result<()> {
    write_group_with(vec![(path.to_path_buf(), |tmp: &Path| Ok(std::fs::write(tmp, bytes)?))], "file")
}

/// `write_group` with any writer (of a `what`, for the messages).
fn write_group_with<W: FnOnce(&Path) -> Result<()>>(files: Vec<(PathBuf, W)>, what: &str) -> Result<()> {
    let mut written = Vec::with_capacity(files.len());
    for (path, write) in files {
        let folder = folder_of(&path);
        let tmp = tempfile::Builder::new()
            .prefix(".chiaro-")
            .suffix(".tmp")
            .tempfile_in(folder)
            .with_context(|| format!("{}: cannot create a file in {}", path.display(), folder.display()))?;
        write(tmp.path()).with_context(|| format!("{}: cannot write {what}", path.display()))?;
        // Temporary files are private (0600); a finished file is an ordinary one.
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt;
            std::fs::set_permissions(tmp.path(), std::fs::Permissions::from_mode(0o644))
                .with_context(|| format!("{}: cannot set permissions", path.display()))?;
        }
        written.push((path, tmp));
    }
    for (path, tmp) in written {
        tmp.persist(&path)
            .with_context(|| format!("{}: cannot move the finished {what} into place", path.display()))?;
    }
    Ok(())
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

impl OutputFormat {
    /// A frame's image as this format stores it: the tone-mapped RGBA8 image for PNG, the
    /// linear radiance for EXR.
    pub fn frame_image<'a>(self, width: u32, height: u32, ldr: &'a [u8], rgb: &'a [[f32; 3]]) -> Encoded<'a> {
        match self {
            OutputFormat::Png => Encoded::Png { width, height, rgba8: ldr },
            OutputFormat::Exr => Encoded::ExrRgb { width, height, rgb },
        }
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

/// An atlas's depths as grey RGBA8 (shared with the viewers' atlas view).
pub use chiaro_render::debug_images::atlas_grey;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_same_pixels_give_the_same_exr_bytes_every_time() {
        // Sixteen 64x64 tiles, compressed in parallel, each different.
        let (width, height) = (256u32, 256u32);
        let values: Vec<f32> = (0..width * height).map(|i| ((i * 7919) % 1013) as f32 * 0.37).collect();
        let dir = tempfile::tempdir().unwrap();
        let bytes: Vec<Vec<u8>> = (0..6)
            .map(|i| {
                let path = dir.path().join(format!("{i}.exr"));
                Encoded::ExrSingle { width, height, values: &values }.write(&path).unwrap();
                std::fs::read(path).unwrap()
            })
            .collect();
        assert!(bytes.iter().all(|b| *b == bytes[0]), "a rerun of a job must be able to compare files by their bytes");
    }

    #[test]
    fn a_failing_file_leaves_the_whole_group_unwritten() {
        let dir = tempfile::tempdir().unwrap();
        let main = dir.path().join("main.png");
        std::fs::write(&main, b"the previous image").unwrap();
        let aov = dir.path().join("main.depth.exr");
        type Writer = Box<dyn FnOnce(&Path) -> Result<()>>;
        let writers: Vec<(PathBuf, Writer)> = vec![
            (main.clone(), Box::new(|tmp: &Path| Ok(std::fs::write(tmp, b"new image")?))),
            (aov.clone(), Box::new(|_: &Path| bail!("no space left on device"))),
        ];
        let e = write_group_with(writers, "image").unwrap_err();
        assert!(format!("{e:#}").contains("main.depth.exr: cannot write image: no space left"), "{e:#}");
        assert_eq!(std::fs::read(&main).unwrap(), b"the previous image");
        assert!(!aov.exists());
        let leftovers = std::fs::read_dir(dir.path()).unwrap().count();
        assert_eq!(leftovers, 1, "no temporary files stay behind");
    }

    #[test]
    fn outputs_that_are_inputs_or_folders_or_homeless_are_refused() {
        let dir = tempfile::tempdir().unwrap();
        let scene = dir.path().join("s.png");
        std::fs::write(&scene, b"{}").unwrap();
        let texture = dir.path().join("tex.png");
        std::fs::write(&texture, b"png").unwrap();
        let inputs = Inputs::new(&[scene.clone(), texture.clone()], None);
        let message = |out: PathBuf| format!("{:#}", check_outputs(&[out], &inputs).unwrap_err());
        assert!(message(scene.clone()).contains("s.png: is the scene file"), "{}", message(scene.clone()));
        // The same file by another name is still the texture.
        let other_name = dir.path().join(".").join("tex.png");
        assert!(message(other_name).contains("is a file the scene reads"));
        assert!(message(dir.path().to_path_buf()).contains("is a folder"));
        let homeless = dir.path().join("no-such-folder").join("out.png");
        let m = message(homeless);
        assert!(
            m.contains("no-such-folder/out.png: cannot write there: folder") && m.contains("no-such-folder"),
            "{m}"
        );
        assert!(check_outputs(&[dir.path().join("new.png")], &inputs).is_ok());
    }
}
