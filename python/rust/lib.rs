//! `fogbank._native`: the Python package's bindings, a thin layer over the
//! `fogbank` library crate (as the command line is). The Python modules in
//! `python/fogbank/` give these functions their documented signatures,
//! the `Image` type and progress bars.

// A `#[pyfunction]`'s parameters are its Python keyword arguments (as
// Mitsuba's `mi.render(scene, params, spp=, seed=, ...)`); grouping them
// into Rust records would change the Python API, so the lint is off for
// the bindings alone.
#![allow(clippy::too_many_arguments)]

mod errors;
mod grid;
mod images;
mod rays;
mod render;
mod scene;
mod study;
mod values;
mod watch;

use pyo3::prelude::*;

#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_class::<scene::Scene>()?;
    m.add_class::<scene::Medium>()?;
    m.add_class::<grid::Grid>()?;
    m.add_class::<render::Part>()?;
    m.add_class::<render::Frames>()?;
    m.add_function(wrap_pyfunction!(scene::load, m)?)?;
    m.add_function(wrap_pyfunction!(scene::load_dict, m)?)?;
    m.add_function(wrap_pyfunction!(scene::default_scene, m)?)?;
    m.add_function(wrap_pyfunction!(grid::read_volume, m)?)?;
    m.add_function(wrap_pyfunction!(render::render, m)?)?;
    m.add_function(wrap_pyfunction!(render::render_frames, m)?)?;
    m.add_function(wrap_pyfunction!(render::merge, m)?)?;
    m.add_function(wrap_pyfunction!(rays::transmittance, m)?)?;
    m.add_function(wrap_pyfunction!(rays::sample_distance, m)?)?;
    m.add_function(wrap_pyfunction!(rays::estimators, m)?)?;
    m.add_function(wrap_pyfunction!(study::stats, m)?)?;
    m.add_function(wrap_pyfunction!(study::converge, m)?)?;
    m.add_function(wrap_pyfunction!(study::experiment, m)?)?;
    m.add_function(wrap_pyfunction!(images::read_image, m)?)?;
    m.add_function(wrap_pyfunction!(images::write_image, m)?)?;
    m.add_function(wrap_pyfunction!(images::png_bytes, m)?)?;
    m.add_function(wrap_pyfunction!(images::compare, m)?)?;
    m.add_function(wrap_pyfunction!(panic_for_tests, m)?)?;
    Ok(())
}

/// Panics inside Rust, for the test that a panic is a `RuntimeError`
/// rather than the interpreter's end.
#[pyfunction]
fn panic_for_tests() -> PyResult<()> {
    errors::guarded(|| panic!("a deliberate panic (fogbank._native.panic_for_tests)"))
}
