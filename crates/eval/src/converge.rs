//! Equal-time convergence: MSE against a reference as a function of render
//! time, one curve per configuration, measured in one run.

use crate::Backend;
use fogbank_render::{Film, Progress, RenderOptions, Scene};
use std::io::Write;
use std::path::Path;
use std::time::Duration;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CurvePoint {
    pub spp: u32,
    pub seconds: f64,
    pub mse: f64,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Curve {
    pub label: String,
    pub points: Vec<CurvePoint>,
}

/// Mean squared error over pixels and channels.
pub fn mse(mean: &[[f32; 3]], reference: &[[f64; 3]]) -> f64 {
    let n = (mean.len() * 3).max(1) as f64;
    mean.iter()
        .zip(reference)
        .map(|(m, r)| (0..3).map(|c| (m[c] as f64 - r[c]).powi(2)).sum::<f64>())
        .sum::<f64>()
        / n
}

/// Renders progressively on `backend` for `seconds` (at least one pass),
/// recording the MSE of the running mean after every pass (CPU) or dispatch
/// (GPU, the film read back). Time spent measuring is not counted.
pub fn convergence(
    backend: Backend,
    scene: &Scene,
    seconds: f64,
    reference: &[[f64; 3]],
    seed: u32,
) -> Result<Vec<CurvePoint>, String> {
    let opts = RenderOptions {
        spp: u32::MAX,
        seed,
        time_budget: Some(Duration::from_secs_f64(seconds)),
    };
    let mut points = Vec::new();
    backend.render_observed(
        scene,
        &opts,
        &Progress::default(),
        Some(&mut |film: &Film, t: f64| {
            points.push(CurvePoint {
                spp: film.min_spp(),
                seconds: t,
                mse: mse(&film.mean(), reference),
            });
        }),
    )?;
    Ok(points)
}

/// Time at which the curve first reaches `target` MSE, interpolated
/// log-log between passes; `None` if it never does.
pub fn time_to_reach(curve: &[CurvePoint], target: f64) -> Option<f64> {
    let first = curve.first()?;
    if first.mse <= target {
        return Some(first.seconds);
    }
    curve.windows(2).find(|w| w[1].mse <= target).map(|w| {
        let (a, b) = (w[0], w[1]);
        if a.mse <= 0.0 || b.mse <= 0.0 || a.seconds <= 0.0 || a.mse == b.mse {
            return b.seconds;
        }
        let f = (target.ln() - a.mse.ln()) / (b.mse.ln() - a.mse.ln());
        (a.seconds.ln() + f * (b.seconds.ln() - a.seconds.ln())).exp()
    })
}

/// CSV with columns `label,spp,seconds,mse`.
pub fn write_csv(path: &Path, curves: &[Curve]) -> std::io::Result<()> {
    let mut f = std::io::BufWriter::new(std::fs::File::create(path)?);
    writeln!(f, "label,spp,seconds,mse")?;
    for c in curves {
        for p in &c.points {
            writeln!(f, "{},{},{:.6},{:.9e}", c.label, p.spp, p.seconds, p.mse)?;
        }
    }
    Ok(())
}

/// Log-log plot of MSE against seconds, one line per curve (`<stem>.svg`,
/// `<stem>.png`).
pub fn plot(curves: &[Curve], title: &str, stem: &Path) -> Result<Vec<std::path::PathBuf>, String> {
    use crate::plot::{palette, Figure, LinePlot, Series};
    let mut p = LinePlot::new(title, "render time (s)", "MSE")
        .log_x()
        .log_y();
    for (i, c) in curves.iter().enumerate() {
        let pts: Vec<(f64, f64)> = c
            .points
            .iter()
            .filter(|q| q.seconds > 0.0 && q.mse > 0.0)
            .map(|q| (q.seconds, q.mse))
            .collect();
        p = p.with(Series::line(c.label.clone(), pts, palette(i)));
    }
    Figure::new(1).with(p).save(stem)
}

#[cfg(test)]
mod converge_test {
    use super::*;

    #[test]
    fn time_to_reach_interpolates_log_log() {
        let c = [
            CurvePoint {
                spp: 1,
                seconds: 1.0,
                mse: 1.0,
            },
            CurvePoint {
                spp: 4,
                seconds: 4.0,
                mse: 0.25,
            },
        ];
        let t = time_to_reach(&c, 0.5).unwrap();
        assert!((t - 2.0).abs() < 1e-9, "{t}");
        assert_eq!(time_to_reach(&c, 0.1), None);
        assert_eq!(time_to_reach(&c, 2.0), Some(1.0));
    }
}
