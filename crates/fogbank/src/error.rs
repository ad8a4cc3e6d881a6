//! Errors of the library entry point, with a kind a front end maps to its
//! own (Python: `ValueError`, `FileNotFoundError`, `RuntimeError`) and the
//! message the command prints.

use std::fmt;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ErrorKind {
    /// Bad input: a scene key, an option, an argument.
    Invalid,
    /// A file that is not there.
    NotFound,
    /// Anything else (a device, an I/O failure while writing).
    Runtime,
    /// Stopped by `Progress::cancel` (Ctrl-C).
    Interrupted,
}

#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Error {
    pub kind: ErrorKind,
    pub message: String,
}

impl Error {
    pub fn invalid(message: impl Into<String>) -> Error {
        Error {
            kind: ErrorKind::Invalid,
            message: message.into(),
        }
    }

    /// A reader's message: `NotFound` when it ends in the OS's "No such
    /// file or directory" (the readers name the file first), else `Invalid`.
    pub fn from_message(message: String) -> Error {
        let kind = if message.contains("No such file or directory") {
            ErrorKind::NotFound
        } else {
            ErrorKind::Invalid
        };
        Error { kind, message }
    }

    pub fn runtime(message: impl Into<String>) -> Error {
        Error {
            kind: ErrorKind::Runtime,
            message: message.into(),
        }
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for Error {}

/// A scene that fails to load or build: a missing file is `NotFound`,
/// anything else `Invalid` ([`Error::from_message`]).
impl From<fogbank_render::SceneError> for Error {
    fn from(e: fogbank_render::SceneError) -> Error {
        Error::from_message(e.0)
    }
}

impl From<std::io::Error> for Error {
    fn from(e: std::io::Error) -> Error {
        Error::runtime(e.to_string())
    }
}
