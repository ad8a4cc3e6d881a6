//! Every integrator's parameter table has one source, its `PARAMS` in the
//! registry: the table in its module doc, the defaults its reader gives,
//! and its keys in the guide's integrator table (docs/guide/integrators.md) are checked against it,
//! so none of them can drift. On a mismatch the message prints what the
//! place should say.

use fogbank_render::integrators::{IntegratorDesc, LISTED};
use fogbank_render::params::{markdown_table, Param};
use std::path::{Path, PathBuf};

/// The file whose module doc describes integrator `name`.
fn module_file(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("src/integrators");
    let file = dir.join(format!("{name}.rs"));
    if file.exists() {
        file
    } else {
        dir.join(name).join("mod.rs")
    }
}

/// The first `| key | default | meaning |` table of a file's `//!` doc.
fn doc_table(source: &str) -> String {
    let mut table = String::new();
    for line in source.lines() {
        match line.strip_prefix("//! ") {
            Some(row) if row.starts_with('|') => table += &format!("{row}\n"),
            _ if !table.is_empty() => break,
            _ => {}
        }
    }
    table
}

#[test]
fn module_docs_carry_the_registered_tables() {
    let mut wrong = Vec::new();
    for (name, params) in LISTED.iter() {
        let path = module_file(name);
        let source = std::fs::read_to_string(&path).unwrap();
        let expected = markdown_table(params);
        if doc_table(&source) != expected {
            let doc: String = expected.lines().map(|l| format!("//! {l}\n")).collect();
            wrong.push(format!("{}: its table should read\n{doc}", path.display()));
        }
    }
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}

/// A written value as a parameter table writes it (`64`, `0.03`,
/// `delta_tracking`, `[1, 1, 1]`); `None` for a table with keys.
fn shown(v: &toml::Value) -> Option<String> {
    Some(match v {
        toml::Value::String(s) => s.clone(),
        toml::Value::Integer(i) => i.to_string(),
        // Parameters are f32: their shortest form is what a table writes.
        toml::Value::Float(f) => format!("{}", *f as f32),
        toml::Value::Boolean(b) => b.to_string(),
        toml::Value::Array(a) => {
            let items: Option<Vec<String>> = a.iter().map(shown).collect();
            format!("[{}]", items?.join(", "))
        }
        toml::Value::Table(t) if t.is_empty() => "{}".into(),
        _ => return None,
    })
}

/// The integrator `name` with every parameter left to its default.
fn defaults(name: &str) -> toml::Table {
    let mut t = toml::Table::new();
    t.insert("type".into(), name.into());
    let desc = IntegratorDesc::from_table("integrator", t).unwrap();
    assert_eq!(desc.name(), name);
    let written = desc.to_table();
    // What a default description writes reads back as itself.
    let again = IntegratorDesc::from_table("integrator", written.clone()).unwrap();
    assert_eq!(again, desc, "{name}");
    written
}

#[test]
fn defaults_read_are_the_defaults_the_tables_state() {
    let mut wrong = Vec::new();
    for (name, params) in LISTED.iter() {
        let written = defaults(name);
        for Param { key, default, .. } in params.iter() {
            let Some(value) = written.get(*key).and_then(shown) else {
                continue;
            };
            // A default may be qualified: `4 (10 with shapes)`.
            let qualified = default
                .strip_prefix(value.as_str())
                .is_some_and(|rest| rest.starts_with(" ("));
            if *default != value && !qualified {
                wrong.push(format!(
                    "{name}.{key}: the table says {default}, reading gives {value}"
                ));
            }
        }
    }
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}

/// The keys cell of integrator `name`'s row in the guide's integrator table (docs/guide/integrators.md).
fn guide_keys(guide: &str, name: &str) -> Option<String> {
    let row = guide
        .lines()
        .find(|l| l.starts_with(&format!("| `{name}` |")))?;
    let cells: Vec<&str> = row.trim_end_matches('|').rsplitn(2, " | ").collect();
    Some(cells.first()?.trim().to_string())
}

/// `` `key` (default) `` for every row, as the guide lists them.
fn keys_cell(params: &[Param]) -> String {
    let keys: Vec<String> = params
        .iter()
        .map(|p| format!("`{}` ({})", p.key, p.default.replace('|', "\\|")))
        .collect();
    keys.join(", ")
}

#[test]
fn the_guide_lists_every_key_with_its_default() {
    let guide_path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../docs/guide/integrators.md");
    let guide = std::fs::read_to_string(guide_path).unwrap();
    let mut wrong = Vec::new();
    for (name, params) in LISTED.iter() {
        let expected = keys_cell(params);
        match guide_keys(&guide, name) {
            Some(cell) if cell == expected => {}
            Some(cell) => wrong.push(format!(
                "`{name}`: the guide's keys cell reads\n{cell}\nand should read\n{expected}"
            )),
            None => wrong.push(format!(
                "`{name}`: no row in the guide's integrator table (docs/guide/integrators.md)"
            )),
        }
    }
    assert!(wrong.is_empty(), "{}", wrong.join("\n\n"));
}

#[test]
fn the_checks_catch_a_drifted_table() {
    // The doc check: a table whose default changed no longer matches.
    let params = [Param {
        key: "max_depth",
        default: "64",
        meaning: "longest path",
    }];
    let doc = "//! text\n//!\n//! | key | default | meaning |\n//! |---|---|---|\n//! | `max_depth` | 65 | longest path |\n\nuse x;\n";
    assert_ne!(doc_table(doc), markdown_table(&params));
    assert_eq!(doc_table(&doc.replace("65", "64")), markdown_table(&params));
    // The guide check: a missing key changes the cell.
    let guide = "| `volpath` | what | `max_depth` (64) |\n";
    assert_eq!(
        guide_keys(guide, "volpath").as_deref(),
        Some(keys_cell(&params).as_str())
    );
    assert_ne!(
        guide_keys("| `volpath` | what | `rr_depth` (3) |", "volpath").unwrap(),
        keys_cell(&params)
    );
    // Values shown as tables write them.
    assert_eq!(
        shown(&toml::Value::Float(f64::from(0.03f32))).unwrap(),
        "0.03"
    );
    assert_eq!(shown(&toml::Value::Float(1.0)).unwrap(), "1");
}
