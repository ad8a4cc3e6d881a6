//! A plugin element (`<bsdf type="diffuse">`, …) read property by
//! property. Each read marks its child element used; [`Plugin::finish`]
//! refuses whatever is left, so a parameter fogbank would ignore is an
//! error naming it and its line, never silently dropped.

use super::transform::read_transform;
use super::values::{numbers, spectrum, xyz};
use super::xml::{find_file, Document, Element};
use fogbank_image::spectrum::SpectrumUse;
use fogbank_render::error::SceneError;
use glam::DMat4;
use std::cell::RefCell;
use std::collections::HashMap;

/// Elements with an `id` at the top level, for `<ref>`.
pub type Ids<'a> = HashMap<&'a str, &'a Element>;

pub struct Plugin<'a> {
    pub e: &'a Element,
    pub ty: &'a str,
    ids: &'a Ids<'a>,
    used: RefCell<Vec<bool>>,
}

/// Tags of nested objects (a child plugin, or a `<ref>` to one).
const OBJECTS: [&str; 13] = [
    "bsdf",
    "texture",
    "emitter",
    "medium",
    "phase",
    "volume",
    "rfilter",
    "sampler",
    "film",
    "shape",
    "sensor",
    "integrator",
    "ref",
];

impl<'a> Plugin<'a> {
    pub fn new(e: &'a Element, ids: &'a Ids<'a>) -> Result<Plugin<'a>, SceneError> {
        let ty = e
            .attr("type")
            .ok_or_else(|| e.error("needs a `type` attribute"))?;
        Ok(Plugin {
            e,
            ty,
            ids,
            used: RefCell::new(vec![false; e.children.len()]),
        })
    }

    pub fn error(&self, what: impl std::fmt::Display) -> SceneError {
        self.e.error(what)
    }

    /// The unused child `<tag name="name">`, marked used.
    fn take(&self, tags: &[&str], name: &str) -> Option<&'a Element> {
        let mut used = self.used.borrow_mut();
        let (i, c) = self.e.children.iter().enumerate().find(|(i, c)| {
            !used[*i] && tags.contains(&c.tag.as_str()) && c.attr("name") == Some(name)
        })?;
        used[i] = true;
        Some(c)
    }

    fn value(c: &Element) -> Result<&str, SceneError> {
        c.attr("value")
            .ok_or_else(|| c.error("needs a `value` attribute"))
    }

    pub fn float(&self, name: &str) -> Result<Option<f64>, SceneError> {
        let Some(c) = self.take(&["float", "integer"], name) else {
            return Ok(None);
        };
        let v = Self::value(c)?;
        v.trim()
            .parse::<f64>()
            .ok()
            .filter(|x| x.is_finite())
            .map(Some)
            .ok_or_else(|| c.error(format!("`{v}` is not a finite number")))
    }

    pub fn integer(&self, name: &str) -> Result<Option<i64>, SceneError> {
        let Some(c) = self.take(&["integer"], name) else {
            return Ok(None);
        };
        let v = Self::value(c)?;
        v.trim()
            .parse::<i64>()
            .map(Some)
            .map_err(|_| c.error(format!("`{v}` is not an integer")))
    }

    pub fn boolean(&self, name: &str) -> Result<Option<bool>, SceneError> {
        let Some(c) = self.take(&["boolean"], name) else {
            return Ok(None);
        };
        match Self::value(c)?.trim() {
            "true" => Ok(Some(true)),
            "false" => Ok(Some(false)),
            v => Err(c.error(format!("`{v}` is not true or false"))),
        }
    }

    /// The required `filename`, through the document's resolver (the
    /// top-level scene's folder and its `<path>`s, as Mitsuba resolves it).
    pub fn filename(&self, doc: &Document) -> Result<std::path::PathBuf, SceneError> {
        let f = self
            .string("filename")?
            .ok_or_else(|| self.error("needs `filename`"))?;
        find_file(&doc.paths, f).map_err(|m| self.error(m))
    }

    pub fn string(&self, name: &str) -> Result<Option<&'a str>, SceneError> {
        self.take(&["string"], name).map(Self::value).transpose()
    }

    /// `<rgb>`, `<float>` or `<spectrum>` (a constant or wavelength:value
    /// pairs, converted as Mitsuba's RGB variants convert them for `usage`,
    /// see [`fogbank_image::spectrum`]): three channels.
    pub fn rgb(&self, name: &str, usage: SpectrumUse) -> Result<Option<[f32; 3]>, SceneError> {
        let Some(c) = self.take(&["rgb", "spectrum", "float"], name) else {
            return Ok(None);
        };
        if c.tag == "spectrum" && c.attr("type") == Some("blackbody") {
            return Err(c.error(
                "blackbody spectra exist in Mitsuba's spectral variants only; fogbank renders in RGB \
                 as Mitsuba's RGB variants do, which refuse them too",
            ));
        }
        if c.tag == "spectrum" && c.attr("filename").is_some() {
            return Err(c.error(
                "spectra from files are not read: give the wavelength:value pairs in `value`",
            ));
        }
        let v = Self::value(c)?;
        if c.tag == "spectrum" {
            return spectrum(v, usage)
                .map(|rgb| Some(rgb.map(|x| x as f32)))
                .map_err(|e| c.error(e));
        }
        let xs = numbers(v).map_err(|e| c.error(e))?;
        match (c.tag.as_str(), xs.as_slice()) {
            (_, [x]) => Ok(Some([*x as f32; 3])),
            ("rgb", [r, g, b]) => Ok(Some([*r as f32, *g as f32, *b as f32])),
            _ => Err(c.error(format!("`{v}` is not one value or three"))),
        }
    }

    /// `<point>`/`<vector>` with `x`, `y`, `z` or `value`.
    pub fn vector(&self, name: &str) -> Result<Option<[f64; 3]>, SceneError> {
        let Some(c) = self.take(&["point", "vector"], name) else {
            return Ok(None);
        };
        xyz(c, 0.0).map(Some)
    }

    pub fn transform(&self, name: &str) -> Result<Option<DMat4>, SceneError> {
        self.take(&["transform"], name)
            .map(read_transform)
            .transpose()
    }

    /// The nested object `<tag name="name">` or `<ref name="name" id>`
    /// (with `name = ""`: one without a name), resolved.
    pub fn object(&self, tag: &str, name: &str) -> Result<Option<&'a Element>, SceneError> {
        let mut used = self.used.borrow_mut();
        for (i, c) in self.e.children.iter().enumerate() {
            if used[i] || c.attr("name").unwrap_or("") != name {
                continue;
            }
            let target = if c.tag == "ref" {
                let id = c.attr("id").ok_or_else(|| c.error("<ref> needs `id`"))?;
                *self
                    .ids
                    .get(id)
                    .ok_or_else(|| c.error(format!("no object has id `{id}`")))?
            } else {
                c
            };
            if target.tag == tag {
                used[i] = true;
                return Ok(Some(target));
            }
        }
        Ok(None)
    }

    /// Every unnamed nested object `<tag>` (or ref to one), in order.
    pub fn objects(&self, tag: &str) -> Result<Vec<&'a Element>, SceneError> {
        let mut out = Vec::new();
        while let Some(e) = self.object(tag, "")? {
            out.push(e);
        }
        Ok(out)
    }

    /// Errors on the first child no read took.
    pub fn finish(self) -> Result<(), SceneError> {
        let used = self.used.borrow();
        if let Some((_, c)) = self.e.children.iter().enumerate().find(|(i, _)| !used[*i]) {
            let what = if OBJECTS.contains(&c.tag.as_str()) {
                "is not supported here"
            } else {
                "is a parameter fogbank does not support (refused rather than ignored)"
            };
            return Err(c.error(format!("in {}: {what}", self.e.at())));
        }
        Ok(())
    }
}
