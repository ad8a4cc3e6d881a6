//! An estimator's options as a scene file, the command line or Python gives
//! them: keys with untyped-until-read values. Each estimator's parameter
//! struct reads the keys it takes ([`super::plugin::EstimatorPlugin`]); the
//! registry refuses any other key before it does.

use std::fmt;

/// One option's value as given.
#[derive(Clone, Debug, PartialEq)]
pub enum OptionValue {
    Int(i64),
    Float(f64),
    Bool(bool),
    Text(String),
}

impl OptionValue {
    /// A value spelled on the command line (`samples=20`, `roulette=0.1`,
    /// `clip=true`, `jitter=uniform`): a number or a boolean when it reads
    /// as one, else text.
    pub fn from_text(v: &str) -> OptionValue {
        if let Ok(i) = v.parse::<i64>() {
            OptionValue::Int(i)
        } else if let Ok(x) = v.parse::<f64>() {
            OptionValue::Float(x)
        } else if let Ok(b) = v.parse::<bool>() {
            OptionValue::Bool(b)
        } else {
            OptionValue::Text(v.to_string())
        }
    }
}

impl fmt::Display for OptionValue {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        match self {
            OptionValue::Int(i) => write!(f, "{i}"),
            OptionValue::Float(x) => write!(f, "{x}"),
            OptionValue::Bool(b) => write!(f, "{b}"),
            OptionValue::Text(s) => write!(f, "`{s}`"),
        }
    }
}

/// Keys and values, in the order given; a key set twice keeps its last value.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Options(Vec<(String, OptionValue)>);

impl Options {
    pub fn set(&mut self, key: &str, value: OptionValue) {
        self.0.retain(|(k, _)| k != key);
        self.0.push((key.to_string(), value));
    }

    /// The options with `key` set to `value`.
    pub fn with(mut self, key: &str, value: OptionValue) -> Options {
        self.set(key, value);
        self
    }

    pub fn get(&self, key: &str) -> Option<&OptionValue> {
        self.0.iter().find(|(k, _)| k == key).map(|(_, v)| v)
    }

    pub fn iter(&self) -> impl Iterator<Item = (&str, &OptionValue)> {
        self.0.iter().map(|(k, v)| (k.as_str(), v))
    }

    fn expected(key: &str, what: &str, v: &OptionValue) -> String {
        format!("{key}: {v} is not {what}")
    }

    /// A non-negative integer.
    pub fn count(&self, key: &str) -> Result<Option<u32>, String> {
        match self.get(key) {
            None => Ok(None),
            Some(OptionValue::Int(i)) if u32::try_from(*i).is_ok() => Ok(Some(*i as u32)),
            Some(v) => Err(Self::expected(key, "a count", v)),
        }
    }

    /// A number (an integer reads as one).
    pub fn number(&self, key: &str) -> Result<Option<f32>, String> {
        match self.get(key) {
            None => Ok(None),
            Some(OptionValue::Int(i)) => Ok(Some(*i as f32)),
            Some(OptionValue::Float(x)) => Ok(Some(*x as f32)),
            Some(v) => Err(Self::expected(key, "a number", v)),
        }
    }

    pub fn flag(&self, key: &str) -> Result<Option<bool>, String> {
        match self.get(key) {
            None => Ok(None),
            Some(OptionValue::Bool(b)) => Ok(Some(*b)),
            Some(v) => Err(Self::expected(key, "true or false", v)),
        }
    }

    pub fn text(&self, key: &str) -> Result<Option<&str>, String> {
        match self.get(key) {
            None => Ok(None),
            Some(OptionValue::Text(s)) => Ok(Some(s)),
            Some(v) => Err(Self::expected(key, "a name", v)),
        }
    }
}
