//! `fogbank compare REFERENCE TEST`: image metrics of a test image against
//! a reference (EXR or PNG).

use fogbank::compare::{
    compare, parse_metrics, read_pair, CompareOptions, Image, Metric, Outcome, ZTEST_ALPHA,
};
use serde_json::{Map, Value};
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct CompareArgs {
    /// Reference image (EXR or PNG); its `variance` layer feeds the z-test.
    pub reference: PathBuf,
    /// Image compared against the reference (same size).
    pub test: PathBuf,
    /// rmse, relmse, smape, flip, ztest or all; repeat or separate with
    /// commas. `all` skips the z-test when neither image has a variance layer.
    #[arg(long, value_delimiter = ',', default_value = "all")]
    pub metric: Vec<String>,
    /// Print one JSON object keyed by metric name instead of a table.
    #[arg(long)]
    pub json: bool,
    /// FLIP: pixels per degree (default 67.02: 0.7 m from a 0.7 m wide 4K monitor).
    #[arg(long)]
    pub ppd: Option<f32>,
    /// FLIP: auto (LDR-FLIP for two PNGs, HDR-FLIP otherwise), ldr or hdr.
    #[arg(long, default_value = "auto")]
    pub flip_mode: String,
    /// HDR-FLIP tone mapper: aces, hable or reinhard.
    #[arg(long, default_value = "aces")]
    pub tonemapper: String,
    /// z-test: family-wise significance level.
    #[arg(long, default_value_t = ZTEST_ALPHA)]
    pub alpha: f64,
}

pub fn run(a: CompareArgs) -> crate::common::CliResult {
    let (wanted, explicit_ztest) = parse_metrics(&a.metric)?;
    let opts = CompareOptions::new(&a.flip_mode, a.ppd, &a.tonemapper, a.alpha)?;
    let (reference, test) = read_pair(&a.reference, &a.test)?;
    let results = compare(&reference, &test, &wanted, explicit_ztest, &opts)
        .map_err(|e| format!("{} vs {}: {e}", a.reference.display(), a.test.display()))?;
    if a.json {
        let mut obj = Map::new();
        for (m, o) in &results {
            obj.insert(m.name().to_string(), o.to_json());
        }
        println!("{}", serde_json::to_string_pretty(&Value::Object(obj))?);
    } else {
        print_table(&a, &reference, &test, &results);
    }
    Ok(())
}

fn describe(path: &std::path::Path, img: &Image) -> String {
    let mut s = format!("{} ({}×{}", path.display(), img.width, img.height);
    if img.is_srgb8 {
        s.push_str(", sRGB");
    }
    if img.variance.is_some() {
        s.push_str(", variance");
    }
    s.push(')');
    s
}

fn print_table(a: &CompareArgs, reference: &Image, test: &Image, results: &[(Metric, Outcome)]) {
    println!("reference  {}", describe(&a.reference, reference));
    println!("test       {}", describe(&a.test, test));
    for (m, o) in results {
        let text = match o {
            Outcome::Scalar(v) => format!("{v:.6}"),
            Outcome::Flip(f) => {
                let how = match f.exposures {
                    Some(e) => format!(
                        "HDR-FLIP, {} exposures in [{:.2}, {:.2}]",
                        e.count, e.start, e.stop
                    ),
                    None => "LDR-FLIP".to_string(),
                };
                format!("{:.6}  ({how}, {:.2} ppd)", f.mean, f.ppd)
            }
            Outcome::Ztest(z) => {
                let at = z
                    .max_abs_z_pixel
                    .map(|(x, y)| format!(" at ({x}, {y})"))
                    .unwrap_or_default();
                let mut s = format!(
                    "{}  {} of {} pixels fail ({:.4} %); |z| threshold {:.3} (Šidák, α = {}, {} tests); max |z| {:.3}{at}",
                    if z.pass { "PASS" } else { "FAIL" },
                    z.failing_pixels,
                    reference.width * reference.height,
                    100.0 * z.failing_fraction,
                    z.threshold,
                    z.alpha,
                    z.tests,
                    z.max_abs_z,
                );
                if z.zero_variance_pixels > 0 {
                    s.push_str(&format!(
                        "; {} zero-variance pixels, {} of them differ",
                        z.zero_variance_pixels, z.zero_variance_mismatches
                    ));
                }
                s.push_str(&format!(
                    "; mean z (R, G, B) = ({:.3}, {:.3}, {:.3})",
                    z.mean_z[0], z.mean_z[1], z.mean_z[2]
                ));
                s
            }
            Outcome::Skipped(why) => format!("skipped: {why}"),
        };
        println!("{:<10} {text}", m.name());
    }
}
