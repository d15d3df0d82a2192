//! The one error type of scene loading: every failure names the file and the problem.

use std::path::PathBuf;

/// Why a scene could not be loaded; every variant names the file.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// The file could not be read.
    #[error("{path}: cannot read file: {source}")]
    Io {
        /// The file that failed.
        path: PathBuf,
        /// What the file system said.
        source: std::io::Error,
    },
    /// The file is not glTF the parser can read.
    #[error("{path}: not a valid glTF file: {message}")]
    Parse {
        /// The glTF file.
        path: PathBuf,
        /// The parser's message.
        message: String,
    },
    /// The file requires an extension Chiaro does not implement.
    #[error("{path}: requires glTF extension `{extension}`, which Chiaro does not support")]
    UnsupportedExtension {
        /// The glTF file.
        path: PathBuf,
        /// The extension's name, such as `EXT_lights_ies`.
        extension: String,
    },
    /// The file breaks the glTF specification or holds values Chiaro refuses.
    #[error("{path}: {message}")]
    Invalid {
        /// The glTF file.
        path: PathBuf,
        /// What is wrong, naming the JSON path or object where it can.
        message: String,
    },
}

impl SceneError {
    /// The error with `context` (what used the failing object, such as a JSON path) before
    /// an `Invalid` message; other kinds already say all they know.
    pub(crate) fn in_context(self, context: &str) -> SceneError {
        match self {
            SceneError::Invalid { path, message } => {
                SceneError::Invalid { path, message: format!("{context}: {message}") }
            }
            other => other,
        }
    }
}
