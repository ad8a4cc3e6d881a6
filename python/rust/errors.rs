//! fogbank's errors as Python exceptions: bad input `ValueError`, a missing
//! file `FileNotFoundError`, anything else `RuntimeError`, a stop by
//! Ctrl-C `KeyboardInterrupt`; each with the message the command prints.
//! A Rust panic (a bug) becomes a `RuntimeError` saying so, never an abort.

use fogbank::{Error, ErrorKind};
use pyo3::exceptions::{PyFileNotFoundError, PyKeyboardInterrupt, PyRuntimeError, PyValueError};
use pyo3::PyErr;
use std::panic::{catch_unwind, AssertUnwindSafe};

pub fn to_py(e: Error) -> PyErr {
    match e.kind {
        ErrorKind::Invalid => PyValueError::new_err(e.message),
        ErrorKind::NotFound => PyFileNotFoundError::new_err(e.message),
        ErrorKind::Runtime => PyRuntimeError::new_err(e.message),
        ErrorKind::Interrupted => PyKeyboardInterrupt::new_err(e.message),
    }
}

/// A scene error (key, file, line) as `ValueError` or `FileNotFoundError`.
pub fn scene_err(e: fogbank::SceneError) -> PyErr {
    to_py(Error::from(e))
}

/// Any other library error's message as `ValueError`.
pub fn invalid(e: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(e.to_string())
}

/// Any other library error's message as `RuntimeError`.
pub fn runtime(e: impl std::fmt::Display) -> PyErr {
    PyRuntimeError::new_err(e.to_string())
}

/// The message of a panic's payload.
pub fn panic_message(payload: &(dyn std::any::Any + Send)) -> String {
    payload
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "unknown panic".into())
}

/// A panic as the `RuntimeError` it is reported as.
pub fn panic_err(payload: &(dyn std::any::Any + Send)) -> PyErr {
    PyRuntimeError::new_err(format!(
        "fogbank internal error (a bug; please report it): {}",
        panic_message(payload)
    ))
}

/// Runs `f`, turning a panic into a `RuntimeError`.
pub fn guarded<T>(f: impl FnOnce() -> Result<T, PyErr>) -> Result<T, PyErr> {
    catch_unwind(AssertUnwindSafe(f)).unwrap_or_else(|p| Err(panic_err(p.as_ref())))
}
