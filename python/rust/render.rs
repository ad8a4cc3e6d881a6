//! `fogbank.render`, `fogbank.render_frames` and `fogbank.merge`: the
//! library's render job (`fogbank::RenderJob`) on a scene, with the GIL
//! released, Ctrl-C and progress watched (`watch`), and the film returned
//! as the arrays the command writes (mean with non-finite pixels as 0,
//! variance of the mean once every pixel has two samples).

use crate::errors::{guarded, invalid, runtime, to_py};
use crate::scene::Scene;
use crate::watch::watched;
use fogbank::frames::{parse_frames, FrameSequence};
use fogbank::output::{film_rgb, FilmImage};
use fogbank::partial::{Partial, PartialHeader};
use fogbank::stats::render_stats;
use fogbank::{Device, Progress, RenderJob, Renderer, Shard, ShardMode};
use numpy::{PyArray1, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::collections::HashMap;
use std::path::PathBuf;
use std::sync::{Arc, Mutex};

/// One worker pool per thread count and one GPU, opened once per process
/// (opening an adapter takes a second; a pool, thread start-up).
pub(crate) fn renderer(device: &str, threads: Option<usize>) -> PyResult<Arc<Renderer>> {
    type Cache = HashMap<(bool, usize), Arc<Renderer>>;
    static CACHE: Mutex<Option<Cache>> = Mutex::new(None);
    let device = Device::parse(device).map_err(|e| invalid(format!("device: {e}")))?;
    let threads =
        fogbank::renderer::threads_or_all(threads).map_err(|e| invalid(format!("threads: {e}")))?;
    let key = (device == Device::Gpu, threads);
    let mut cache = CACHE.lock().unwrap_or_else(|e| e.into_inner());
    let cache = cache.get_or_insert_with(HashMap::new);
    if let Some(r) = cache.get(&key) {
        return Ok(r.clone());
    }
    let r = Arc::new(Renderer::new(device, Some(threads)).map_err(to_py)?);
    cache.insert(key, r.clone());
    Ok(r)
}

/// H×W×3 float32 array of `rgb`.
fn image_array<'py>(
    py: Python<'py>,
    rgb: &[[f32; 3]],
    width: u32,
    height: u32,
) -> PyResult<Bound<'py, PyAny>> {
    let flat: Vec<f32> = rgb.iter().flatten().copied().collect();
    Ok(PyArray1::from_vec(py, flat)
        .reshape([height as usize, width as usize, 3])?
        .into_any())
}

/// The dict the Python `Image` is made from.
fn image_dict<'py>(
    py: Python<'py>,
    img: &FilmImage,
    scene: &fogbank::Scene,
    spp: u32,
) -> PyResult<Bound<'py, PyDict>> {
    let (w, h) = (scene.camera.width, scene.camera.height);
    let d = PyDict::new(py);
    d.set_item("mean", image_array(py, &img.rgb, w, h)?)?;
    match &img.variance {
        Some(v) => d.set_item("variance", image_array(py, v, w, h)?)?,
        None => d.set_item("variance", py.None())?,
    }
    d.set_item("spp", spp)?;
    d.set_item("exposure", scene.desc.render.exposure)?;
    d.set_item("tonemap", scene.desc.render.tonemap.name())?;
    Ok(d)
}

/// `I/N` with `samples` or `tiles`.
fn shard_of(shard: Option<&str>, mode: &str) -> PyResult<Option<Shard>> {
    let mode = ShardMode::parse(mode).map_err(|e| invalid(format!("shard_mode: {e}")))?;
    shard
        .map(|s| Shard::parse(s, mode).map_err(|e| invalid(format!("shard: {e}"))))
        .transpose()
}

/// A shard's part of a render, for `merge` and `save("….fbpart")`.
#[pyclass(module = "fogbank._native", frozen)]
pub struct Part {
    pub partial: Partial,
    name: String,
}

#[pymethods]
impl Part {
    /// Writes the part as a `.fbpart` file (`fogbank merge` reads it).
    fn save(&self, py: Python<'_>, path: PathBuf) -> PyResult<()> {
        guarded(|| py.detach(|| self.partial.write(&path)).map_err(runtime))
    }
    /// The shard, `I/N`.
    #[getter]
    fn shard(&self) -> String {
        self.name.clone()
    }
    fn __repr__(&self) -> String {
        format!("fogbank.Part(shard {})", self.name)
    }
}

/// Renders `scene`; see `fogbank.render` for the parameters. Returns the
/// dict the Python `Image` is made from.
#[pyfunction]
#[pyo3(signature = (scene, spp=None, seed=None, device="cpu", threads=None, time_budget=None, progress=None, shard=None, shard_mode="samples"))]
pub fn render<'py>(
    py: Python<'py>,
    scene: &Scene,
    spp: Option<u32>,
    seed: Option<u32>,
    device: &str,
    threads: Option<usize>,
    time_budget: Option<f64>,
    progress: Option<Bound<'py, PyAny>>,
    shard: Option<&str>,
    shard_mode: &str,
) -> PyResult<Bound<'py, PyDict>> {
    let job = RenderJob {
        spp,
        time_budget,
        shard: shard_of(shard, shard_mode)?,
    };
    if let Some(b) = time_budget {
        if !(b > 0.0 && b.is_finite()) {
            return Err(invalid("time_budget must be a positive number of seconds"));
        }
    }
    let scene = scene.with_seed(seed);
    job.check_shard(Device::parse(device).map_err(|e| invalid(format!("device: {e}")))?)
        .map_err(to_py)?;
    job.check_integrator(&scene).map_err(to_py)?;
    let r = renderer(device, threads)?;
    let p = Progress::default();
    let spp_asked = job.spp(&scene);
    let w = watched(py, &p, progress.as_ref(), || job.run(&r, &scene, &p, None))?;
    let rendered = w.value.map_err(to_py)?;
    let img = film_rgb(&rendered.film);
    let seed = scene.desc.render.seed;
    let stats = render_stats(&scene, &r, &rendered, spp_asked, seed, img.bad_pixels);
    let d = image_dict(py, &img, &scene, rendered.film.min_spp())?;
    d.set_item("stats", serde_json::to_string(&stats).map_err(runtime)?)?;
    d.set_item("interrupted", rendered.interrupted)?;
    d.set_item("keyboard_interrupt", w.interrupt.is_some())?;
    if let Some(s) = job.shard {
        let run = fogbank::shard_run::run(s, spp_asked, rendered.seconds, r.threads());
        let header =
            PartialHeader::for_shard("render", &scene, seed, spp_asked, &rendered.film, run);
        let part = Part {
            partial: Partial {
                header,
                film: rendered.film,
                covered: None,
            },
            name: s.label(),
        };
        d.set_item("part", Py::new(py, part)?)?;
    }
    Ok(d)
}

/// Merges shards' parts (`Part`s or `.fbpart` paths) as `fogbank merge`
/// does; returns the dict of the merged image (render parts only).
#[pyfunction]
#[pyo3(signature = (parts, allow_partial=false))]
pub fn merge<'py>(
    py: Python<'py>,
    parts: Vec<Bound<'py, PyAny>>,
    allow_partial: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let mut named = Vec::new();
    for (i, p) in parts.iter().enumerate() {
        if let Ok(part) = p.cast::<Part>() {
            named.push((
                format!("part {i} (shard {})", part.get().name),
                part.get().partial.clone(),
            ));
        } else {
            let path: PathBuf = p.extract().map_err(|_| {
                invalid(format!(
                    "parts[{i}]: expected a fogbank Part or a .fbpart path"
                ))
            })?;
            let partial = guarded(|| {
                py.detach(|| Partial::read(&path)).map_err(|e| {
                    if e.contains("No such file") {
                        pyo3::exceptions::PyFileNotFoundError::new_err(e)
                    } else {
                        invalid(e)
                    }
                })
            })?;
            named.push((path.display().to_string(), partial));
        }
    }
    let merged = guarded(|| {
        py.detach(|| fogbank::merge::merge(&named, allow_partial))
            .map_err(invalid)
    })?;
    let p = &merged.partial;
    if p.header.identity.kind != "render" {
        return Err(invalid(
            "merge: these are `stats` parts; merge them with `fogbank merge -o DIR`",
        ));
    }
    let img = film_rgb(&p.film);
    let d = PyDict::new(py);
    let (w, h) = (p.film.width, p.film.height);
    d.set_item("mean", image_array(py, &img.rgb, w, h)?)?;
    match &img.variance {
        Some(v) => d.set_item("variance", image_array(py, v, w, h)?)?,
        None => d.set_item("variance", py.None())?,
    }
    d.set_item("spp", p.film.min_spp())?;
    d.set_item("exposure", p.header.exposure)?;
    d.set_item("tonemap", p.header.tonemap.clone())?;
    d.set_item("missing", merged.missing.clone())?;
    Ok(d)
}

/// The frames of an animated scene, one at a time (what
/// `fogbank.render_frames` iterates).
#[pyclass(module = "fogbank._native")]
pub struct Frames {
    // Declared first, so dropped before the scene, renderer and progress
    // it borrows (see `Frames::new`).
    sequence: Option<FrameSequence<'static>>,
    _first: Arc<fogbank::Scene>,
    _renderer: Arc<Renderer>,
    progress: Arc<Progress>,
    report: Option<Py<PyAny>>,
    /// Samples per pixel of every frame.
    spp: u32,
}

/// Frames of `scene`: `frames` a range, `"A..B"`, `"A..=B"` or a count.
#[pyfunction]
#[pyo3(signature = (scene, frames, spp=None, seed=None, device="cpu", threads=None, progress=None))]
pub fn render_frames(
    py: Python<'_>,
    scene: &Scene,
    frames: &str,
    spp: Option<u32>,
    seed: Option<u32>,
    device: &str,
    threads: Option<usize>,
    progress: Option<Py<PyAny>>,
) -> PyResult<Frames> {
    let base = scene.with_seed(seed);
    let Some(anim) = &base.desc.animation else {
        return Err(invalid("frames: the scene has no [animation] table"));
    };
    let range = parse_frames(frames, anim.frames).map_err(to_py)?;
    let first = Arc::new(guarded(|| {
        py.detach(|| base.at_frame(range.start))
            .map_err(crate::errors::scene_err)
    })?);
    let renderer = renderer(device, threads)?;
    let progress_state = Arc::new(Progress::default());
    let job = RenderJob {
        spp,
        ..Default::default()
    };
    let spp = job.spp(&first);
    // SAFETY: see `Frames`; the references live as long as the Arcs the
    // struct owns, and `sequence` is dropped first.
    let (s, r, p): (
        &'static fogbank::Scene,
        &'static Renderer,
        &'static Progress,
    ) = unsafe {
        (
            &*Arc::as_ptr(&first),
            &*Arc::as_ptr(&renderer),
            &*Arc::as_ptr(&progress_state),
        )
    };
    let sequence = guarded(|| {
        py.detach(|| FrameSequence::new(s, range, r, job, p))
            .map_err(to_py)
    })?;
    Ok(Frames {
        sequence: Some(sequence),
        _first: first,
        _renderer: renderer,
        progress: progress_state,
        report: progress,
        spp,
    })
}

#[pymethods]
impl Frames {
    fn __iter__(slf: PyRef<'_, Self>) -> PyRef<'_, Self> {
        slf
    }

    /// The next frame's image dict (with its index under `frame`).
    fn __next__<'py>(mut slf: PyRefMut<'py, Self>) -> PyResult<Option<Bound<'py, PyDict>>> {
        let py = slf.py();
        let Some(mut seq) = slf.sequence.take() else {
            return Ok(None);
        };
        let progress = slf.progress.clone();
        let report = slf.report.as_ref().map(|r| r.bind(py).clone());
        let w = watched(py, &progress, report.as_ref(), move || {
            let next = seq.next();
            (seq, next)
        })?;
        let (seq, next) = w.value;
        if let Some(e) = w.interrupt {
            return Err(e);
        }
        let Some(frame) = next else {
            return Ok(None);
        };
        slf.sequence = Some(seq);
        let frame = frame.map_err(to_py)?;
        let img = frame.image.as_ref().expect("whole frames have images");
        let d = image_dict(py, img, &frame.scene, slf.spp)?;
        d.set_item("frame", frame.index)?;
        d.set_item("seconds", frame.seconds)?;
        Ok(Some(d))
    }
}
