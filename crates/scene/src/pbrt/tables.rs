//! Small helpers shared by the mappings: TOML values of matrices and of
//! grids placed by the current transform.

use glam::DMat4;
use toml::{Table, Value};

/// A matrix as a `to_world = { matrix = [[row], …] }` table.
pub fn matrix_table(m: DMat4) -> Table {
    let rows = m.transpose().to_cols_array_2d();
    let rows = rows
        .iter()
        .map(|r| Value::Array(r.iter().map(|&x| Value::Float(x)).collect()))
        .collect();
    let mut t = Table::new();
    t.insert("matrix".into(), Value::Array(rows));
    t
}

/// A field read from the in-memory array registered as `name`
/// (`{ array = name }`).
pub fn array_field(name: String) -> Value {
    let mut f = Table::new();
    f.insert("array".into(), name.into());
    Value::Table(f)
}

/// The keys of a medium whose density is the in-memory array `name`, set
/// in `t`: placed by `ctm` (the array's box is already in its transform),
/// interpolated trilinearly as pbrt's grid lookups are.
pub fn set_array_density(t: &mut Table, name: String, ctm: DMat4) {
    t.insert("density".into(), array_field(name));
    t.insert("to_world".into(), Value::Table(matrix_table(ctm)));
    t.insert("filter".into(), "trilinear".into());
}
