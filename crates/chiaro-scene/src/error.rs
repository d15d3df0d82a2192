//! The one error type of scene loading: every failure names the file and the problem.

use std::path::PathBuf;

#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    #[error("{path}: cannot read file: {source}")]
    Io { path: PathBuf, source: std::io::Error },
    #[error("{path}: not a valid glTF file: {message}")]
    Parse { path: PathBuf, message: String },
    #[error("{path}: requires glTF extension `{extension}`, which Chiaro does not support")]
    UnsupportedExtension { path: PathBuf, extension: String },
    #[error("{path}: {message}")]
    Invalid { path: PathBuf, message: String },
}
