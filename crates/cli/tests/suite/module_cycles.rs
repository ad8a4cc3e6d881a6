//! The workspace's layering holds inside each crate too: no two modules
//! (files) import each other, directly or around a circle. This reads the
//! `use` lines and inline paths of every `crates/*/src` file, resolves them
//! to the module (file) they name — following `pub use` re-exports to the
//! module that defines the item — and fails naming every circle it finds.
//! Declaring a child (`pub mod x;`) is not an import.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// One file: its module path (`["integrators", "shared"]`), child modules,
/// the re-exports of its top level, and its code split by inline module.
struct Module {
    file: PathBuf,
    path: Vec<String>,
    children: BTreeSet<String>,
    /// `pub use a::b::Item` → ("Item", absolute path of a::b::Item).
    reexports: BTreeMap<String, Vec<String>>,
    scopes: Vec<Scope>,
}

/// The code of one (file or inline) module and what its `use` lines bring
/// into scope.
struct Scope {
    /// Module path of the inline module (the file's own for its top level).
    here: Vec<String>,
    code: String,
    /// Local name → absolute path it stands for.
    imports: Vec<(String, Vec<String>)>,
    /// Absolute paths of glob imports (`use crate::*`).
    globs: Vec<Vec<String>>,
}

/// Splits a file's code by inline module (`mod tests { … }`), each part with
/// the inline module names around it.
fn split_inline(code: &str) -> Vec<(Vec<String>, String)> {
    let mut parts: BTreeMap<Vec<String>, String> = BTreeMap::new();
    let mut stack: Vec<(String, i32)> = Vec::new();
    let mut depth = 0i32;
    for line in code.lines() {
        let l = line.trim();
        let l2 = l
            .strip_prefix("pub(crate) ")
            .or_else(|| l.strip_prefix("pub "))
            .unwrap_or(l);
        let opened = l2
            .strip_prefix("mod ")
            .and_then(|r| r.strip_suffix('{'))
            .map(|n| n.trim().to_string());
        let key: Vec<String> = stack.iter().map(|(n, _)| n.clone()).collect();
        if let Some(name) = opened {
            stack.push((name, depth));
            depth += 1;
            continue;
        }
        let part = parts.entry(key).or_default();
        part.push_str(line);
        part.push('\n');
        depth += line.matches('{').count() as i32 - line.matches('}').count() as i32;
        while stack.last().is_some_and(|(_, d)| depth <= *d) {
            stack.pop();
        }
    }
    parts.into_iter().collect()
}

fn strip_comments(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for line in text.lines() {
        let mut code = line;
        // Good enough for this code base: `//` inside a string literal is
        // rare and at worst hides a path in the rest of that line.
        if let Some(i) = line.find("//") {
            if !line[..i].contains('"') {
                code = &line[..i];
            }
        }
        out.push_str(code);
        out.push('\n');
    }
    out
}

fn module_path(src: &Path, file: &Path) -> Vec<String> {
    let rel = file.strip_prefix(src).unwrap();
    let mut parts: Vec<String> = rel
        .iter()
        .map(|p| p.to_string_lossy().into_owned())
        .collect();
    let last = parts.pop().unwrap();
    match last.as_str() {
        "lib.rs" | "main.rs" | "mod.rs" => {}
        f => parts.push(f.trim_end_matches(".rs").to_string()),
    }
    parts
}

/// Expands a use tree (`a::{b, c::{d, e as f}}`) into (alias, path) pairs.
fn expand_use(tree: &str, prefix: &[String], out: &mut Vec<(String, Vec<String>)>) {
    let tree = tree.trim();
    if let Some(open) = tree.find('{') {
        let head: Vec<String> = tree[..open]
            .split("::")
            .map(str::trim)
            .filter(|s| !s.is_empty())
            .map(String::from)
            .collect();
        let mut base = prefix.to_vec();
        base.extend(head);
        let inner = &tree[open + 1..tree.rfind('}').unwrap()];
        let (mut depth, mut start) = (0, 0);
        for (i, c) in inner.char_indices() {
            match c {
                '{' => depth += 1,
                '}' => depth -= 1,
                ',' if depth == 0 => {
                    expand_use(&inner[start..i], &base, out);
                    start = i + 1;
                }
                _ => {}
            }
        }
        expand_use(&inner[start..], &base, out);
        return;
    }
    if tree.is_empty() {
        return;
    }
    let (path, alias) = match tree.split_once(" as ") {
        Some((p, a)) => (p.trim(), Some(a.trim().to_string())),
        None => (tree, None),
    };
    let mut full = prefix.to_vec();
    full.extend(path.split("::").map(|s| s.trim().to_string()));
    let alias = alias.unwrap_or_else(|| full.last().cloned().unwrap_or_default());
    out.push((alias, full));
}

/// Turns a path as written in module `here` into an absolute one
/// (`crate`-relative, without `crate`), or `None` for another crate's.
fn absolute(here: &[String], path: &[String], children: &BTreeSet<String>) -> Option<Vec<String>> {
    let mut base: Vec<String> = here.to_vec();
    let mut rest = path;
    match rest.first().map(String::as_str) {
        Some("crate") => {
            base.clear();
            rest = &rest[1..];
        }
        Some("self") => rest = &rest[1..],
        Some("super") => {
            while rest.first().map(String::as_str) == Some("super") {
                base.pop();
                rest = &rest[1..];
            }
        }
        Some(first) if children.contains(first) => {}
        _ => return None,
    }
    base.extend(rest.iter().cloned());
    Some(base)
}

fn load(src: &Path) -> Vec<Module> {
    let mut files = Vec::new();
    let mut stack = vec![src.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                stack.push(p);
            } else if p.extension().is_some_and(|x| x == "rs") {
                files.push(p);
            }
        }
    }
    files.sort();
    let decl = child_declarations();
    files
        .into_iter()
        .map(|file| {
            let code = strip_comments(&std::fs::read_to_string(&file).unwrap());
            let path = module_path(src, &file);
            let children = decl(&code);
            let mut reexports = BTreeMap::new();
            let mut scopes = Vec::new();
            for (inline, code) in split_inline(&code) {
                let mut here = path.clone();
                here.extend(inline.iter().cloned());
                let kids = if inline.is_empty() {
                    children.clone()
                } else {
                    BTreeSet::new()
                };
                let mut imports = Vec::new();
                let mut globs = Vec::new();
                for stmt in use_statements(&code) {
                    let public = stmt.starts_with("pub");
                    let tree = stmt.split_once("use ").map_or("", |x| x.1);
                    let mut pairs = Vec::new();
                    expand_use(tree, &[], &mut pairs);
                    for (alias, p) in pairs {
                        let Some(abs) = absolute(&here, &p, &kids) else {
                            continue;
                        };
                        if alias == "*" {
                            globs.push(abs[..abs.len() - 1].to_vec());
                            continue;
                        }
                        if public && inline.is_empty() {
                            reexports.insert(alias.clone(), abs.clone());
                        }
                        imports.push((alias, abs));
                    }
                }
                scopes.push(Scope {
                    here,
                    code,
                    imports,
                    globs,
                });
            }
            Module {
                file,
                path,
                children,
                reexports,
                scopes,
            }
        })
        .collect()
}

/// `mod x;` / `pub mod x;` declarations of child files (not inline modules).
fn child_declarations() -> impl Fn(&str) -> BTreeSet<String> {
    |code: &str| {
        code.lines()
            .filter_map(|l| {
                let l = l.trim();
                let l = l
                    .strip_prefix("pub(crate) ")
                    .or_else(|| l.strip_prefix("pub "))
                    .unwrap_or(l);
                let name = l.strip_prefix("mod ")?.strip_suffix(';')?;
                Some(name.trim().to_string())
            })
            .collect()
    }
}

/// The text of each `use …;` statement (possibly spanning lines).
fn use_statements(code: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut rest = code;
    while let Some(i) = find_use(rest) {
        let after = &rest[i..];
        let end = after.find(';').unwrap_or(after.len());
        out.push(
            after[..end]
                .split_whitespace()
                .collect::<Vec<_>>()
                .join(" "),
        );
        rest = &after[end.min(after.len())..];
        if rest.is_empty() {
            break;
        }
        rest = &rest[1.min(rest.len())..];
    }
    out
}

fn find_use(s: &str) -> Option<usize> {
    let mut from = 0;
    while let Some(j) = s[from..].find("use ") {
        let i = from + j;
        let before = s[..i].trim_end_matches(' ');
        let line_start = before.is_empty() || before.ends_with('\n') || before.ends_with('{');
        if line_start {
            return Some(i);
        }
        if before.ends_with("pub")
            || before.ends_with("pub(crate)")
            || before.ends_with("pub(super)")
        {
            let k = before.rfind("pub").unwrap();
            let b2 = s[..k].trim_end_matches(' ');
            if b2.is_empty() || b2.ends_with('\n') || b2.ends_with('{') {
                return Some(k);
            }
        }
        from = i + 4;
    }
    None
}

/// The paths written inline (`crate::a::b`, `super::x`, `child::f`,
/// `imported::g`) in a module's code, outside `use` statements.
fn inline_paths(code: &str) -> Vec<Vec<String>> {
    let mut out = Vec::new();
    let bytes = code.as_bytes();
    let is_ident = |c: u8| c.is_ascii_alphanumeric() || c == b'_';
    let mut i = 0;
    while i < bytes.len() {
        if is_ident(bytes[i]) && (i == 0 || !(is_ident(bytes[i - 1]) || bytes[i - 1] == b':')) {
            let start = i;
            let mut segs = Vec::new();
            let mut j = i;
            loop {
                let s = j;
                while j < bytes.len() && is_ident(bytes[j]) {
                    j += 1;
                }
                segs.push(code[s..j].to_string());
                if code[j..].starts_with("::") && j + 2 < bytes.len() && is_ident(bytes[j + 2]) {
                    j += 2;
                } else {
                    break;
                }
            }
            if segs.len() > 1 {
                out.push(segs);
            }
            i = j.max(start + 1);
        } else {
            i += 1;
        }
    }
    out
}

/// The module file an absolute path lands in: its longest prefix that is a
/// module, following re-exports of the next segment.
fn resolve(
    mods: &BTreeMap<Vec<String>, usize>,
    all: &[Module],
    path: &[String],
    depth: u32,
) -> Option<usize> {
    let mut best = None;
    for n in (0..=path.len()).rev() {
        if let Some(&m) = mods.get(&path[..n].to_vec()) {
            best = Some((m, n));
            break;
        }
    }
    let (m, n) = best?;
    if depth < 8 {
        if let Some(next) = path.get(n) {
            if let Some(target) = all[m].reexports.get(next) {
                let mut t = target.clone();
                t.extend(path[n + 1..].iter().cloned());
                if let Some(r) = resolve(mods, all, &t, depth + 1) {
                    return Some(r);
                }
            }
        }
    }
    Some(m)
}

fn edges(all: &[Module]) -> Vec<BTreeSet<usize>> {
    let mods: BTreeMap<Vec<String>, usize> = all
        .iter()
        .enumerate()
        .map(|(i, m)| (m.path.clone(), i))
        .collect();
    all.iter()
        .enumerate()
        .map(|(i, m)| {
            let mut out = BTreeSet::new();
            let mut add = |abs: &[String]| {
                if let Some(t) = resolve(&mods, all, abs, 0) {
                    if t != i {
                        out.insert(t);
                    }
                }
            };
            for s in &m.scopes {
                let kids = if s.here == m.path {
                    m.children.clone()
                } else {
                    BTreeSet::new()
                };
                let mut scope: BTreeMap<&str, &Vec<String>> = BTreeMap::new();
                for (alias, abs) in &s.imports {
                    add(abs);
                    scope.insert(alias.as_str(), abs);
                }
                for p in inline_paths(&s.code) {
                    let first = p[0].as_str();
                    if matches!(first, "crate" | "super" | "self") || kids.contains(first) {
                        if let Some(abs) = absolute(&s.here, &p, &kids) {
                            add(&abs);
                        }
                    } else if let Some(base) = scope.get(first) {
                        let mut abs = (*base).clone();
                        abs.extend(p[1..].iter().cloned());
                        add(&abs);
                    } else {
                        for g in &s.globs {
                            let mut abs = g.clone();
                            abs.extend(p.iter().cloned());
                            if mods.contains_key(&abs[..g.len() + 1]) {
                                add(&abs);
                            }
                        }
                    }
                }
            }
            out
        })
        .collect()
}

/// Strongly connected components of more than one module (Tarjan).
fn cycles(g: &[BTreeSet<usize>]) -> Vec<Vec<usize>> {
    struct T<'a> {
        g: &'a [BTreeSet<usize>],
        index: Vec<Option<usize>>,
        low: Vec<usize>,
        on: Vec<bool>,
        stack: Vec<usize>,
        next: usize,
        out: Vec<Vec<usize>>,
    }
    fn visit(t: &mut T, v: usize) {
        t.index[v] = Some(t.next);
        t.low[v] = t.next;
        t.next += 1;
        t.stack.push(v);
        t.on[v] = true;
        for &w in t.g[v].iter() {
            match t.index[w] {
                None => {
                    visit(t, w);
                    t.low[v] = t.low[v].min(t.low[w]);
                }
                Some(iw) if t.on[w] => t.low[v] = t.low[v].min(iw),
                _ => {}
            }
        }
        if Some(t.low[v]) == t.index[v] {
            let mut comp = Vec::new();
            loop {
                let w = t.stack.pop().unwrap();
                t.on[w] = false;
                comp.push(w);
                if w == v {
                    break;
                }
            }
            if comp.len() > 1 {
                t.out.push(comp);
            }
        }
    }
    let n = g.len();
    let mut t = T {
        g,
        index: vec![None; n],
        low: vec![0; n],
        on: vec![false; n],
        stack: Vec::new(),
        next: 0,
        out: Vec::new(),
    };
    for v in 0..n {
        if t.index[v].is_none() {
            visit(&mut t, v);
        }
    }
    t.out
}

fn crates_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

fn report(src: &Path) -> Vec<String> {
    let all = load(src);
    let g = edges(&all);
    cycles(&g)
        .into_iter()
        .map(|comp| {
            let mut names: Vec<String> = comp
                .iter()
                .map(|&i| {
                    let deps: Vec<String> = g[i]
                        .iter()
                        .filter(|j| comp.contains(j))
                        .map(|&j| all[j].file.strip_prefix(src).unwrap().display().to_string())
                        .collect();
                    format!(
                        "{} → {}",
                        all[i].file.strip_prefix(src).unwrap().display(),
                        deps.join(", ")
                    )
                })
                .collect();
            names.sort();
            format!("{}: {}", src.display(), names.join("; "))
        })
        .collect()
}

#[test]
fn no_module_imports_itself_around_a_circle() {
    let mut found = Vec::new();
    let mut crates = 0;
    for e in std::fs::read_dir(crates_dir()).unwrap() {
        let src = e.unwrap().path().join("src");
        if src.is_dir() {
            crates += 1;
            found.extend(report(&src));
        }
    }
    assert!(crates >= 7, "found only {crates} crates");
    assert!(found.is_empty(), "module cycles:\n{}", found.join("\n"));
}

/// The checker finds what it should: a pair of files importing each other,
/// through a `super::` path, a re-export and an inline path.
#[test]
fn the_checker_finds_a_planted_cycle() {
    let dir = std::env::temp_dir().join(format!("fogbank-cycles-{}", std::process::id()));
    let src = dir.join("src");
    std::fs::create_dir_all(src.join("a")).unwrap();
    let write = |p: &str, t: &str| std::fs::write(src.join(p), t).unwrap();
    write("lib.rs", "pub mod a;\npub mod b;\npub use b::Thing;\n");
    write(
        "a/mod.rs",
        "pub mod c;\n// use crate::b; (a comment, not an import)\n",
    );
    write("a/c.rs", "use crate::Thing;\npub fn f() {}\n");
    write(
        "b.rs",
        "pub struct Thing;\npub fn g() { crate::a::c::f() }\n",
    );
    assert!(!report(&src).is_empty(), "a/c.rs ↔ b.rs is a cycle");
    write("b.rs", "pub struct Thing;\n");
    assert!(report(&src).is_empty(), "{:?}", report(&src));
    write("a/mod.rs", "pub mod c;\nuse super::b::Thing;\n");
    write("b.rs", "pub struct Thing;\nuse crate::a;\n");
    assert_eq!(report(&src).len(), 1, "a/mod.rs ↔ b.rs");
    std::fs::remove_dir_all(&dir).ok();
}
