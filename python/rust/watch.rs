//! Long work with the interpreter free: the work runs on a helper thread
//! without the GIL (other Python threads run, two renders run side by side)
//! while the calling thread wakes every 100 ms to let Python handle
//! signals — Ctrl-C sets `Progress::cancel`, so a render stops within its
//! pass and keeps what it accumulated — and to report progress to a Python
//! callable. Python runs signal handlers on its main thread only: a render
//! started from another thread is stopped by its own `Progress` only.

use crate::errors::panic_err;
use fogbank::Progress;
use pyo3::prelude::*;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::atomic::Ordering;
use std::sync::{Arc, Condvar, Mutex};
use std::time::Duration;

/// What a watched run ended with: its value, and the `KeyboardInterrupt`
/// that stopped it, if one did.
pub struct Watched<T> {
    pub value: T,
    pub interrupt: Option<PyErr>,
}

/// Runs `work` off the GIL, calling `report(samples_done)` from this thread
/// every 100 ms (and once at the end) when given.
pub fn watched<T: Send>(
    py: Python<'_>,
    progress: &Progress,
    report: Option<&Bound<'_, PyAny>>,
    work: impl FnOnce() -> T + Send,
) -> PyResult<Watched<T>> {
    let done = Arc::new((Mutex::new(false), Condvar::new()));
    let mut interrupt = None;
    let outcome = std::thread::scope(|s| -> PyResult<_> {
        let signal = done.clone();
        let worker = s.spawn(move || {
            let r = catch_unwind(AssertUnwindSafe(work));
            let (flag, cv) = &*signal;
            *flag.lock().unwrap_or_else(|e| e.into_inner()) = true;
            cv.notify_all();
            r
        });
        loop {
            let finished = py.detach(|| {
                let (flag, cv) = &*done;
                let guard = flag.lock().unwrap_or_else(|e| e.into_inner());
                let (guard, _) = cv
                    .wait_timeout_while(guard, Duration::from_millis(100), |d| !*d)
                    .unwrap_or_else(|e| e.into_inner());
                *guard
            });
            if interrupt.is_none() {
                if let Err(e) = py.check_signals() {
                    progress.cancel.store(true, Ordering::SeqCst);
                    interrupt = Some(e);
                }
            }
            if let Some(r) = report {
                // A failing progress callable must not lose the render.
                let _ = r.call1((progress.samples_done.load(Ordering::Relaxed),));
            }
            if finished {
                break;
            }
        }
        Ok(py.detach(|| worker.join()))
    })?;
    match outcome {
        Ok(Ok(value)) => Ok(Watched { value, interrupt }),
        Ok(Err(payload)) | Err(payload) => Err(panic_err(payload.as_ref())),
    }
}
