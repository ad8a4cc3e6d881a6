//! Errors of the volume layer. Every loader error names the file (and grid or
//! key) at fault, so a user can act on it without a debugger.

use std::fmt;
use std::path::{Path, PathBuf};

#[derive(Debug)]
pub enum VolumeError {
    /// The file could not be opened or read.
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    /// The file was read but its contents are malformed or unsupported.
    Format { path: PathBuf, message: String },
    /// A requested grid does not exist; `available` lists what does.
    GridNotFound {
        path: PathBuf,
        grid: String,
        available: Vec<String>,
    },
    /// Parameters given by the user (dims, sizes, options) are invalid.
    Invalid(String),
}

impl VolumeError {
    pub fn format(path: &Path, message: impl Into<String>) -> Self {
        VolumeError::Format {
            path: path.to_path_buf(),
            message: message.into(),
        }
    }
    pub fn io(path: &Path, source: std::io::Error) -> Self {
        VolumeError::Io {
            path: path.to_path_buf(),
            source,
        }
    }
}

impl fmt::Display for VolumeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            VolumeError::Io { path, source } => write!(f, "{}: {}", path.display(), source),
            VolumeError::Format { path, message } => write!(f, "{}: {}", path.display(), message),
            VolumeError::GridNotFound {
                path,
                grid,
                available,
            } => write!(
                f,
                "{}: no grid named `{}` (available: {})",
                path.display(),
                grid,
                if available.is_empty() {
                    "none".to_string()
                } else {
                    available.join(", ")
                }
            ),
            VolumeError::Invalid(m) => write!(f, "{m}"),
        }
    }
}

impl std::error::Error for VolumeError {}

pub type Result<T> = std::result::Result<T, VolumeError>;
