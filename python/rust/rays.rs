//! `fogbank.transmittance`, `fogbank.sample_distance` and
//! `fogbank.estimators`: estimators on the caller's own rays (see
//! `fogbank::rays`), the medium a scene's (`scene.media[i]`, with its
//! transform, σ_t scale and filter) or a bare `Grid`.

use crate::errors::{invalid, to_py};
use crate::grid::Grid;
use crate::scene::Medium;
use crate::watch::watched;
use fogbank::rays::{
    sample_distance_on_rays, transmittance_on_rays, FlightSampler, Medium as VolumeMedium,
    OptionValue, Options, Rays,
};
use fogbank::{Estimator, Progress, Renderer};
use numpy::{PyArray1, PyArrayMethods, PyReadonlyArray1, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::sync::Arc;

/// The scene medium `medium` stands for: a scene's, or a grid's in a scene
/// of its own (`sigma_t_scale`, `filter` as a medium's keys).
fn medium_of(
    py: Python<'_>,
    medium: &Bound<'_, PyAny>,
    grid_keys: &mut Vec<(String, String)>,
) -> PyResult<(Arc<fogbank::Scene>, usize)> {
    if let Ok(m) = medium.cast::<Medium>() {
        if !grid_keys.is_empty() {
            return Err(invalid(format!(
                "{}: a scene's medium has its own σ_t scale and filter; set them on the scene",
                grid_keys
                    .iter()
                    .map(|(k, _)| k.as_str())
                    .collect::<Vec<_>>()
                    .join(", ")
            )));
        }
        return Ok((m.get().scene.clone(), m.get().index));
    }
    let Ok(g) = medium.cast::<Grid>() else {
        return Err(pyo3::exceptions::PyTypeError::new_err(
            "medium: expected a scene's medium (scene.media[i]) or a fogbank.Grid",
        ));
    };
    let mut text = format!("[[media]]\ndensity = {{ array = \"{}\" }}\n", g.get().name);
    for (k, v) in grid_keys.drain(..) {
        text.push_str(&format!("{k} = {v}\n"));
    }
    let scene = py
        .detach(|| {
            let desc = fogbank::parse_scene(&text, "medium", &[])?;
            fogbank::Scene::build(desc, std::path::Path::new("."))
        })
        .map_err(crate::errors::scene_err)?;
    Ok((Arc::new(scene), 0))
}

/// Estimator options from keyword arguments (`samples=`, `roulette=`, …).
fn estimator_of(
    name: &str,
    options: Option<&Bound<'_, PyDict>>,
    grid_keys: &mut Vec<(String, String)>,
) -> PyResult<Estimator> {
    let mut o = Options::default();
    let takes = Estimator::option_keys(name).unwrap_or(&[]);
    if let Some(d) = options {
        for (k, v) in d.iter() {
            let k: String = k.extract()?;
            let key = k.clone();
            let bad = |what: &str| invalid(format!("{key}: expected {what}"));
            match k.as_str() {
                "sigma_t_scale" => grid_keys.push((k, v.extract::<f64>().map_err(|_| bad("a number"))?.to_string())),
                "filter" => grid_keys.push((k, format!("{:?}", v.extract::<String>().map_err(|_| bad("a string"))?))),
                key if takes.contains(&key) => o.set(key, option_value(&v).map_err(|_| bad("a number, True or False, or a string"))?),
                other => {
                    return Err(invalid(format!(
                        "{other}: not an option of {name} (its options: {}; for a Grid also sigma_t_scale, filter)",
                        Some(takes.join(", ")).filter(|s| !s.is_empty()).unwrap_or_else(|| "none".into())
                    )))
                }
            }
        }
    }
    Estimator::with_options(name, &o).map_err(|e| invalid(format!("estimator: {e}")))
}

/// A Python option value as the estimators read it (a bool before an int:
/// Python's `True` is an int too).
fn option_value(v: &Bound<'_, PyAny>) -> PyResult<OptionValue> {
    if let Ok(b) = v.cast::<pyo3::types::PyBool>() {
        return Ok(OptionValue::Bool(b.is_true()));
    }
    if let Ok(i) = v.extract::<i64>() {
        return Ok(OptionValue::Int(i));
    }
    if let Ok(x) = v.extract::<f64>() {
        return Ok(OptionValue::Float(x));
    }
    Ok(OptionValue::Text(v.extract::<String>()?))
}

/// N×3 float32 rays and N t_max (a scalar t_max applies to all).
struct RayArrays {
    o: Vec<[f32; 3]>,
    d: Vec<[f32; 3]>,
    t: Vec<f32>,
}

/// Runs `work` on the caller's rays through medium `index` of `scene` on
/// the CPU pool, with the GIL released and Ctrl-C watched (an interrupt
/// raises `KeyboardInterrupt`).
fn on_rays<T: Send>(
    py: Python<'_>,
    (scene, index): (Arc<fogbank::Scene>, usize),
    r: &RayArrays,
    threads: Option<usize>,
    work: impl FnOnce(&Renderer, &VolumeMedium, Rays, &Progress) -> Result<T, fogbank::Error> + Send,
) -> PyResult<T> {
    let renderer = crate::render::renderer("cpu", threads)?;
    let progress = Progress::default();
    let w = watched(py, &progress, None, || {
        let rays = Rays {
            origins: &r.o,
            directions: &r.d,
            t_max: &r.t,
        };
        work(&renderer, &scene.media[index].medium, rays, &progress)
    })?;
    if let Some(i) = w.interrupt {
        return Err(i);
    }
    w.value.map_err(to_py)
}

fn rays_of<'py>(
    origins: &Bound<'py, PyAny>,
    directions: &Bound<'py, PyAny>,
    t_max: &Bound<'py, PyAny>,
) -> PyResult<RayArrays> {
    let np = origins.py().import("numpy")?;
    let as_f32 = |a: &Bound<'py, PyAny>, what: &str| -> PyResult<Bound<'py, PyAny>> {
        np.call_method1("ascontiguousarray", (a, "float32"))
            .map_err(|e| invalid(format!("{what}: {e}")))
    };
    let n3 = |a: &Bound<'py, PyAny>, what: &str| -> PyResult<Vec<[f32; 3]>> {
        let a = as_f32(a, what)?;
        let arr: PyReadonlyArray2<f32> = a.extract().map_err(|_| {
            invalid(format!(
                "{what}: expected an N×3 array, got shape {}",
                a.getattr("shape")
                    .map(|s| s.to_string())
                    .unwrap_or_default()
            ))
        })?;
        let shape = arr.shape();
        if shape[1] != 3 {
            return Err(invalid(format!(
                "{what}: expected an N×3 array, got shape ({}, {})",
                shape[0], shape[1]
            )));
        }
        let s = arr
            .as_slice()
            .map_err(|e| invalid(format!("{what}: {e}")))?;
        Ok(s.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect())
    };
    let o = n3(origins, "origins")?;
    let d = n3(directions, "directions")?;
    // asarray, not ascontiguousarray, which makes a scalar 1-D.
    let t_arr = np
        .call_method1("asarray", (t_max, "float32"))
        .map_err(|e| invalid(format!("t_max: {e}")))?;
    let t = if t_arr.getattr("ndim")?.extract::<usize>()? == 0 {
        vec![t_arr.extract::<f32>()?; o.len()]
    } else {
        let a: PyReadonlyArray1<f32> = t_arr
            .extract()
            .map_err(|_| invalid("t_max: expected a number or an array of N"))?;
        a.as_slice()
            .map_err(|e| invalid(format!("t_max: {e}")))?
            .to_vec()
    };
    Ok(RayArrays { o, d, t })
}

/// N×K (or N when K = 1) array of `v`.
fn shaped<'py, T: numpy::Element>(
    py: Python<'py>,
    v: Vec<T>,
    n: usize,
    k: u32,
) -> PyResult<Bound<'py, PyAny>> {
    let a = PyArray1::from_vec(py, v);
    Ok(if k == 1 {
        a.into_any()
    } else {
        a.reshape([n, k as usize])?.into_any()
    })
}

/// Transmittance estimates along the caller's rays; see
/// `fogbank.transmittance`. Returns (estimates, lookups).
#[pyfunction]
#[pyo3(signature = (medium, origins, directions, t_max, estimator="jackknife", seed=0, per_ray=1, threads=None, **options))]
pub fn transmittance<'py>(
    py: Python<'py>,
    medium: &Bound<'py, PyAny>,
    origins: &Bound<'py, PyAny>,
    directions: &Bound<'py, PyAny>,
    t_max: &Bound<'py, PyAny>,
    estimator: &str,
    seed: u32,
    per_ray: u32,
    threads: Option<usize>,
    options: Option<&Bound<'py, PyDict>>,
) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyAny>)> {
    let mut grid_keys = Vec::new();
    let e = estimator_of(estimator, options, &mut grid_keys)?;
    let on = medium_of(py, medium, &mut grid_keys)?;
    let r = rays_of(origins, directions, t_max)?;
    let (t, n) = on_rays(py, on, &r, threads, |renderer, m, rays, progress| {
        transmittance_on_rays(renderer, m, e, rays, per_ray, seed, progress)
    })?;
    let rays = r.o.len();
    Ok((shaped(py, t, rays, per_ray)?, shaped(py, n, rays, per_ray)?))
}

/// Free-flight distances along the caller's rays; see
/// `fogbank.sample_distance`. Returns (t, weight, lookups).
#[pyfunction]
#[pyo3(signature = (medium, origins, directions, t_max, sampler="delta_tracking", seed=0, per_ray=1, threads=None, light=None, **options))]
pub fn sample_distance<'py>(
    py: Python<'py>,
    medium: &Bound<'py, PyAny>,
    origins: &Bound<'py, PyAny>,
    directions: &Bound<'py, PyAny>,
    t_max: &Bound<'py, PyAny>,
    sampler: &str,
    seed: u32,
    per_ray: u32,
    threads: Option<usize>,
    light: Option<[f32; 3]>,
    options: Option<&Bound<'py, PyDict>>,
) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyAny>, Bound<'py, PyAny>)> {
    let s = FlightSampler::parse(sampler, light).map_err(to_py)?;
    let mut grid_keys = Vec::new();
    if let Some(d) = options {
        for (k, v) in d.iter() {
            let k: String = k.extract()?;
            match k.as_str() {
                "sigma_t_scale" => grid_keys.push((k, v.extract::<f64>()?.to_string())),
                "filter" => grid_keys.push((k, format!("{:?}", v.extract::<String>()?))),
                other => return Err(invalid(format!("{other}: not an option of sample_distance (light, and for a Grid sigma_t_scale, filter)"))),
            }
        }
    }
    let on = medium_of(py, medium, &mut grid_keys)?;
    let r = rays_of(origins, directions, t_max)?;
    let f = on_rays(py, on, &r, threads, |renderer, m, rays, progress| {
        sample_distance_on_rays(renderer, m, s, rays, per_ray, seed, progress)
    })?;
    let n = r.o.len();
    Ok((
        shaped(py, f.t, n, per_ray)?,
        shaped(py, f.weight, n, per_ray)?,
        shaped(py, f.lookups, n, per_ray)?,
    ))
}

/// The transmittance estimators, as `fogbank estimators` lists them: name,
/// biased, description, options.
#[pyfunction]
pub fn estimators(py: Python<'_>) -> PyResult<Vec<Bound<'_, PyDict>>> {
    Estimator::all()
        .into_iter()
        .map(|e| {
            let d = PyDict::new(py);
            d.set_item("name", e.name())?;
            d.set_item("biased", e.biased())?;
            d.set_item("description", e.description())?;
            d.set_item("options", e.options_help())?;
            Ok(d)
        })
        .collect()
}
