//! `--set a.b.0.c=VALUE`: edits of the parsed TOML document, applied
//! before the typed descriptions are built, so unknown keys are still
//! caught by them.

use crate::error::SceneError;

/// Parses the value of a `--set` as TOML (`40`, `"x"`, `[1, 2, 3]`, `true`),
/// falling back to a bare string so `--set integrator.estimator=track_length`
/// needs no quotes.
pub fn parse_value(text: &str) -> toml::Value {
    match toml::from_str::<toml::Table>(&format!("v = {text}")) {
        Ok(mut t) => t
            .remove("v")
            .unwrap_or_else(|| toml::Value::String(text.into())),
        Err(_) => toml::Value::String(text.into()),
    }
}

/// Sets `path` (dotted; numbers index arrays) in `doc` to `value`. Missing
/// tables are created; an index past an array's end is an error. Unknown keys
/// are caught afterwards, when the document is deserialised.
pub fn apply_override(
    doc: &mut toml::Table,
    path: &str,
    value: toml::Value,
) -> Result<(), SceneError> {
    let mut root = toml::Value::Table(std::mem::take(doc));
    let result = set_path(&mut root, path, value);
    if let toml::Value::Table(t) = root {
        *doc = t;
    }
    result
}

fn set_path(root: &mut toml::Value, path: &str, value: toml::Value) -> Result<(), SceneError> {
    let parts: Vec<&str> = path.split('.').collect();
    if parts.iter().any(|p| p.is_empty()) {
        return Err(SceneError(format!("--set {path}: empty key segment")));
    }
    let (last, parents) = parts.split_last().expect("split yields at least one part");
    let mut node = root;
    for (i, part) in parents.iter().enumerate() {
        let so_far = parts[..=i].join(".");
        node = match node {
            toml::Value::Table(t) => t
                .entry(part.to_string())
                .or_insert_with(|| toml::Value::Table(toml::Table::new())),
            toml::Value::Array(a) => {
                let len = a.len();
                let idx: usize = part.parse().map_err(|_| {
                    SceneError(format!(
                        "--set {path}: `{so_far}` indexes a list, expected a number"
                    ))
                })?;
                a.get_mut(idx).ok_or_else(|| {
                    SceneError(format!(
                        "--set {path}: `{so_far}` is out of range (the list has {len} entries)"
                    ))
                })?
            }
            _ => {
                return Err(SceneError(format!(
                    "--set {path}: `{}` is not a table",
                    parts[..i].join(".")
                )))
            }
        };
    }
    match node {
        toml::Value::Table(t) => {
            t.insert(last.to_string(), value);
            Ok(())
        }
        toml::Value::Array(a) => {
            let len = a.len();
            let idx: usize = last.parse().map_err(|_| {
                SceneError(format!(
                    "--set {path}: `{last}` indexes a list, expected a number"
                ))
            })?;
            let slot = a.get_mut(idx).ok_or_else(|| {
                SceneError(format!(
                    "--set {path}: index {idx} is out of range (the list has {len} entries)"
                ))
            })?;
            *slot = value;
            Ok(())
        }
        _ => Err(SceneError(format!(
            "--set {path}: `{}` is not a table",
            parents.join(".")
        ))),
    }
}
