//! pbrt-v4's lexical level: `#` comments to the end of the line, quoted
//! strings (with `\"`, `\\`, `\n`, `\t` escapes), `[` and `]`, and bare
//! words (statement names and numbers). Every token remembers its file and
//! line, so that any later error can name them.

use fogbank_render::error::SceneError;
use std::fmt;
use std::path::PathBuf;
use std::rc::Rc;

/// Where a token starts.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Loc {
    pub file: Rc<PathBuf>,
    pub line: u32,
}

impl fmt::Display for Loc {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}", self.file.display(), self.line)
    }
}

impl Loc {
    /// A scene error at this place.
    pub fn error(&self, msg: impl fmt::Display) -> SceneError {
        SceneError(format!("{self}: {msg}"))
    }
}

#[derive(Clone, Debug, PartialEq)]
pub enum TokenKind {
    /// A quoted string, unescaped.
    Str(String),
    /// A bare word: a statement name, a number or `true`/`false`.
    Word(String),
    Open,
    Close,
}

#[derive(Clone, Debug)]
pub struct Token {
    pub kind: TokenKind,
    pub loc: Loc,
}

impl Token {
    /// The token as written, for messages.
    pub fn describe(&self) -> String {
        match &self.kind {
            TokenKind::Str(s) => format!("\"{s}\""),
            TokenKind::Word(w) => w.clone(),
            TokenKind::Open => "[".into(),
            TokenKind::Close => "]".into(),
        }
    }
}

/// Splits `text` (the contents of `file`) into tokens.
pub fn tokenize(text: &str, file: Rc<PathBuf>) -> Result<Vec<Token>, SceneError> {
    let mut out = Vec::new();
    let mut chars = text.chars().peekable();
    let mut line = 1u32;
    while let Some(&c) = chars.peek() {
        let loc = Loc {
            file: file.clone(),
            line,
        };
        match c {
            '\n' => {
                line += 1;
                chars.next();
            }
            c if c.is_whitespace() => {
                chars.next();
            }
            '#' => {
                while chars.peek().is_some_and(|&c| c != '\n') {
                    chars.next();
                }
            }
            '[' | ']' => {
                chars.next();
                let kind = if c == '[' {
                    TokenKind::Open
                } else {
                    TokenKind::Close
                };
                out.push(Token { kind, loc });
            }
            '"' => {
                chars.next();
                let s = quoted(&mut chars, &mut line).map_err(|m| loc.error(m))?;
                out.push(Token {
                    kind: TokenKind::Str(s),
                    loc,
                });
            }
            _ => {
                let mut w = String::new();
                while let Some(&c) = chars.peek() {
                    if c.is_whitespace() || matches!(c, '"' | '[' | ']' | '#') {
                        break;
                    }
                    w.push(c);
                    chars.next();
                }
                out.push(Token {
                    kind: TokenKind::Word(w),
                    loc,
                });
            }
        }
    }
    Ok(out)
}

/// The rest of a quoted string after its opening quote.
fn quoted(
    chars: &mut std::iter::Peekable<std::str::Chars>,
    line: &mut u32,
) -> Result<String, String> {
    let mut s = String::new();
    loop {
        match chars.next() {
            None => return Err("a string is not closed".into()),
            Some('"') => return Ok(s),
            Some('\n') => return Err("a new line inside a string".into()),
            Some('\\') => match chars.next() {
                Some('n') => s.push('\n'),
                Some('t') => s.push('\t'),
                Some('\\') => s.push('\\'),
                Some('"') => s.push('"'),
                Some('\n') => {
                    *line += 1;
                }
                Some(c) => return Err(format!("unknown escape `\\{c}` in a string")),
                None => return Err("a string is not closed".into()),
            },
            Some(c) => s.push(c),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn kinds(text: &str) -> Vec<TokenKind> {
        tokenize(text, Rc::new("t.pbrt".into()))
            .unwrap()
            .into_iter()
            .map(|t| t.kind)
            .collect()
    }

    #[test]
    fn comments_strings_brackets_and_lines() {
        let toks = tokenize(
            "Shape \"sphere\" # a comment \"not a string\"\n  \"float radius\" [ 2.5 ]",
            Rc::new("t.pbrt".into()),
        )
        .unwrap();
        assert_eq!(toks.len(), 6);
        assert_eq!(toks[2].kind, TokenKind::Str("float radius".into()));
        assert_eq!(toks[2].loc.line, 2);
        assert_eq!(toks[4].kind, TokenKind::Word("2.5".into()));
        assert_eq!(kinds("[1 2]")[0], TokenKind::Open);
        assert_eq!(kinds("\"a\\\"b\"")[0], TokenKind::Str("a\"b".into()));
    }

    #[test]
    fn an_open_string_is_an_error_with_its_line() {
        let e = tokenize("\n\n\"abc", Rc::new("x.pbrt".into())).unwrap_err();
        assert!(e.0.starts_with("x.pbrt:3:"), "{}", e.0);
    }
}
