//! Parameter lists: `"type name" value` or `"type name" [ values ]`. The
//! types are pbrt-v4's (`integer`, `float`, `point2`, `vector2`, `point3`,
//! `vector3`, `normal`, `bool`, `string`, `texture`, `rgb`, `blackbody`,
//! `spectrum`); pbrt-v3's `point`, `color` and friends are refused. As in
//! pbrt, a parameter nobody asks for is an error (a misspelt name or the
//! wrong type would otherwise be silently ignored): [`ParamList::finish`].

use super::tokenizer::{Loc, Token, TokenKind};
use fogbank_render::error::SceneError;
use std::cell::Cell;

/// The most values one parameter may hold (a 256³ grid is 16.8 M).
const MAX_VALUES: usize = 1 << 27;

#[derive(Clone, Debug, PartialEq)]
pub enum Values {
    Nums(Vec<f64>),
    Strs(Vec<String>),
    Bools(Vec<bool>),
}

#[derive(Clone, Debug)]
pub struct Param {
    pub ty: String,
    pub name: String,
    pub values: Values,
    pub loc: Loc,
    used: Cell<bool>,
}

/// How many numbers one element of a numeric type holds.
fn arity(ty: &str) -> Option<usize> {
    Some(match ty {
        "integer" | "float" | "blackbody" => 1,
        "point2" | "vector2" => 2,
        "point3" | "vector3" | "normal" | "rgb" => 3,
        _ => return None,
    })
}

impl Param {
    /// The parameter declared by the string token `decl` with `values`
    /// (the tokens of one value or of a bracketed list, brackets removed).
    pub fn new(decl: &Token, values: Vec<Token>) -> Result<Param, SceneError> {
        let loc = decl.loc.clone();
        let TokenKind::Str(d) = &decl.kind else {
            return Err(loc.error(format!(
                "expected a parameter \"type name\", found {}",
                decl.describe()
            )));
        };
        let mut words = d.split_whitespace();
        let (Some(ty), Some(name), None) = (words.next(), words.next(), words.next()) else {
            return Err(loc.error(format!("parameter \"{d}\" is not \"type name\"")));
        };
        if values.len() > MAX_VALUES {
            return Err(loc.error(format!(
                "parameter \"{d}\" has more than {MAX_VALUES} values"
            )));
        }
        let values =
            typed_values(ty, &values).map_err(|m| loc.error(format!("parameter \"{d}\": {m}")))?;
        Ok(Param {
            ty: ty.into(),
            name: name.into(),
            values,
            loc,
            used: Cell::new(false),
        })
    }

    fn nums(&self) -> &[f64] {
        match &self.values {
            Values::Nums(v) => v,
            _ => &[],
        }
    }

    /// Marks this parameter used (one that may go unused).
    pub fn mark_used(&self) {
        self.used.set(true);
    }

    pub fn error(&self, msg: impl std::fmt::Display) -> SceneError {
        self.loc
            .error(format!("parameter \"{} {}\": {msg}", self.ty, self.name))
    }
}

fn typed_values(ty: &str, toks: &[Token]) -> Result<Values, String> {
    let word = |t: &Token| match &t.kind {
        TokenKind::Word(w) => Some(w.clone()),
        _ => None,
    };
    let string = |t: &Token| match &t.kind {
        TokenKind::Str(s) => Some(s.clone()),
        _ => None,
    };
    let numbers = || -> Result<Vec<f64>, String> {
        toks.iter()
            .map(|t| {
                word(t)
                    .and_then(|w| w.parse::<f64>().ok())
                    .filter(|x| x.is_finite())
                    .ok_or_else(|| format!("{} is not a finite number", t.describe()))
            })
            .collect()
    };
    match ty {
        "spectrum" if toks.first().is_some_and(|t| string(t).is_some()) => {
            let s: Option<Vec<String>> = toks.iter().map(string).collect();
            match s {
                Some(s) if s.len() == 1 => Ok(Values::Strs(s)),
                _ => Err("a named spectrum is one string".into()),
            }
        }
        "spectrum" => {
            let v = numbers()?;
            if v.len() < 4 || v.len() % 2 != 0 {
                return Err("a spectrum is [λ value …] pairs, two or more".into());
            }
            Ok(Values::Nums(v))
        }
        "string" | "texture" => toks
            .iter()
            .map(|t| string(t).ok_or_else(|| format!("{} is not a quoted string", t.describe())))
            .collect::<Result<_, _>>()
            .map(Values::Strs),
        "bool" => toks
            .iter()
            .map(|t| match (word(t).or_else(|| string(t))).as_deref() {
                Some("true") => Ok(true),
                Some("false") => Ok(false),
                _ => Err(format!("{} is not true or false", t.describe())),
            })
            .collect::<Result<_, _>>()
            .map(Values::Bools),
        _ => {
            let n = arity(ty).ok_or_else(|| format!("unknown parameter type `{ty}`"))?;
            let v = numbers()?;
            if v.is_empty() || v.len() % n != 0 {
                return Err(format!("{} values, not a multiple of {n}", v.len()));
            }
            if ty == "integer" && v.iter().any(|x| x.fract() != 0.0) {
                return Err("an integer has no fraction".into());
            }
            Ok(Values::Nums(v))
        }
    }
}

/// A statement's parameters; lookups mark them used.
#[derive(Clone, Debug, Default)]
pub struct ParamList {
    pub params: Vec<Param>,
}

impl ParamList {
    /// Adds `p`, refusing a second parameter of the same name.
    pub fn push(&mut self, p: Param) -> Result<(), SceneError> {
        if self.params.iter().any(|q| q.name == p.name) {
            return Err(p
                .loc
                .error(format!("parameter \"{}\" is given twice", p.name)));
        }
        self.params.push(p);
        Ok(())
    }

    /// The parameter `name` if its type is one of `types` (marking it used).
    pub fn lookup(&self, name: &str, types: &[&str]) -> Option<&Param> {
        let p = self
            .params
            .iter()
            .find(|p| p.name == name && types.contains(&p.ty.as_str()))?;
        p.used.set(true);
        Some(p)
    }

    /// Whether a parameter `name` of any type is present (not a use).
    pub fn has(&self, name: &str) -> bool {
        self.params.iter().any(|p| p.name == name)
    }

    /// The numbers of `name` of type `ty`, all of them.
    pub fn nums(&self, ty: &str, name: &str) -> Option<&[f64]> {
        self.lookup(name, &[ty]).map(|p| p.nums())
    }

    /// One number of type `ty` (`float` or `integer`).
    pub fn one(&self, ty: &str, name: &str) -> Result<Option<f64>, SceneError> {
        let Some(p) = self.lookup(name, &[ty]) else {
            return Ok(None);
        };
        match p.nums() {
            [x] => Ok(Some(*x)),
            v => Err(p.error(format!("needs one value, has {}", v.len()))),
        }
    }

    pub fn float(&self, name: &str, default: f64) -> Result<f64, SceneError> {
        Ok(self.one("float", name)?.unwrap_or(default))
    }

    pub fn int(&self, name: &str, default: i64) -> Result<i64, SceneError> {
        Ok(self
            .one("integer", name)?
            .map(|x| x as i64)
            .unwrap_or(default))
    }

    /// One 3-vector of any of pbrt's 3D types.
    pub fn vec3(&self, name: &str) -> Result<Option<[f64; 3]>, SceneError> {
        let Some(p) = self.lookup(name, &["point3", "vector3", "normal"]) else {
            return Ok(None);
        };
        match p.nums() {
            [a, b, c] => Ok(Some([*a, *b, *c])),
            v => Err(p.error(format!("needs one 3-vector, has {} numbers", v.len()))),
        }
    }

    pub fn string(&self, name: &str) -> Result<Option<&str>, SceneError> {
        let Some(p) = self.lookup(name, &["string"]) else {
            return Ok(None);
        };
        match &p.values {
            Values::Strs(s) if s.len() == 1 => Ok(Some(&s[0])),
            _ => Err(p.error("needs one string")),
        }
    }

    pub fn bool(&self, name: &str, default: bool) -> Result<bool, SceneError> {
        let Some(p) = self.lookup(name, &["bool"]) else {
            return Ok(default);
        };
        match &p.values {
            Values::Bools(b) if b.len() == 1 => Ok(b[0]),
            _ => Err(p.error("needs one bool")),
        }
    }

    /// Marks every parameter used (a statement approximated as a whole).
    pub fn mark_all_used(&self) {
        for p in &self.params {
            p.used.set(true);
        }
    }

    /// The first parameter nobody used, as pbrt's error: `what` names the
    /// statement (`Shape "sphere"`).
    pub fn finish(&self, what: &str) -> Result<(), SceneError> {
        match self.params.iter().find(|p| !p.used.get()) {
            None => Ok(()),
            Some(p) => Err(p.loc.error(format!(
                "{what}: parameter \"{} {}\" is not used (misspelt, of the wrong type, or not supported)",
                p.ty, p.name
            ))),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pbrt::tokenizer::tokenize;
    use std::rc::Rc;

    fn param(text: &str) -> Result<Param, SceneError> {
        let toks = tokenize(text, Rc::new("p.pbrt".into())).unwrap();
        let vals = toks[1..]
            .iter()
            .filter(|t| !matches!(t.kind, TokenKind::Open | TokenKind::Close))
            .cloned()
            .collect();
        Param::new(&toks[0], vals)
    }

    #[test]
    fn types_and_sizes() {
        assert_eq!(
            param("\"float r\" 2").unwrap().values,
            Values::Nums(vec![2.0])
        );
        assert_eq!(
            param("\"bool b\" \"true\"").unwrap().values,
            Values::Bools(vec![true])
        );
        assert!(param("\"rgb c\" [1 2]").is_err());
        assert!(param("\"integer n\" [1.5]").is_err());
        assert!(param("\"point p\" [1 2 3]")
            .unwrap_err()
            .0
            .contains("unknown parameter type"));
        assert!(param("\"color c\" [1 2 3]").is_err());
        assert!(param("\"spectrum s\" [400 1 700]").is_err());
        assert!(param("\"float x\" [nan]").is_err());
    }

    #[test]
    fn an_unused_parameter_is_an_error_naming_it() {
        let mut l = ParamList::default();
        l.push(param("\"float radius\" 1").unwrap()).unwrap();
        l.push(param("\"float radiu\" 1").unwrap()).unwrap();
        assert_eq!(l.float("radius", 0.0).unwrap(), 1.0);
        let e = l.finish("Shape \"sphere\"").unwrap_err().0;
        assert!(e.starts_with("p.pbrt:1:") && e.contains("radiu"), "{e}");
    }
}
