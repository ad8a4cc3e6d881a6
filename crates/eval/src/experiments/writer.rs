//! Where an experiment's output goes: the writer that puts its files into
//! the output directory and records them for the report.

use std::path::PathBuf;

/// Writes an experiment's files into its output directory and records them.
pub struct Writer {
    pub(super) out: PathBuf,
    pub(super) files: Vec<PathBuf>,
}

impl Writer {
    pub fn text(&mut self, file: &str, text: &str) -> Result<(), String> {
        let p = self.out.join(file);
        std::fs::write(&p, text).map_err(|e| format!("{}: {e}", p.display()))?;
        self.files.push(p);
        Ok(())
    }

    /// A CSV file from a header and rows of already formatted fields.
    pub fn csv(&mut self, file: &str, header: &[&str], rows: &[Vec<String>]) -> Result<(), String> {
        let mut s = header.join(",");
        s.push('\n');
        for r in rows {
            s.push_str(&r.join(","));
            s.push('\n');
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

    pub fn figure(&mut self, stem: &str, fig: &crate::plot::Figure) -> Result<(), String> {
        let files = fig.save(&self.out.join(stem))?;
        self.files.extend(files);
        Ok(())
    }
}
