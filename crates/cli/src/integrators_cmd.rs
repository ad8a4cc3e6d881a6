//! `fogbank integrators [NAME]`: the integrators and their parameter
//! tables, printed from the registry (the tables the module docs and the
//! guide are checked against).

use crate::common::CliResult;
use clap::Args;
use fogbank::desc::{markdown_table, INTEGRATORS as REGISTRY};

#[derive(Args)]
pub struct IntegratorsArgs {
    /// One integrator's table (all of them when omitted).
    pub name: Option<String>,
}

pub fn run(a: IntegratorsArgs) -> CliResult {
    let names: Vec<&str> = REGISTRY.iter().map(|(n, _)| *n).collect();
    if let Some(n) = a.name.as_deref().filter(|n| !names.contains(n)) {
        return Err(format!("unknown integrator `{n}` (available: {})", names.join(", ")).into());
    }
    for (name, params) in REGISTRY.iter() {
        if a.name.as_deref().is_none_or(|n| n == *name) {
            println!("integrator.type = \"{name}\"\n\n{}", markdown_table(params));
        }
    }
    Ok(())
}
