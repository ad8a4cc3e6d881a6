//! Notices of approximations, each printed once per scene (to standard
//! error, where the command's other progress goes), never silently.

use std::collections::BTreeSet;

#[derive(Debug, Default)]
pub struct Warnings {
    seen: BTreeSet<String>,
}

impl Warnings {
    /// Prints `msg` unless it was printed before.
    pub fn warn(&mut self, msg: impl Into<String>) {
        let msg = msg.into();
        if self.seen.insert(msg.clone()) {
            eprintln!("warning: pbrt: {msg}");
        }
    }

    /// Everything warned so far (for tests).
    pub fn all(&self) -> impl Iterator<Item = &str> {
        self.seen.iter().map(String::as_str)
    }
}
