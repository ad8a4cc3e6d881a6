//! Reading one table of typed parameters (an integrator's, an estimator's)
//! out of the scene's TOML, so each integrator declares its own keys and a
//! misplaced or misspelt key is refused with the table's key list.

use crate::error::SceneError;
use fogbank_estimators::{Estimator, OptionValue, Options};
use serde::de::DeserializeOwned;

/// One row of a parameter table: what `fogbank` prints and what errors
/// list. Integrators keep theirs beside the parameter struct.
#[derive(Clone, Copy, Debug)]
pub struct Param {
    pub key: &'static str,
    pub default: &'static str,
    pub meaning: &'static str,
}

/// A TOML table being consumed key by key. `path` is where it sits in the
/// scene (`integrator`), `owner` whose parameters it holds (`"volpath"`).
pub struct ParamReader {
    path: String,
    owner: String,
    table: toml::Table,
}

impl ParamReader {
    pub fn new(path: &str, owner: &str, table: toml::Table) -> ParamReader {
        ParamReader {
            path: path.into(),
            owner: owner.into(),
            table,
        }
    }

    /// The same table, its leftover keys reported as not belonging to `owner`.
    pub fn with_owner(mut self, owner: &str) -> ParamReader {
        self.owner = owner.into();
        self
    }

    /// The dotted name of `key` in the scene.
    pub fn key_path(&self, key: &str) -> String {
        format!("{}.{key}", self.path)
    }

    /// The first key not yet taken.
    pub fn first_key(&self) -> Option<String> {
        self.table.keys().next().cloned()
    }

    pub fn has(&self, key: &str) -> bool {
        self.table.contains_key(key)
    }

    /// Removes `key` and converts it; a value of the wrong type is an error
    /// naming the key.
    pub fn take<T: DeserializeOwned>(&mut self, key: &str) -> Result<Option<T>, SceneError> {
        match self.table.remove(key) {
            None => Ok(None),
            Some(v) => v
                .try_into()
                .map(Some)
                .map_err(|e| SceneError(format!("{}: {}", self.key_path(key), first_line(&e)))),
        }
    }

    /// Removes `key` as it is.
    pub fn take_value(&mut self, key: &str) -> Option<toml::Value> {
        self.table.remove(key)
    }

    /// Every key must have been taken: the first left over is refused,
    /// naming the keys this table takes.
    pub fn finish(self, takes: &[&str]) -> Result<(), SceneError> {
        match self.table.keys().next() {
            None => Ok(()),
            Some(k) => Err(SceneError(format!(
                "{}.{k} is not a parameter of \"{}\"; it takes {}",
                self.path,
                self.owner,
                takes.join(", ")
            ))),
        }
    }
}

fn first_line(e: &impl std::fmt::Display) -> String {
    e.to_string().lines().next().unwrap_or_default().to_string()
}

/// The keys of a parameter table, in order.
pub fn keys(params: &[Param]) -> Vec<&'static str> {
    params.iter().map(|p| p.key).collect()
}

/// A parameter table as Markdown (`| key | default | meaning |`), the
/// form an integrator's module doc carries and `fogbank integrators`
/// prints: the docs are checked against this, so `PARAMS` is their one
/// source (`tests/suite/param_tables.rs`).
pub fn markdown_table(params: &[Param]) -> String {
    let mut s = String::from("| key | default | meaning |\n|---|---|---|\n");
    for p in params {
        s += &format!(
            "| `{}` | {} | {} |\n",
            p.key,
            p.default.replace('|', "\\|"),
            p.meaning.replace('|', "\\|")
        );
    }
    s
}

/// Reads the estimator of an integrator's table: `estimator = "name"`, or
/// `estimator = { type = "name", samples = 20, … }`; the estimator's options
/// may also stand flat in the integrator's table (`samples = 20`), as
/// `--set integrator.samples=20` writes them. Options the estimator does not
/// take are left in the table, for [`ParamReader::finish`] to refuse.
pub fn take_estimator(r: &mut ParamReader) -> Result<Estimator, SceneError> {
    let key = r.key_path("estimator");
    let (name, mut nested) = match r.take_value("estimator") {
        None => (Estimator::default().name().to_string(), None),
        Some(toml::Value::String(s)) => (s, None),
        Some(toml::Value::Table(mut t)) => match t.remove("type") {
            Some(toml::Value::String(s)) => (s.clone(), Some(ParamReader::new(&key, &s, t))),
            _ => {
                return Err(SceneError(format!(
                "{key}: a table needs `type = \"<estimator>\"` (`fogbank estimators` lists them)"
            )))
            }
        },
        Some(other) => {
            return Err(SceneError(format!(
                "{key}: expected an estimator name or a table, got {}",
                other.type_str()
            )))
        }
    };
    let takes = Estimator::option_keys(&name).ok_or_else(|| {
        SceneError(format!(
            "{key}: unknown estimator `{name}` (available: {})",
            Estimator::names().join(", ")
        ))
    })?;
    let mut o = Options::default();
    for &k in takes {
        let flat = r.has(k);
        let inner = nested.as_ref().is_some_and(|n| n.has(k));
        if flat && inner {
            return Err(SceneError(format!(
                "{}: given both flat and inside {key}",
                r.key_path(k)
            )));
        }
        let from = match nested.as_mut() {
            Some(n) if inner => n,
            _ => &mut *r,
        };
        if let Some(v) = from.take_value(k) {
            o.set(k, option_value(&from.key_path(k), v)?);
        }
    }
    if let Some(n) = nested {
        let mut keys = vec!["type"];
        keys.extend_from_slice(takes);
        n.finish(&keys)?;
    }
    Estimator::with_options(&name, &o).map_err(|e| SceneError(format!("{key}: {e}")))
}

/// An estimator option's scene value as the estimators read it.
fn option_value(path: &str, v: toml::Value) -> Result<OptionValue, SceneError> {
    Ok(match v {
        toml::Value::Integer(i) => OptionValue::Int(i),
        toml::Value::Float(x) => OptionValue::Float(x),
        toml::Value::Boolean(b) => OptionValue::Bool(b),
        toml::Value::String(s) => OptionValue::Text(s),
        other => {
            return Err(SceneError(format!(
                "{path}: expected a number, true or false, or a name, got {}",
                other.type_str()
            )))
        }
    })
}

/// The scene value of an estimator: its name when its options are the
/// defaults, else a table with `type` and every option.
pub fn estimator_value(e: Estimator) -> toml::Value {
    if Estimator::parse(e.name()) == Some(e) {
        return e.name().into();
    }
    let mut t = toml::Table::new();
    t.insert("type".into(), e.name().into());
    for (k, v) in e.options().iter() {
        let v = match v {
            OptionValue::Int(i) => (*i).into(),
            OptionValue::Float(x) => (*x).into(),
            OptionValue::Bool(b) => (*b).into(),
            OptionValue::Text(s) => s.clone().into(),
        };
        t.insert(k.into(), v);
    }
    toml::Value::Table(t)
}
