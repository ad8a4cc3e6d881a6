//! Python values as scene values and back: what `scene.set(key, value)`,
//! `fogbank.load(path, **overrides)` and `fogbank.load_dict(d)` accept
//! (numbers, booleans, strings, lists, tuples, dicts, numpy scalars and
//! arrays, and `Grid`s, which become `{ array = NAME }` tables), and what
//! `scene.get(key)` / `scene.to_dict()` return.

use crate::grid::Grid;
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};

/// Converts `v` (at scene key `key`, for messages), recording every `Grid`
/// it holds in `grids` so the scene can keep them alive.
pub fn to_toml(
    v: &Bound<'_, PyAny>,
    key: &str,
    grids: &mut Vec<Py<Grid>>,
) -> PyResult<toml::Value> {
    if let Ok(g) = v.cast::<Grid>() {
        let mut t = toml::Table::new();
        t.insert("array".into(), toml::Value::String(g.get().name.clone()));
        grids.push(g.clone().unbind());
        return Ok(toml::Value::Table(t));
    }
    if v.is_instance_of::<PyBool>() || is_numpy_bool(v) {
        return Ok(toml::Value::Boolean(v.is_truthy()?));
    }
    if let Ok(s) = v.cast::<PyString>() {
        return Ok(toml::Value::String(s.extract::<String>()?));
    }
    if let Ok(d) = v.cast::<PyDict>() {
        let mut t = toml::Table::new();
        for (k, x) in d.iter() {
            let k: String = k.extract().map_err(|_| {
                PyTypeError::new_err(format!(
                    "{key}: dict keys must be strings, not {}",
                    type_name(&k)
                ))
            })?;
            let sub = if key.is_empty() {
                k.clone()
            } else {
                format!("{key}.{k}")
            };
            t.insert(k, to_toml(&x, &sub, grids)?);
        }
        return Ok(toml::Value::Table(t));
    }
    if has_ndim(v)? {
        // A numpy array: as nested lists.
        return to_toml(&v.call_method0("tolist")?, key, grids);
    }
    if v.is_instance_of::<PyList>() || v.is_instance_of::<PyTuple>() {
        let items = v
            .try_iter()?
            .enumerate()
            .map(|(i, x)| to_toml(&x?, &format!("{key}.{i}"), grids))
            .collect::<PyResult<Vec<_>>>()?;
        return Ok(toml::Value::Array(items));
    }
    // Integers, numpy's included (they have __index__; floats do not).
    if v.is_instance_of::<PyInt>() || (v.hasattr("__index__")? && !v.is_instance_of::<PyFloat>()) {
        if let Ok(i) = v.extract::<i64>() {
            return Ok(toml::Value::Integer(i));
        }
    }
    if v.is_instance_of::<PyFloat>() || v.hasattr("__float__")? {
        return Ok(toml::Value::Float(v.extract::<f64>()?));
    }
    if v.is_none() {
        return Err(PyTypeError::new_err(format!(
            "{key}: None is not a scene value (leave the key out for its default)"
        )));
    }
    Err(PyTypeError::new_err(format!(
        "{key}: a {} is not a scene value (numbers, booleans, strings, lists, dicts, numpy arrays, fogbank.Grid)",
        type_name(v)
    )))
}

fn type_name(v: &Bound<'_, PyAny>) -> String {
    v.get_type()
        .name()
        .map(|n| n.to_string())
        .unwrap_or_else(|_| "value".into())
}

fn has_ndim(v: &Bound<'_, PyAny>) -> PyResult<bool> {
    Ok(v.hasattr("ndim")? && v.getattr("ndim")?.extract::<usize>().is_ok_and(|n| n > 0))
}

fn is_numpy_bool(v: &Bound<'_, PyAny>) -> bool {
    let module = v
        .get_type()
        .module()
        .map(|m| m.to_string())
        .unwrap_or_default();
    module == "numpy" && type_name(v).starts_with("bool")
}

/// A scene value as a Python object.
pub fn to_py<'py>(py: Python<'py>, v: &toml::Value) -> PyResult<Bound<'py, PyAny>> {
    Ok(match v {
        toml::Value::String(s) => s.into_pyobject(py)?.into_any(),
        toml::Value::Integer(i) => i.into_pyobject(py)?.into_any(),
        toml::Value::Float(f) => f.into_pyobject(py)?.into_any(),
        toml::Value::Boolean(b) => PyBool::new(py, *b).to_owned().into_any(),
        toml::Value::Datetime(d) => d.to_string().into_pyobject(py)?.into_any(),
        toml::Value::Array(a) => {
            let items = a
                .iter()
                .map(|x| to_py(py, x))
                .collect::<PyResult<Vec<_>>>()?;
            PyList::new(py, items)?.into_any()
        }
        toml::Value::Table(t) => {
            let d = PyDict::new(py);
            for (k, x) in t {
                d.set_item(k, to_py(py, x)?)?;
            }
            d.into_any()
        }
    })
}
