//! `fogbank.stats`, `fogbank.converge` and `fogbank.experiment`: the
//! command's studies (`fogbank::study`, `fogbank_experiments`) as
//! calls returning arrays and dicts, writing files only when asked.

use crate::errors::{guarded, invalid, runtime, to_py};
use crate::scene::Scene;
use crate::watch::watched;
use fogbank::study::{write_curves, write_stats, ConvergeJob, StatsJob, StatsReference};
use fogbank::Progress;
use numpy::{PyArray1, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::PathBuf;
use std::sync::Arc;

fn image_f64<'py>(py: Python<'py>, v: &[[f64; 3]], w: u32, h: u32) -> PyResult<Bound<'py, PyAny>> {
    let flat: Vec<f64> = v.iter().flatten().copied().collect();
    Ok(PyArray1::from_vec(py, flat)
        .reshape([h as usize, w as usize, 3])?
        .into_any())
}

/// Per-pixel statistics of `scene`'s estimator over `runs` 1-spp frames;
/// see `fogbank.stats`.
#[pyfunction]
#[pyo3(signature = (scene, estimator=None, runs=1024, seed=1, reference_estimator=None, reference=None, device="cpu", threads=None, out=None))]
pub fn stats<'py>(
    py: Python<'py>,
    scene: &Scene,
    estimator: Option<&str>,
    runs: u32,
    seed: u32,
    reference_estimator: Option<&str>,
    reference: Option<PathBuf>,
    device: &str,
    threads: Option<usize>,
    out: Option<PathBuf>,
) -> PyResult<Bound<'py, PyDict>> {
    let inner = match estimator {
        Some(e) => {
            let o = [format!("integrator.estimator={e}")];
            Arc::new(guarded(|| {
                py.detach(|| scene.rebuild(&o))
                    .map_err(crate::errors::scene_err)
            })?)
        }
        None => scene.inner.clone(),
    };
    let reference = match (reference_estimator, reference) {
        (Some(_), Some(_)) => {
            return Err(invalid("give reference_estimator or reference, not both"))
        }
        (Some(n), None) => Some(StatsReference::exact(n).map_err(to_py)?),
        (None, Some(p)) => Some(StatsReference::Image(p)),
        (None, None) => None,
    };
    let job = StatsJob {
        runs,
        seed,
        reference,
    };
    job.check().map_err(to_py)?;
    let renderer = crate::render::renderer(device, threads)?;
    let p = Progress::default();
    let w = watched(py, &p, None, || job.run(&renderer, &inner))?;
    if let Some(i) = w.interrupt {
        return Err(i);
    }
    let st = w.value.map_err(to_py)?;
    let summary = job.summary(&inner, &renderer, &st);
    if let Some(dir) = &out {
        guarded(|| {
            py.detach(|| {
                std::fs::create_dir_all(dir)
                    .map_err(|e| fogbank::Error::runtime(format!("{}: {e}", dir.display())))?;
                write_stats(&st, inner.integrator.estimator_name(), dir, &summary)
            })
            .map_err(to_py)
        })?;
    }
    let d = PyDict::new(py);
    d.set_item("mean", image_f64(py, &st.mean, st.width, st.height)?)?;
    let std: Vec<[f64; 3]> = st.variance.iter().map(|p| p.map(f64::sqrt)).collect();
    d.set_item("std", image_f64(py, &std, st.width, st.height)?)?;
    match st.bias() {
        Some(b) => d.set_item("bias", image_f64(py, &b, st.width, st.height)?)?,
        None => d.set_item("bias", py.None())?,
    }
    d.set_item(
        "count",
        PyArray1::from_vec(py, st.count.clone())
            .reshape([st.height as usize, st.width as usize])?,
    )?;
    d.set_item("summary", serde_json::to_string(&summary).map_err(runtime)?)?;
    Ok(d)
}

/// Equal-time MSE-versus-time curves; see `fogbank.converge`.
#[pyfunction]
#[pyo3(signature = (scene, estimators, seconds=10.0, reference_estimator="analytic_trilinear", seed=1, device="cpu", threads=None, out=None))]
pub fn converge<'py>(
    py: Python<'py>,
    scene: &Scene,
    estimators: Vec<String>,
    seconds: f64,
    reference_estimator: &str,
    seed: u32,
    device: &str,
    threads: Option<usize>,
    out: Option<PathBuf>,
) -> PyResult<Bound<'py, PyDict>> {
    let job = ConvergeJob {
        estimators,
        seconds,
        reference: reference_estimator.to_string(),
        seed,
    };
    job.check().map_err(to_py)?;
    let renderer = crate::render::renderer(device, threads)?;
    let p = Progress::default();
    let w = watched(py, &p, None, || {
        let load = |extra: &[String]| -> Result<fogbank::Scene, fogbank::Error> {
            let o: Vec<String> = ConvergeJob::overrides(&[])
                .into_iter()
                .chain(extra.iter().cloned())
                .collect();
            Ok(scene.rebuild(&o)?)
        };
        job.run(&renderer, &load, &mut |_| {})
    })?;
    if let Some(i) = w.interrupt {
        return Err(i);
    }
    let curves = w.value.map_err(to_py)?;
    if let Some(dir) = &out {
        guarded(|| {
            py.detach(|| {
                std::fs::create_dir_all(dir)
                    .map_err(|e| fogbank::Error::runtime(format!("{}: {e}", dir.display())))?;
                write_curves(&curves, dir)
            })
            .map_err(to_py)
        })?;
    }
    let d = PyDict::new(py);
    for c in &curves {
        let cols = PyDict::new(py);
        cols.set_item("spp", c.points.iter().map(|p| p.spp).collect::<Vec<_>>())?;
        cols.set_item(
            "seconds",
            c.points.iter().map(|p| p.seconds).collect::<Vec<_>>(),
        )?;
        cols.set_item("mse", c.points.iter().map(|p| p.mse).collect::<Vec<_>>())?;
        d.set_item(&c.label, cols)?;
    }
    Ok(d)
}

/// Runs one of the papers' experiments into `out`; see
/// `fogbank.experiment`. Returns (summary, files, seconds).
#[pyfunction]
#[pyo3(signature = (name, out=None, trials=None))]
pub fn experiment(
    py: Python<'_>,
    name: &str,
    out: Option<PathBuf>,
    trials: Option<u64>,
) -> PyResult<(String, Vec<PathBuf>, f64)> {
    if !fogbank_experiments::names().contains(&name) {
        return Err(invalid(format!(
            "experiment `{name}`: not one of {}",
            fogbank_experiments::names().join(", ")
        )));
    }
    let out = out.unwrap_or_else(|| PathBuf::from("experiments").join(name));
    let p = Arc::new(Progress::default());
    let w = watched(py, &p, None, || {
        fogbank_experiments::run(name, &out, trials)
    })?;
    if let Some(i) = w.interrupt {
        return Err(i);
    }
    let r = w.value.map_err(runtime)?;
    Ok((r.summary, r.files, r.seconds))
}
