//! False-colour maps of per-pixel statistics (Peters 2025 Figs. 8 and 10:
//! image, bias, standard deviation), each with a colour bar.

use crate::frame_stats::FrameStats;
use crate::plot::{ColourMap, Figure, HeatMap};
use std::path::{Path, PathBuf};

/// Channel average per pixel, rows flipped so row 0 of the heat map is the
/// image's bottom row.
fn plane(st: &FrameStats, v: &[[f64; 3]], f: impl Fn(f64) -> f64) -> Vec<f64> {
    let (w, h) = (st.width as usize, st.height as usize);
    (0..h)
        .rev()
        .flat_map(|y| (0..w).map(move |x| y * w + x))
        .map(|p| v[p].iter().map(|&c| f(c)).sum::<f64>() / 3.0)
        .collect()
}

/// One panel; the colour limits are the `q`-quantile of |values| (at least
/// 1e-6), symmetric about 0 for a diverging map, from 0 otherwise.
fn map(
    st: &FrameStats,
    title: &str,
    values: Vec<f64>,
    cmap: ColourMap,
    q: f64,
    bar: &str,
) -> HeatMap {
    let lim = quantile_abs(&values, q).max(1e-6);
    let limits = match cmap {
        ColourMap::Diverging => (-lim, lim),
        ColourMap::Sequential => (0.0, lim),
    };
    HeatMap {
        title: title.into(),
        x_label: "x (pixels)".into(),
        y_label: "y (pixels)".into(),
        x_range: (0.0, st.width as f64),
        y_range: (0.0, st.height as f64),
        nx: st.width as usize,
        ny: st.height as usize,
        values,
        map: cmap,
        limits,
        bar_label: bar.into(),
        overlays: Vec::new(),
    }
}

/// The `q`-quantile of |values| (robust colour limits: a few fireflies must
/// not wash out the map).
fn quantile_abs(values: &[f64], q: f64) -> f64 {
    let mut a: Vec<f64> = values
        .iter()
        .map(|v| v.abs())
        .filter(|v| v.is_finite())
        .collect();
    if a.is_empty() {
        return 0.0;
    }
    a.sort_by(|x, y| x.partial_cmp(y).unwrap());
    a[((a.len() - 1) as f64 * q) as usize]
}

/// Writes `<stem>.svg` and `<stem>.png` with the mean image, the bias (when a
/// reference exists) and the single-frame standard deviation.
pub fn write_maps(st: &FrameStats, label: &str, stem: &Path) -> Result<Vec<PathBuf>, String> {
    let mut fig = Figure::new(3)
        .title(format!("{label}: {} frames", st.runs))
        .panel_size(420, 380);
    fig = fig.with(map(
        st,
        "mean",
        plane(st, &st.mean, |c| c),
        ColourMap::Sequential,
        0.999,
        "value",
    ));
    if let Some(b) = st.bias() {
        fig = fig.with(map(
            st,
            "bias",
            plane(st, &b, |c| c),
            ColourMap::Diverging,
            0.99,
            "mean − reference",
        ));
    }
    fig = fig.with(map(
        st,
        "std (one frame)",
        plane(st, &st.variance, f64::sqrt),
        ColourMap::Sequential,
        0.99,
        "standard deviation",
    ));
    fig.save(stem)
}
