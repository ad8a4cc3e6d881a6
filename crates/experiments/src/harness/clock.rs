//! Wall-clock time of one piece of work, the measure every experiment's
//! timing columns use.

use std::time::Instant;

/// `f`'s result and the wall-clock seconds it took.
pub fn clocked<T>(f: impl FnOnce() -> T) -> (T, f64) {
    let clock = Instant::now();
    let out = f();
    (out, clock.elapsed().as_secs_f64())
}
