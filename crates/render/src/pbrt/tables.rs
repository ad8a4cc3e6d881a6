//! Small helpers shared by the mappings: TOML values of matrices.

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
