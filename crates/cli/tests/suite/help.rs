//! What the program says about itself: every command's `--help` and the
//! guide's command table (`docs/guide/cli.md`) name every format the
//! readers take and every option each command has.

use crate::support;

use std::path::Path;
use support::*;

fn help(args: &[&str]) -> String {
    let out = run_ok(fogbank().args(args));
    String::from_utf8_lossy(&out.stdout).to_string()
}

/// The guide's pages (`docs/guide/*.md`), one after another.
fn guide() -> String {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../docs/guide");
    let mut pages: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "md"))
        .collect();
    pages.sort();
    assert!(
        pages.len() > 5,
        "{} holds {} pages",
        dir.display(),
        pages.len()
    );
    pages
        .iter()
        .map(|p| std::fs::read_to_string(p).unwrap())
        .collect()
}

/// Every command's help names every format it reads, as the readers'
/// registry (`fogbank::convert::FORMATS`) lists them: the scene
/// formats for the commands that take a scene, the volume formats for
/// `info`, all of them for `convert`; and the guide names them all.
#[test]
fn help_texts_and_guide_name_every_format_the_readers_take() {
    use fogbank::convert::FORMATS;
    let scene_exts: Vec<&str> = FORMATS
        .iter()
        .filter(|f| f.1.is_scene())
        .map(|f| f.0)
        .collect();
    let volume_exts: Vec<&str> = FORMATS
        .iter()
        .filter(|f| !f.1.is_scene())
        .map(|f| f.0)
        .collect();
    // `.nii` is named only where it stands on its own, not inside `.nii.gz`.
    let names = |text: &str, e: &str| {
        text.match_indices(e).any(|(i, _)| {
            let next = text[i + e.len()..].chars().next();
            !next.is_some_and(|c| c.is_alphanumeric() || c == '.')
        })
    };
    let missing = |text: &str, exts: &[&str]| -> Vec<String> {
        exts.iter()
            .filter(|e| !names(text, e))
            .map(|e| e.to_string())
            .collect()
    };
    for cmd in ["render", "view", "stats", "converge", "export"] {
        let h = help(&[cmd, "--help"]);
        assert!(
            missing(&h, &scene_exts).is_empty(),
            "{cmd} --help lacks {:?}:\n{h}",
            missing(&h, &scene_exts)
        );
    }
    let h = help(&["info", "--help"]);
    assert!(
        missing(&h, &volume_exts).is_empty(),
        "info --help lacks {:?}",
        missing(&h, &volume_exts)
    );
    let top = help(&["--help"]);
    let info_line = top
        .lines()
        .find(|l| l.trim_start().starts_with("info"))
        .unwrap();
    assert!(
        missing(info_line, &volume_exts).is_empty(),
        "fogbank --help's info line lacks {:?}",
        missing(info_line, &volume_exts)
    );
    let all: Vec<&str> = FORMATS.iter().map(|f| f.0).collect();
    let h = help(&["convert", "--help"]);
    assert!(
        missing(&h, &all).is_empty(),
        "convert --help lacks {:?}",
        missing(&h, &all)
    );
    let guide = guide();
    let absent = missing(&guide, &all);
    assert!(absent.is_empty(), "docs/guide does not name {absent:?}");
    // And the command table's rows name what each command reads.
    let row = |cmd: &str| {
        let head = format!("| `fogbank {cmd} ");
        guide
            .lines()
            .find(|l| l.starts_with(&head))
            .unwrap_or_default()
            .to_string()
    };
    let absent = missing(&row("info"), &volume_exts);
    assert!(absent.is_empty(), "the guide's info row lacks {absent:?}");
    for cmd in ["render", "view", "convert"] {
        let absent = missing(&row(cmd), &scene_exts);
        assert!(absent.is_empty(), "the guide's {cmd} row lacks {absent:?}");
    }
    // A file of none of these kinds is refused naming them.
    let dir = tmp_dir("help-formats");
    std::fs::write(dir.join("x.dat"), "").unwrap();
    let out = fogbank()
        .args(["info", dir.join("x.dat").to_str().unwrap()])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success() && volume_exts.iter().all(|e| err.contains(e)),
        "{err}"
    );
}

/// The commands `fogbank --help` lists (but `help`).
fn commands() -> Vec<String> {
    help(&["--help"])
        .lines()
        .skip_while(|l| !l.starts_with("Commands:"))
        .skip(1)
        .take_while(|l| !l.trim().is_empty())
        .filter_map(|l| l.split_whitespace().next())
        .filter(|c| *c != "help")
        .map(str::to_string)
        .collect()
}

/// The options a command's help defines, as (`--long`, `-s` if any): the
/// lines of its "Options:" section that start with a dash (an option's
/// description may mention others; only its own name counts).
fn options(cmd: &str) -> Vec<(String, Option<String>)> {
    help(&[cmd, "--help"])
        .lines()
        .skip_while(|l| !l.starts_with("Options:"))
        .filter_map(|l| {
            let l = l.trim_start();
            if !l.starts_with('-') {
                return None;
            }
            let mut words = l.split([' ', ',']).filter(|w| !w.is_empty());
            let first = words.next()?;
            let (short, long) = if first.starts_with("--") {
                (None, first)
            } else {
                (Some(first.to_string()), words.next()?)
            };
            (long != "--help" && long != "--version").then(|| (long.to_string(), short))
        })
        .collect()
}

/// The guide's command table (`docs/guide/cli.md`) gives every command a row (its first cell
/// `` `fogbank NAME …` ``) and names, in that command's rows, every
/// option the command has (by its long name, or by its short one where
/// it has one); `experiment`'s row names every experiment.
#[test]
fn guide_command_table_names_every_command_and_option() {
    let guide = guide();
    let table: Vec<&str> = guide
        .lines()
        .skip_while(|l| !l.starts_with("# The `fogbank` command"))
        .skip_while(|l| !l.starts_with("| command |"))
        .take_while(|l| l.starts_with('|'))
        .collect();
    let commands = commands();
    assert!(
        commands.iter().any(|c| c == "render") && commands.len() > 10,
        "{commands:?}"
    );
    let mut missing = Vec::new();
    for cmd in &commands {
        let head = format!("`fogbank {cmd}");
        let rows: String = table
            .iter()
            .filter(|r| {
                let first = r.split(" | ").next().unwrap_or("");
                first.match_indices(&head).any(|(i, _)| {
                    let next = first[i + head.len()..].chars().next();
                    matches!(next, Some(' ' | '`'))
                })
            })
            .copied()
            .collect::<Vec<_>>()
            .join("\n");
        if rows.is_empty() {
            missing.push(format!("no row for `fogbank {cmd}`"));
            continue;
        }
        for (long, short) in options(cmd) {
            let named = |o: &str| {
                rows.match_indices(o).any(|(i, _)| {
                    let next = rows[i + o.len()..].chars().next();
                    !next.is_some_and(|c| c.is_alphanumeric() || c == '-')
                })
            };
            if !named(&long) && !short.as_deref().is_some_and(named) {
                missing.push(format!("`fogbank {cmd}` row lacks {long}"));
            }
        }
    }
    let experiment = help(&["experiment", "--help"]);
    let names = experiment
        .split("Experiment: ")
        .nth(1)
        .and_then(|t| t.split(" (").next())
        .expect("experiment --help lists the experiments");
    let row = table
        .iter()
        .find(|r| r.starts_with("| `fogbank experiment"))
        .unwrap();
    for name in names
        .split([',', ' '])
        .filter(|n| !n.is_empty() && *n != "or")
    {
        if !row.contains(&format!("`{name}`")) {
            missing.push(format!("`fogbank experiment` row lacks `{name}`"));
        }
    }
    assert!(missing.is_empty(), "{}", missing.join("\n"));
}
