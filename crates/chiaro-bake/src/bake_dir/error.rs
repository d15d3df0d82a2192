//! The one error of reading and writing bake directories: each variant names the file
//! and says what is wrong with it, in the words users see in warnings and messages.

use super::FORMAT_VERSION;
use crate::bake::MAX_PROBES;
use crate::layout::MAX_ATLAS_SIZE;
use std::path::PathBuf;

/// Why a bake directory could not be written, or does not fit the scene it was read for.
#[derive(Debug, thiserror::Error)]
pub enum BakeDirError {
    /// The cancel flag was set before the bake was swapped in.
    #[error("interrupted; nothing was written")]
    Cancelled,
    /// A file or directory could not be read, written or renamed.
    #[error("{}: {source}", path.display())]
    Io { path: PathBuf, source: std::io::Error },
    /// An EXR atlas could not be read or written.
    #[error("{}: {source}", path.display())]
    Exr { path: PathBuf, source: exr::error::Error },
    /// The manifest could not be encoded (it is plain data, so this means a bug).
    #[error("{0}")]
    Encode(serde_json::Error),
    /// The manifest is not JSON of a bake manifest.
    #[error("{}: not a bake manifest: {source}", path.display())]
    NotAManifest { path: PathBuf, source: serde_json::Error },
    /// Another format version wrote the directory.
    #[error("{}: format version {found} (this Chiaro reads {FORMAT_VERSION}); bake again", path.display())]
    FormatVersion { path: PathBuf, found: u32 },
    /// The scene's files changed since the bake.
    #[error("{}: made for another version of the scene (its files' hash differs); bake again", path.display())]
    OtherScene { path: PathBuf },
    /// A mesh instance the manifest names is not the scene's.
    #[error("{}: instance {instance} ({name}) does not match the scene", path.display())]
    InstanceMismatch { path: PathBuf, instance: usize, name: String },
    /// A light the manifest names is not the scene's.
    #[error("{}: light {light} ({name}) does not match the scene", path.display())]
    LightMismatch { path: PathBuf, light: usize, name: String },
    /// A light's shadow mask channel does not exist.
    #[error("{}: light {name} has channel {channel}", path.display())]
    Channel { path: PathBuf, name: String, channel: u8 },
    /// More or larger atlases than a bake may have.
    #[error("{}: {count} atlases of {size} texels (at most {} of {MAX_ATLAS_SIZE})", path.display(), super::MAX_ATLASES)]
    Atlases { path: PathBuf, count: usize, size: u32 },
    /// Shadow masks that do not pair with the lightmaps.
    #[error("{}: {masks} shadow masks for {lightmaps} lightmaps", path.display())]
    MaskCount { path: PathBuf, masks: usize, lightmaps: usize },
    /// A probe grid too large, empty or with a spacing that is not positive.
    #[error(
        "{}: a probe grid of {counts:?} probes {spacing:?} m apart (1 to {MAX_PROBES} probes, positive spacing)",
        path.display()
    )]
    ProbeGrid { path: PathBuf, counts: [u32; 3], spacing: [f32; 3] },
    /// An EXR atlas of another size than the manifest's.
    #[error("{}: not {size}x{size} texels, as the manifest says", path.display())]
    AtlasSize { path: PathBuf, size: u32 },
    /// A binary file longer than the manifest accounts for, refused before it is read.
    #[error("{}: {len} bytes, more than the manifest accounts for ({limit})", path.display())]
    TooLong { path: PathBuf, len: u64, limit: usize },
    /// The lightmap coordinates hold another number of values than the manifest needs.
    #[error("{}: {found} values, the manifest needs {wanted}", path.display())]
    UvCount { path: PathBuf, found: usize, wanted: usize },
    /// A per-probe file of another length than the grid needs.
    #[error("{}: {found} bytes, {probes} probes need {wanted}", path.display())]
    ProbeBytes { path: PathBuf, found: usize, probes: usize, wanted: usize },
    /// The bake read back but could not be attached to the scene.
    #[error("{}: {message}", dir.display())]
    Apply { dir: PathBuf, message: String },
}

impl BakeDirError {
    /// The mapping of an I/O error at `path`.
    pub(crate) fn io(path: &std::path::Path) -> impl Fn(std::io::Error) -> BakeDirError + '_ {
        move |source| BakeDirError::Io { path: path.to_path_buf(), source }
    }
}
