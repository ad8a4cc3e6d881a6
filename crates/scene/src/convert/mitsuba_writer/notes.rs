//! The notes a conversion to Mitsuba gathers, and the ids media get.

/// What a conversion left out or changed, one line each.
#[derive(Default)]
pub struct Notes(pub Vec<String>);

impl Notes {
    pub fn note(&mut self, s: impl Into<String>) {
        self.0.push(s.into());
    }
}

/// The id of medium `i`.
pub fn medium_id(i: usize) -> String {
    format!("medium{i}")
}
