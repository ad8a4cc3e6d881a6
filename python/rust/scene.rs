//! `fogbank.Scene`: a scene as the command line loads it (a TOML or
//! Mitsuba XML file, the built-in default, or a dict of the TOML schema)
//! with `--set`'s dotted-key overrides, built and ready to render.
//!
//! A scene is its source text plus the overrides set on it, rebuilt after
//! each `set`, so `fogbank.load(f).set(k, v)` is `fogbank render f --set
//! k=v` exactly, errors included (a misspelt key raises `ValueError`
//! naming it, and the scene stays as it was).

use crate::errors::{guarded, scene_err};
use crate::grid::Grid;
use crate::values;
use fogbank::{parse_scene, SceneError, SceneFormat, DEFAULT_SCENE};
use numpy::{PyArray1, PyArrayMethods};
use pyo3::exceptions::PyKeyError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// A built scene: `fogbank.load(path)`, `fogbank.load_dict(d)` or
/// `fogbank.default_scene()`. `set(key, value)` changes it with the
/// command line's dotted keys, `get(key)` reads them, `to_toml()` /
/// `to_dict()` give its full description, `media` its media and
/// `camera_rays()` the rays through its pixel centres.
#[pyclass(module = "fogbank._native")]
pub struct Scene {
    /// TOML text (a Mitsuba file's converted document).
    text: String,
    /// Names the source in messages: the file, `built-in scene` or `dict`.
    origin: String,
    /// Where relative file names resolve.
    base: PathBuf,
    overrides: Vec<String>,
    pub inner: Arc<fogbank::Scene>,
    /// Grids the scene names, kept alive while it may be rebuilt.
    grids: Vec<Py<Grid>>,
}

fn build(
    text: &str,
    origin: &str,
    base: &Path,
    overrides: &[String],
) -> Result<fogbank::Scene, SceneError> {
    let desc = parse_scene(text, origin, overrides)?;
    fogbank::Scene::build(desc, base)
}

impl Scene {
    fn new(
        py: Python<'_>,
        text: String,
        origin: String,
        base: PathBuf,
        overrides: Vec<String>,
        grids: Vec<Py<Grid>>,
    ) -> PyResult<Scene> {
        let inner = guarded(|| {
            py.detach(|| build(&text, &origin, &base, &overrides))
                .map_err(scene_err)
        })?;
        Ok(Scene {
            text,
            origin,
            base,
            overrides,
            inner: Arc::new(inner),
            grids,
        })
    }

    /// `--set KEY=VALUE` for a Python value.
    fn override_of(
        key: &str,
        value: &Bound<'_, PyAny>,
        grids: &mut Vec<Py<Grid>>,
    ) -> PyResult<String> {
        let v = values::to_toml(value, key, grids)?;
        Ok(format!("{key}={v}"))
    }

    /// The scene rebuilt with `extra` overrides after its own.
    pub fn rebuild(&self, extra: &[String]) -> Result<fogbank::Scene, SceneError> {
        let all: Vec<String> = self.overrides.iter().chain(extra).cloned().collect();
        build(&self.text, &self.origin, &self.base, &all)
    }

    /// A copy of this scene with another seed, for `render(seed=…)`: the
    /// description says the seed, as `--seed` makes it; the world is shared.
    pub fn with_seed(&self, seed: Option<u32>) -> Arc<fogbank::Scene> {
        match seed {
            Some(s) if s != self.inner.desc.render.seed => {
                let mut sc = (*self.inner).clone();
                sc.desc.render.seed = s;
                Arc::new(sc)
            }
            _ => self.inner.clone(),
        }
    }
}

/// The overrides of `overrides` (dotted keys), recording grids.
fn overrides_of(
    overrides: Option<&Bound<'_, PyDict>>,
    grids: &mut Vec<Py<Grid>>,
) -> PyResult<Vec<String>> {
    let mut out = Vec::new();
    if let Some(d) = overrides {
        for (k, v) in d.iter() {
            let k: String = k.extract()?;
            out.push(Scene::override_of(&k, &v, grids)?);
        }
    }
    Ok(out)
}

/// Loads a scene file: TOML (fogbank's format) or Mitsuba XML. Keyword
/// arguments are overrides with the command line's dotted keys
/// (`fogbank.load(f, **{"render.spp": 64})`); for a Mitsuba file, a key
/// without a dot is a `$name` parameter of the file, as `mi.load_file`
/// takes them.
#[pyfunction]
#[pyo3(signature = (path, **overrides))]
pub fn load(
    py: Python<'_>,
    path: PathBuf,
    overrides: Option<&Bound<'_, PyDict>>,
) -> PyResult<Scene> {
    let mut grids = Vec::new();
    // Keys without a dot are a Mitsuba scene's defines (its `-D`); dotted
    // keys override the converted scene like the command's `--set`.
    let takes_defines = SceneFormat::of(&path).takes_defines();
    let mut defines = Vec::new();
    let sets = PyDict::new(py);
    if let Some(d) = overrides {
        for (k, v) in d.iter() {
            let key: String = k.extract()?;
            if takes_defines && !key.contains('.') {
                defines.push((key, v.str()?.to_string()));
            } else {
                sets.set_item(k, v)?;
            }
        }
    }
    let source = guarded(|| {
        py.detach(|| fogbank::read_scene_source(&path, &defines))
            .map_err(scene_err)
    })?;
    let o = overrides_of(Some(&sets), &mut grids)?;
    Scene::new(py, source.text, source.origin, source.base, o, grids)
}

/// A scene from a dict of fogbank's TOML schema (what `scene.to_dict()`
/// returns); relative file names resolve against `base` (default: the
/// working directory).
#[pyfunction]
#[pyo3(signature = (d, base = None))]
pub fn load_dict(py: Python<'_>, d: &Bound<'_, PyDict>, base: Option<PathBuf>) -> PyResult<Scene> {
    let mut grids = Vec::new();
    let doc = values::to_toml(d.as_any(), "", &mut grids)?;
    let text = toml::to_string(&doc).map_err(crate::errors::invalid)?;
    Scene::new(
        py,
        text,
        "dict".into(),
        base.unwrap_or_default(),
        Vec::new(),
        grids,
    )
}

/// The built-in default scene (what `fogbank render` renders without a
/// file); keyword arguments as for `load`.
#[pyfunction]
#[pyo3(signature = (**overrides))]
pub fn default_scene(py: Python<'_>, overrides: Option<&Bound<'_, PyDict>>) -> PyResult<Scene> {
    let mut grids = Vec::new();
    let o = overrides_of(overrides, &mut grids)?;
    Scene::new(
        py,
        DEFAULT_SCENE.to_string(),
        "built-in scene".into(),
        PathBuf::from("."),
        o,
        grids,
    )
}

/// One of a scene's media, for `fogbank.transmittance` and
/// `fogbank.sample_distance`: its grid, transform, σ_t scale and filter.
#[pyclass(module = "fogbank._native", frozen)]
pub struct Medium {
    pub scene: Arc<fogbank::Scene>,
    pub index: usize,
}

#[pymethods]
impl Medium {
    #[getter]
    fn index(&self) -> usize {
        self.index
    }
    /// What the density came from.
    #[getter]
    fn source(&self) -> String {
        self.scene.media[self.index].source.clone()
    }
    /// Grid dimensions (x, y, z).
    #[getter]
    fn dims(&self) -> [u32; 3] {
        self.scene.media[self.index].medium.dims()
    }
    /// The world-space box ((x0, y0, z0), (x1, y1, z1)) the medium fills.
    #[getter]
    fn bounds(&self) -> ([f32; 3], [f32; 3]) {
        let b = self.scene.media[self.index].medium.world_bounds();
        (b.min.to_array(), b.max.to_array())
    }
    fn __repr__(&self) -> String {
        format!("fogbank.Medium({}, index={})", self.source(), self.index)
    }
}

#[pymethods]
impl Scene {
    /// Sets a scene key with the command line's dotted names
    /// (`scene.set("media.0.sigma_t_scale", 40)`) and rebuilds the scene;
    /// returns the scene. A value may be a number, string, list, dict,
    /// numpy array or `fogbank.Grid`.
    fn set<'py>(
        mut slf: PyRefMut<'py, Self>,
        key: &str,
        value: &Bound<'py, PyAny>,
    ) -> PyResult<PyRefMut<'py, Self>> {
        let py = slf.py();
        let mut grids: Vec<Py<Grid>> = slf.grids.iter().map(|g| g.clone_ref(py)).collect();
        let o = Scene::override_of(key, value, &mut grids)?;
        let mut overrides = slf.overrides.clone();
        overrides.push(o);
        let (text, origin, base) = (slf.text.clone(), slf.origin.clone(), slf.base.clone());
        let inner = guarded(|| {
            py.detach(|| build(&text, &origin, &base, &overrides))
                .map_err(scene_err)
        })?;
        slf.inner = Arc::new(inner);
        slf.overrides = overrides;
        slf.grids = grids;
        Ok(slf)
    }

    /// The value of a dotted key in the scene's full description (defaults
    /// filled in); `KeyError` naming the key when it has none.
    fn get<'py>(&self, py: Python<'py>, key: &str) -> PyResult<Bound<'py, PyAny>> {
        let doc = toml::Value::try_from(&self.inner.desc).map_err(crate::errors::runtime)?;
        let mut node = &doc;
        for part in key.split('.') {
            let next = match node {
                toml::Value::Table(t) => t.get(part),
                toml::Value::Array(a) => part.parse::<usize>().ok().and_then(|i| a.get(i)),
                _ => None,
            };
            node = next
                .ok_or_else(|| PyKeyError::new_err(format!("{key}: the scene has no such key")))?;
        }
        values::to_py(py, node)
    }

    /// The scene's full description as fogbank TOML; `fogbank.load_dict(
    /// tomllib.loads(scene.to_toml()))` is the same scene (grids are named
    /// `array:N` and exist only in this process).
    fn to_toml(&self) -> PyResult<String> {
        toml::to_string(&self.inner.desc).map_err(crate::errors::runtime)
    }

    /// The full description as a dict of the TOML schema.
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let doc = toml::Value::try_from(&self.inner.desc).map_err(crate::errors::runtime)?;
        values::to_py(py, &doc)
    }

    /// An independent copy (later `set`s on one do not change the other).
    pub fn copy(&self, py: Python<'_>) -> Scene {
        Scene {
            text: self.text.clone(),
            origin: self.origin.clone(),
            base: self.base.clone(),
            overrides: self.overrides.clone(),
            inner: self.inner.clone(),
            grids: self.grids.iter().map(|g| g.clone_ref(py)).collect(),
        }
    }

    #[getter]
    fn width(&self) -> u32 {
        self.inner.camera.width
    }
    #[getter]
    fn height(&self) -> u32 {
        self.inner.camera.height
    }
    /// `render.spp`.
    #[getter]
    fn spp(&self) -> u32 {
        self.inner.desc.render.spp
    }
    /// `render.seed`.
    #[getter]
    fn seed(&self) -> u32 {
        self.inner.desc.render.seed
    }
    /// The integrator's name.
    #[getter]
    fn integrator(&self) -> &'static str {
        self.inner.integrator.name()
    }
    /// The transmittance estimator the integrator uses.
    #[getter]
    fn estimator(&self) -> &'static str {
        self.inner.integrator.estimator_name()
    }
    /// Frames of the scene's `[animation]`, None without one.
    #[getter]
    fn frames(&self) -> Option<u32> {
        self.inner.desc.animation.as_ref().map(|a| a.frames)
    }
    /// The media, in scene order (instances included).
    #[getter]
    fn media(&self) -> Vec<Medium> {
        (0..self.inner.media.len())
            .map(|index| Medium {
                scene: self.inner.clone(),
                index,
            })
            .collect()
    }

    /// The camera's rays through pixel centres, row by row: origins and
    /// directions (N×3 float32) and where each ends (N, float32; inf
    /// without a far plane): the rays a `transmittance` render through
    /// pixel centres estimates along, pixel `y·width + x` being ray index
    /// `y·width + x`.
    fn camera_rays<'py>(
        &self,
        py: Python<'py>,
    ) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyAny>, Bound<'py, PyAny>)> {
        let (o, d, t) = fogbank::rays::camera_rays(&self.inner);
        let n = t.len();
        let flat = |v: Vec<[f32; 3]>| v.into_iter().flatten().collect::<Vec<f32>>();
        Ok((
            PyArray1::from_vec(py, flat(o)).reshape([n, 3])?.into_any(),
            PyArray1::from_vec(py, flat(d)).reshape([n, 3])?.into_any(),
            PyArray1::from_vec(py, t).into_any(),
        ))
    }

    fn __repr__(&self) -> String {
        format!(
            "fogbank.Scene({}, {}×{}, integrator={}, estimator={}, media={})",
            self.origin,
            self.inner.camera.width,
            self.inner.camera.height,
            self.inner.integrator.name(),
            self.inner.integrator.estimator_name(),
            self.inner.media.len()
        )
    }
}
