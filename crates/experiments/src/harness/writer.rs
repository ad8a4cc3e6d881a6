//! Where an experiment's output goes: the writer that puts its files into
//! the output directory and records them for the report.

use std::path::PathBuf;

/// Writes an experiment's files into its output directory and records them.
pub struct Writer {
    pub(crate) out: PathBuf,
    pub(crate) files: Vec<PathBuf>,
}

impl Writer {
    pub fn text(&mut self, file: &str, text: &str) -> Result<(), String> {
        let p = self.out.join(file);
        std::fs::write(&p, text).map_err(|e| format!("{}: {e}", p.display()))?;
        self.files.push(p);
        Ok(())
    }

    /// A CSV file from a header and rows of already formatted fields;
    /// fields holding commas, quotes or line breaks are quoted (RFC 4180).
    pub fn csv(&mut self, file: &str, header: &[&str], rows: &[Vec<String>]) -> Result<(), String> {
        let mut s = csv_line(header.iter().copied());
        for r in rows {
            s.push_str(&csv_line(r.iter().map(String::as_str)));
        }
        self.text(file, &s)
    }

    /// Where `file` goes, for writers outside this type; `record` it after.
    pub fn path(&self, file: &str) -> PathBuf {
        self.out.join(file)
    }

    pub fn record(&mut self, path: PathBuf) {
        self.files.push(path);
    }

    /// An 8-bit sRGB PNG of linear `rgb` scaled by 2^`exposure`.
    pub fn png(
        &mut self,
        file: &str,
        width: u32,
        height: u32,
        rgb: &[[f32; 3]],
        exposure: f32,
    ) -> Result<(), String> {
        let p = self.out.join(file);
        let tone = fogbank_image::ToneMapping {
            exposure,
            ..Default::default()
        };
        fogbank_image::image_io::write_png(&p, width, height, rgb, &tone)?;
        self.files.push(p);
        Ok(())
    }

    /// The exposure (stops) that maps the 95th percentile of `rgb`'s
    /// luminance to 1, for images whose range is far from [0, 1] (seed
    /// 003's gradient lobe makes glints of hundreds).
    pub fn auto_exposure(rgb: &[[f32; 3]]) -> f32 {
        let mut lum: Vec<f32> = rgb
            .iter()
            .map(|&c| fogbank_image::luminance(c))
            .filter(|l| l.is_finite() && *l > 0.0)
            .collect();
        if lum.is_empty() {
            return 0.0;
        }
        let k = (0.95 * (lum.len() - 1) as f32) as usize;
        let (_, p95, _) = lum.select_nth_unstable_by(k, f32::total_cmp);
        -p95.log2()
    }

    /// Equal-size linear images side by side, 2 px of black between them,
    /// as one PNG (the paper's side-by-side figures).
    pub fn png_strip(
        &mut self,
        file: &str,
        width: u32,
        height: u32,
        panels: &[&[[f32; 3]]],
        exposure: f32,
    ) -> Result<(), String> {
        const GAP: usize = 2;
        let (w, h) = (width as usize, height as usize);
        if panels.is_empty() || panels.iter().any(|p| p.len() != w * h) {
            return Err(format!("{file}: panels must be {w}×{h} images"));
        }
        let total = panels.len() * w + (panels.len() - 1) * GAP;
        let mut rgb = vec![[0.0f32; 3]; total * h];
        for (k, panel) in panels.iter().enumerate() {
            for y in 0..h {
                let dst = y * total + k * (w + GAP);
                rgb[dst..dst + w].copy_from_slice(&panel[y * w..(y + 1) * w]);
            }
        }
        self.png(file, total as u32, height, &rgb, exposure)
    }

    pub fn figure(&mut self, stem: &str, fig: &fogbank_eval::plot::Figure) -> Result<(), String> {
        let files = fig.save(&self.out.join(stem))?;
        self.files.extend(files);
        Ok(())
    }
}

#[cfg(test)]
impl Writer {
    /// A writer into a fresh folder `<name>_<process id>` under the
    /// temporary directory, for tests that run an experiment.
    pub(crate) fn temp(name: &str) -> Writer {
        let out = std::env::temp_dir().join(format!("{name}_{}", std::process::id()));
        std::fs::create_dir_all(&out).unwrap();
        Writer {
            out,
            files: Vec::new(),
        }
    }
}

/// One CSV record with its line break.
fn csv_line<'a>(fields: impl Iterator<Item = &'a str>) -> String {
    let quoted: Vec<String> = fields
        .map(|f| {
            if f.contains([',', '"', '\n', '\r']) {
                format!("\"{}\"", f.replace('"', "\"\""))
            } else {
                f.to_string()
            }
        })
        .collect();
    quoted.join(",") + "\n"
}

#[cfg(test)]
mod tests {
    #[test]
    fn csv_fields_with_commas_and_quotes_are_quoted() {
        let line = super::csv_line(["a", "b, c", "say \"hi\"", "1.5"].into_iter());
        assert_eq!(line, "a,\"b, c\",\"say \"\"hi\"\"\",1.5\n");
    }
}
