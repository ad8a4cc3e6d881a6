//! The token stream of a scene and the files it includes. `Include`
//! splices the included file's tokens in place, so a statement (or a
//! parameter list) may continue across the end of an included file, as
//! pbrt-v4 reads it. A relative name resolves against the including
//! file's folder and then the top-level file's (pbrt's search directory).

use super::tokenizer::{tokenize, Loc, Token, TokenKind};
use fogbank_render::error::SceneError;
use std::path::{Path, PathBuf};
use std::rc::Rc;

/// Deeper nesting of `Include` is taken for a cycle.
const MAX_INCLUDE_DEPTH: usize = 32;

pub struct Cursor {
    /// Per open file: its tokens and the next one's index.
    stack: Vec<(Vec<Token>, usize)>,
    top_dir: PathBuf,
}

impl Cursor {
    /// The tokens of `text`, the contents of `file`.
    pub fn new(text: &str, file: &Path) -> Result<Cursor, SceneError> {
        let toks = tokenize(text, Rc::new(file.to_path_buf()))?;
        Ok(Cursor {
            stack: vec![(toks, 0)],
            top_dir: file.parent().map(Path::to_path_buf).unwrap_or_default(),
        })
    }

    /// The folder of the top-level file.
    pub fn top_dir(&self) -> &Path {
        &self.top_dir
    }

    fn drop_finished(&mut self) {
        while self.stack.len() > 1 && self.stack.last().is_some_and(|(t, i)| *i >= t.len()) {
            self.stack.pop();
        }
    }

    pub fn peek(&mut self) -> Option<&Token> {
        self.drop_finished();
        let (toks, i) = self.stack.last()?;
        toks.get(*i)
    }

    pub fn next_token(&mut self) -> Option<Token> {
        self.drop_finished();
        let (toks, i) = self.stack.last_mut()?;
        let t = toks.get(*i).cloned();
        *i += 1;
        t
    }

    /// The next token, which must exist: `what` says what was expected.
    pub fn expect(&mut self, at: &Loc, what: &str) -> Result<Token, SceneError> {
        self.next_token()
            .ok_or_else(|| at.error(format!("the file ends where {what} was expected")))
    }

    /// A quoted string.
    pub fn string(&mut self, at: &Loc, what: &str) -> Result<(String, Loc), SceneError> {
        let t = self.expect(at, what)?;
        match t.kind {
            TokenKind::Str(s) => Ok((s, t.loc)),
            _ => Err(t
                .loc
                .error(format!("expected {what}, found {}", t.describe()))),
        }
    }

    /// `n` numbers, bare or in one bracketed list.
    pub fn numbers(&mut self, at: &Loc, n: usize, what: &str) -> Result<Vec<f64>, SceneError> {
        let bracket = self.peek().is_some_and(|t| t.kind == TokenKind::Open);
        if bracket {
            self.next_token();
        }
        let mut v = Vec::with_capacity(n);
        for _ in 0..n {
            let t = self.expect(at, what)?;
            let x = match &t.kind {
                TokenKind::Word(w) => w.parse::<f64>().ok().filter(|x| x.is_finite()),
                _ => None,
            };
            v.push(x.ok_or_else(|| {
                t.loc
                    .error(format!("{what}: {} is not a finite number", t.describe()))
            })?);
        }
        if bracket {
            let t = self.expect(at, "]")?;
            if t.kind != TokenKind::Close {
                return Err(t.loc.error(format!("{what} takes {n} numbers")));
            }
        }
        Ok(v)
    }

    /// Splices the tokens of the file `name` (named at `at`) in here.
    pub fn include(&mut self, name: &str, at: &Loc) -> Result<(), SceneError> {
        if self.stack.len() > MAX_INCLUDE_DEPTH {
            return Err(at.error(format!(
                "Include \"{name}\": nested deeper than {MAX_INCLUDE_DEPTH} (an include cycle?)"
            )));
        }
        let path = self.resolve(name, at);
        if name.ends_with(".gz") {
            return Err(at.error(format!(
                "Include \"{name}\": gzip-compressed scene files are not supported; decompress it"
            )));
        }
        let text = std::fs::read_to_string(&path)
            .map_err(|e| at.error(format!("Include \"{name}\": {}: {e}", path.display())))?;
        let toks = tokenize(&text, Rc::new(path))?;
        self.stack.push((toks, 0));
        Ok(())
    }

    /// A file name relative to the including file's folder, else the top
    /// file's.
    pub fn resolve(&self, name: &str, at: &Loc) -> PathBuf {
        resolve(name, at, &self.top_dir)
    }
}

/// The file `name`, named at `at`: an absolute name as is, else beside the
/// file that names it if it exists there, else in `top_dir` (the top-level
/// scene's folder, pbrt's search directory).
pub fn resolve(name: &str, at: &Loc, top_dir: &Path) -> PathBuf {
    let p = Path::new(name);
    if p.is_absolute() {
        return p.to_path_buf();
    }
    let beside = at
        .file
        .parent()
        .map(|d| d.join(p))
        .unwrap_or_else(|| p.to_path_buf());
    if beside.exists() {
        beside
    } else {
        top_dir.join(p)
    }
}
