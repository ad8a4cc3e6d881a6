//! Edits of a scene's text that fail when they miss. An experiment that
//! adapts a shipped scene (a smaller film, its own integrator) must stop
//! with an error naming the scene and the edit when that scene changes,
//! not run on the unedited text.

use std::path::Path;

/// A scene's TOML text with where it came from, for messages.
pub struct SceneText {
    text: String,
    origin: String,
}

impl SceneText {
    /// The scene file at `path`; a missing file is an error naming it.
    pub fn read(path: &Path) -> Result<SceneText, String> {
        let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
        Ok(SceneText {
            text,
            origin: path.display().to_string(),
        })
    }

    /// Text an experiment wrote itself; `origin` names it in messages.
    pub fn new(text: impl Into<String>, origin: &str) -> SceneText {
        SceneText {
            text: text.into(),
            origin: origin.into(),
        }
    }

    /// Replaces every occurrence of `from` by `to`; an error when there is
    /// none.
    pub fn replace(self, from: &str, to: &str) -> Result<SceneText, String> {
        if !self.text.contains(from) {
            return Err(format!(
                "{}: the experiment's edit expects {from:?}, which the scene does not contain",
                self.origin
            ));
        }
        Ok(SceneText {
            text: self.text.replace(from, to),
            origin: self.origin,
        })
    }

    pub fn text(self) -> String {
        self.text
    }
}

#[cfg(test)]
mod scene_edit_test {
    use super::*;

    #[test]
    fn an_edit_that_matches_nothing_names_the_scene_and_the_edit() {
        let s = SceneText::new("width = 480\nheight = 400\n", "explosion.toml");
        let edited = s.replace("width = 480", "width = 128").unwrap();
        assert_eq!(edited.text(), "width = 128\nheight = 400\n");
        let e = SceneText::new("width = 320\n", "explosion.toml")
            .replace("width = 480", "width = 128")
            .err()
            .unwrap();
        assert!(
            e.contains("explosion.toml") && e.contains("width = 480"),
            "{e}"
        );
        let e = SceneText::read(Path::new("/nonexistent/scene.toml"))
            .err()
            .unwrap();
        assert!(e.contains("/nonexistent/scene.toml"), "{e}");
    }
}
