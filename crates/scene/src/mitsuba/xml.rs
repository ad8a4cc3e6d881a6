//! Reading a Mitsuba 3 XML file into an owned element tree: `include`d
//! files spliced in, `default` values and `$name` substitution applied,
//! relative file names resolved as Mitsuba's `FileResolver` does. Every
//! element keeps its file and line for messages.
//!
//! Mitsuba's resolver is a list of folders searched in order: loading a
//! scene file puts the file's folder before the working directory; a
//! `<path>` puts its folder first; an `<include>` is looked for with the
//! including file's folder put first, in a copy of the list that the
//! included file's own `<path>`s change and that is dropped after it. The
//! file names of plugins (meshes, textures, volumes) are resolved when the
//! scene is built, with the top-level list: relative to the top-level
//! scene's folder and its `<path>`s, never to the included file that names
//! them.

use fogbank_render::error::SceneError;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Largest XML file read (bigger ones are refused before reading).
const MAX_FILE_BYTES: u64 = 64 << 20;
/// How deep `include`s may nest (a cycle stops here).
const MAX_INCLUDE_DEPTH: u32 = 16;

#[derive(Clone, Debug)]
pub struct Element {
    pub tag: String,
    pub attrs: Vec<(String, String)>,
    pub children: Vec<Element>,
    /// The file the element is written in, for messages and relative paths.
    pub file: Arc<PathBuf>,
    pub line: u32,
}

impl Element {
    pub fn attr(&self, name: &str) -> Option<&str> {
        self.attrs
            .iter()
            .find(|(k, _)| k == name)
            .map(|(_, v)| v.as_str())
    }

    /// `file:line: <tag type="…" name="…">` for messages.
    pub fn at(&self) -> String {
        let mut s = format!("{}:{}: <{}", self.file.display(), self.line, self.tag);
        for key in ["type", "name", "id"] {
            if let Some(v) = self.attr(key) {
                s += &format!(" {key}=\"{v}\"");
            }
        }
        s + ">"
    }

    pub fn error(&self, what: impl std::fmt::Display) -> SceneError {
        SceneError(format!("{}: {what}", self.at()))
    }
}

/// The scene root with the folders its plugins' file names resolve in.
#[derive(Clone, Debug)]
pub struct Document {
    pub root: Element,
    /// Mitsuba's resolver after the top-level file: its `<path>` folders,
    /// the latest first, then the file's folder, then the working directory.
    pub paths: Vec<PathBuf>,
}

/// Reads `path` with `defines` (name, value) overriding its `default`s.
pub fn read(path: &Path, defines: &[(String, String)]) -> Result<Document, SceneError> {
    document(path, defines, |scope| read_file(path, scope))
}

/// What a file is read in: the variables (`<default>`s and defines, shared
/// with the files it includes), the resolver's folders (each include sees
/// its own copy) and how deep in includes it stands.
struct Scope<'a> {
    vars: &'a mut HashMap<String, String>,
    paths: &'a mut Vec<PathBuf>,
    depth: u32,
}

/// A document read by `read` from the top-level file `path`, with `defines`
/// as its starting variables.
fn document(
    path: &Path,
    defines: &[(String, String)],
    read: impl FnOnce(&mut Scope) -> Result<Element, SceneError>,
) -> Result<Document, SceneError> {
    let mut vars: HashMap<String, String> = defines.iter().cloned().collect();
    let mut paths = vec![folder_of(path)];
    if let Ok(cwd) = std::env::current_dir() {
        paths.push(cwd);
    }
    let root = read(&mut Scope {
        vars: &mut vars,
        paths: &mut paths,
        depth: 0,
    })?;
    Ok(Document { root, paths })
}

fn read_file(path: &Path, scope: &mut Scope) -> Result<Element, SceneError> {
    let err = |m: String| SceneError(format!("{}: {m}", path.display()));
    let len = std::fs::metadata(path)
        .map_err(|e| err(e.to_string()))?
        .len();
    if len > MAX_FILE_BYTES {
        return Err(err(format!(
            "{len} bytes, more than the {} MiB an XML scene may have",
            MAX_FILE_BYTES >> 20
        )));
    }
    let text = std::fs::read_to_string(path).map_err(|e| err(e.to_string()))?;
    read_text(&text, path, scope)
}

/// [`read`] of the text of file `path` (which names it in messages and
/// anchors relative file names).
pub fn read_str(
    text: &str,
    path: &Path,
    defines: &[(String, String)],
) -> Result<Document, SceneError> {
    document(path, defines, |scope| read_text(text, path, scope))
}

fn read_text(text: &str, path: &Path, scope: &mut Scope) -> Result<Element, SceneError> {
    let err = |m: String| SceneError(format!("{}: {m}", path.display()));
    let opts = roxmltree::ParsingOptions {
        allow_dtd: false,
        ..Default::default()
    };
    let doc = roxmltree::Document::parse_with_options(text, opts)
        .map_err(|e| err(format!("not well-formed XML: {e}")))?;
    let file = Arc::new(path.to_path_buf());
    let root = convert(&doc, doc.root_element(), &file);
    if root.tag != "scene" {
        return Err(root.error("the root element must be <scene>"));
    }
    let mut scene = Element {
        children: Vec::new(),
        ..root.clone()
    };
    // Defaults first, in document order, so that `$name` anywhere in the
    // file sees them (a value given from outside wins).
    for c in root.children.iter().filter(|c| c.tag == "default") {
        let (Some(name), Some(value)) = (c.attr("name"), c.attr("value")) else {
            return Err(c.error("<default> needs `name` and `value`"));
        };
        scope
            .vars
            .entry(name.to_string())
            .or_insert_with(|| value.to_string());
    }
    for mut c in root.children {
        substitute(&mut c, scope.vars)?;
        match c.tag.as_str() {
            "default" => {}
            "path" => {
                let v = c
                    .attr("value")
                    .ok_or_else(|| c.error("<path> needs `value`"))?;
                // Beside the file first, then through the resolver.
                let beside = folder_of(&c.file).join(v);
                let folder = if beside.is_dir() {
                    beside
                } else {
                    resolve(scope.paths, v)
                        .filter(|p| p.is_dir())
                        .ok_or_else(|| c.error(format!("<path>: folder `{v}` not found")))?
                };
                scope.paths.insert(0, folder);
            }
            "include" => {
                if scope.depth >= MAX_INCLUDE_DEPTH {
                    return Err(c.error(format!(
                        "includes nest deeper than {MAX_INCLUDE_DEPTH} (a cycle?)"
                    )));
                }
                let f = c
                    .attr("filename")
                    .ok_or_else(|| c.error("<include> needs `filename`"))?;
                let mut local = scope.paths.clone();
                local.insert(0, folder_of(&c.file));
                let inc = find_file(&local, f).map_err(|e| c.error(e))?;
                let sub = read_file(
                    &inc,
                    &mut Scope {
                        vars: scope.vars,
                        paths: &mut local,
                        depth: scope.depth + 1,
                    },
                )?;
                scene.children.extend(sub.children);
            }
            _ => scene.children.push(c),
        }
    }
    Ok(scene)
}

fn convert(doc: &roxmltree::Document, n: roxmltree::Node, file: &Arc<PathBuf>) -> Element {
    Element {
        tag: n.tag_name().name().to_string(),
        attrs: n
            .attributes()
            .map(|a| (a.name().to_string(), a.value().to_string()))
            .collect(),
        children: n
            .children()
            .filter(|c| c.is_element())
            .map(|c| convert(doc, c, file))
            .collect(),
        file: file.clone(),
        line: doc.text_pos_at(n.range().start).row,
    }
}

/// `$name` in attribute values replaced by the variable's value.
fn substitute(e: &mut Element, vars: &HashMap<String, String>) -> Result<(), SceneError> {
    for i in 0..e.attrs.len() {
        let v = &e.attrs[i].1;
        if !v.contains('$') {
            continue;
        }
        let mut out = String::new();
        let mut rest = v.as_str();
        while let Some(k) = rest.find('$') {
            out += &rest[..k];
            let tail = &rest[k + 1..];
            let end = tail
                .find(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
                .unwrap_or(tail.len());
            let name = &tail[..end];
            let value = vars.get(name).ok_or_else(|| {
                e.error(format!("`${name}` has no <default> and no value was given"))
            })?;
            out += value;
            rest = &tail[end..];
        }
        out += rest;
        e.attrs[i].1 = out;
    }
    for c in &mut e.children {
        substitute(c, vars)?;
    }
    Ok(())
}

/// The folder holding `file` (`.` for a bare file name).
fn folder_of(file: &Path) -> PathBuf {
    match file.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

/// `name` in the first folder of `paths` that has it (Mitsuba's
/// `FileResolver::resolve`); an absolute `name` as it is, if it exists.
fn resolve(paths: &[PathBuf], name: &str) -> Option<PathBuf> {
    if Path::new(name).is_absolute() {
        return Some(PathBuf::from(name)).filter(|p| p.exists());
    }
    paths.iter().map(|p| p.join(name)).find(|p| p.exists())
}

/// The file `name` through the resolver `paths`, or an error listing the
/// folders looked in.
pub fn find_file(paths: &[PathBuf], name: &str) -> Result<PathBuf, String> {
    resolve(paths, name).ok_or_else(|| {
        let looked: Vec<String> = paths.iter().map(|p| p.display().to_string()).collect();
        format!(
            "file `{name}` not found (looked in {}: the top-level scene's folder, its <path> \
             folders and the working directory, as Mitsuba does; an included file's own folder \
             counts only for further <include>s)",
            looked.join(", ")
        )
    })
}
