//! The guide's estimator table (`docs/guide/estimators.md`) against the
//! registry: one row per registered estimator, in the registry's order, its
//! bias column agreeing with the registry's, and its options cell naming
//! every option key the estimator takes; no row for an estimator the
//! registry lacks.

use fogbank_estimators::Estimator;
use std::path::Path;

/// The table's rows as (name, bias cell, options cell).
fn rows() -> Vec<(String, String, String)> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../docs/guide/estimators.md");
    let text = std::fs::read_to_string(&path).unwrap();
    text.lines()
        .skip_while(|l| !l.starts_with("| name | bias | options |"))
        .skip(2)
        .take_while(|l| l.starts_with('|'))
        .map(|l| {
            let cells: Vec<&str> = l.trim_matches('|').split(" | ").map(str::trim).collect();
            let name = cells[0].trim_matches('`').to_string();
            (name, cells[1].to_string(), cells[2].to_string())
        })
        .collect()
}

#[test]
fn the_guide_lists_every_estimator_with_its_options() {
    let rows = rows();
    let names: Vec<&str> = rows.iter().map(|r| r.0.as_str()).collect();
    assert_eq!(
        names,
        Estimator::names(),
        "the guide's rows against the registry"
    );
    let mut wrong = Vec::new();
    for ((name, bias, options), e) in rows.iter().zip(Estimator::all()) {
        let says_biased = bias.starts_with("biased");
        if says_biased != e.biased() {
            wrong.push(format!(
                "`{name}`: bias cell `{bias}`, registry biased = {}",
                e.biased()
            ));
        }
        for key in Estimator::option_keys(name).unwrap() {
            if !options.contains(&format!("`{key}`")) {
                wrong.push(format!("`{name}`: options cell lacks `{key}`"));
            }
        }
    }
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}
