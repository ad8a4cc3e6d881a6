//! `fogbank.read_image`, `fogbank.write_image`, `fogbank.compare` and the
//! PNG a notebook shows: images as the command reads and writes them (EXR
//! with a `variance` layer, PNG tone-mapped) and its metrics.

use crate::errors::{guarded, invalid, runtime, to_py};
use fogbank::compare::ZTEST_ALPHA;
use fogbank::compare::{compare as compare_images, parse_metrics, CompareOptions, Outcome};
use fogbank::image::{encode_png, read_image as read, Image, ToneCurve, ToneMapping};
use numpy::{PyArray1, PyArrayMethods, PyReadonlyArray3, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict};
use std::path::PathBuf;

/// H×W×3 float32 pixels of an array-like (`what` names it in errors).
fn pixels(a: &Bound<'_, PyAny>, what: &str) -> PyResult<(u32, u32, Vec<[f32; 3]>)> {
    let np = a.py().import("numpy")?;
    let a = np
        .call_method1("ascontiguousarray", (a, "float32"))
        .map_err(|e| invalid(format!("{what}: {e}")))?;
    let arr: PyReadonlyArray3<f32> = a.extract().map_err(|_| {
        invalid(format!(
            "{what}: expected an H×W×3 array, got shape {}",
            a.getattr("shape")
                .map(|s| s.to_string())
                .unwrap_or_default()
        ))
    })?;
    let s = arr.shape();
    if s[2] != 3 {
        return Err(invalid(format!(
            "{what}: expected an H×W×3 array, got shape ({}, {}, {})",
            s[0], s[1], s[2]
        )));
    }
    let v = arr
        .as_slice()
        .map_err(|e| invalid(format!("{what}: {e}")))?;
    Ok((
        s[1] as u32,
        s[0] as u32,
        v.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect(),
    ))
}

fn tone(exposure: f32, tonemap: &str) -> PyResult<ToneMapping> {
    if !exposure.is_finite() {
        return Err(invalid("exposure must be finite"));
    }
    Ok(ToneMapping {
        exposure,
        curve: ToneCurve::parse(tonemap).map_err(|e| invalid(format!("tonemap: {e}")))?,
    })
}

/// Writes `mean` (H×W×3) to `path`: EXR (linear, with `variance` as a
/// layer when given) or PNG (tone-mapped), as `fogbank render` writes them.
/// Non-finite pixels are written as 0.
#[pyfunction]
#[pyo3(signature = (path, mean, variance=None, exposure=0.0, tonemap="linear"))]
pub fn write_image(
    py: Python<'_>,
    path: PathBuf,
    mean: &Bound<'_, PyAny>,
    variance: Option<&Bound<'_, PyAny>>,
    exposure: f32,
    tonemap: &str,
) -> PyResult<()> {
    let (w, h, mut rgb) = pixels(mean, "mean")?;
    rgb.iter_mut().for_each(|p| {
        p.iter_mut().for_each(|c| {
            if !c.is_finite() {
                *c = 0.0
            }
        })
    });
    let var = match variance {
        Some(v) => {
            let (vw, vh, v) = pixels(v, "variance")?;
            if (vw, vh) != (w, h) {
                return Err(invalid(format!(
                    "variance: {vh}×{vw}, the image is {h}×{w}"
                )));
            }
            Some(v)
        }
        None => None,
    };
    let tone = tone(exposure, tonemap)?;
    match path.extension().and_then(|e| e.to_str()) {
        Some("exr") | Some("png") => {}
        _ => {
            return Err(invalid(format!(
                "{}: output must end in .exr or .png",
                path.display()
            )))
        }
    }
    guarded(|| {
        py.detach(|| fogbank::output::write_image(&path, w, h, &rgb, var.as_deref(), &tone))
            .map_err(to_py)
    })
}

/// The PNG `write_image` writes, as bytes (for a notebook's display).
#[pyfunction]
#[pyo3(signature = (mean, exposure=0.0, tonemap="linear"))]
pub fn png_bytes<'py>(
    py: Python<'py>,
    mean: &Bound<'py, PyAny>,
    exposure: f32,
    tonemap: &str,
) -> PyResult<Bound<'py, PyBytes>> {
    let (w, h, rgb) = pixels(mean, "mean")?;
    let tone = tone(exposure, tonemap)?;
    let bytes = py
        .detach(|| encode_png(w, h, &rgb, &tone))
        .map_err(runtime)?;
    Ok(PyBytes::new(py, &bytes))
}

/// Reads an EXR or PNG: a dict with `mean` (H×W×3 float32) and `variance`
/// (or None).
#[pyfunction]
pub fn read_image<'py>(py: Python<'py>, path: PathBuf) -> PyResult<Bound<'py, PyDict>> {
    if !path.exists() {
        return Err(pyo3::exceptions::PyFileNotFoundError::new_err(format!(
            "{}: no such file",
            path.display()
        )));
    }
    let img = guarded(|| {
        py.detach(|| read(&path))
            .map_err(|e| invalid(format!("{}: {e}", path.display())))
    })?;
    image_dict(py, &img)
}

fn image_dict<'py>(py: Python<'py>, img: &Image) -> PyResult<Bound<'py, PyDict>> {
    let arr = |v: &[[f32; 3]]| -> PyResult<Bound<'py, PyAny>> {
        let flat: Vec<f32> = v.iter().flatten().copied().collect();
        Ok(PyArray1::from_vec(py, flat)
            .reshape([img.height, img.width, 3])?
            .into_any())
    };
    let d = PyDict::new(py);
    d.set_item("mean", arr(&img.rgb)?)?;
    match &img.variance {
        Some(v) => d.set_item("variance", arr(v)?)?,
        None => d.set_item("variance", py.None())?,
    }
    Ok(d)
}

/// An image for a metric: a path, or (mean, variance-or-None).
fn image_of(a: &Bound<'_, PyAny>, what: &str) -> PyResult<Image> {
    if let Ok(p) = a.extract::<PathBuf>() {
        if !p.exists() {
            return Err(pyo3::exceptions::PyFileNotFoundError::new_err(format!(
                "{what}: {}: no such file",
                p.display()
            )));
        }
        return read(&p).map_err(|e| invalid(format!("{what}: {}: {e}", p.display())));
    }
    let (mean, variance): (Bound<'_, PyAny>, Option<Bound<'_, PyAny>>) = a.extract()?;
    let (w, h, rgb) = pixels(&mean, what)?;
    let variance = variance
        .map(|v| pixels(&v, &format!("{what} variance")).map(|x| x.2))
        .transpose()?;
    Ok(Image {
        width: w as usize,
        height: h as usize,
        rgb,
        variance,
        is_srgb8: false,
    })
}

/// Metrics of `test` against `reference` (paths or (mean, variance)
/// pairs); see `fogbank.compare`. Returns {metric: JSON text}.
#[pyfunction]
#[pyo3(signature = (reference, test, metrics, flip_mode="auto", ppd=None, tonemapper="aces", alpha=None))]
pub fn compare<'py>(
    py: Python<'py>,
    reference: &Bound<'py, PyAny>,
    test: &Bound<'py, PyAny>,
    metrics: Vec<String>,
    flip_mode: &str,
    ppd: Option<f32>,
    tonemapper: &str,
    alpha: Option<f64>,
) -> PyResult<Bound<'py, PyDict>> {
    let (wanted, explicit) = parse_metrics(&metrics).map_err(to_py)?;
    let opts = CompareOptions::new(flip_mode, ppd, tonemapper, alpha.unwrap_or(ZTEST_ALPHA))
        .map_err(to_py)?;
    let (r, t) = (image_of(reference, "reference")?, image_of(test, "test")?);
    let results = guarded(|| {
        py.detach(|| compare_images(&r, &t, &wanted, explicit, &opts))
            .map_err(to_py)
    })?;
    let d = PyDict::new(py);
    for (m, o) in results {
        let v = match o {
            Outcome::Scalar(x) => x.into_pyobject(py)?.into_any(),
            other => serde_json::to_string(&other.to_json())
                .map_err(runtime)?
                .into_pyobject(py)?
                .into_any(),
        };
        d.set_item(m.name(), v)?;
    }
    Ok(d)
}
