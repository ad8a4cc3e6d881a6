//! Transfer functions of scientific visualisation (Lerzer and Dachsbacher 2025 §3): a scalar
//! volume (CT, MRI, simulation output) classified into extinction, albedo
//! and emission. Post-interpolative by default — interpolate the scalar at
//! the point, then classify — as the paper and ParaView do; pre-interpolative
//! (classify the voxels, then interpolate, optionally box-filtered) for the
//! paper's comparisons (Figs. 3, 11).
//!
//! | key | default | meaning |
//! |---|---|---|
//! | `opacity` | from `paraview`, else required | `[[value, α], …]`, α ≥ 0: σ_t = `sigma_t_scale` · α(s) per world unit (ParaView's "scalar opacity unit distance" is 1/`sigma_t_scale`) |
//! | `color` | from `paraview`, else white | `[[value, r, g, b], …]`: single-scattering albedo, channels in [0, 1] (times the medium's `albedo`, default 1 here) |
//! | `emission` | none | `[[value, r, g, b], …]`: radiance L_e, emitted where the medium absorbs (the μ_a L_e of Lerzer and Dachsbacher 2025 Eq. 1) |
//! | `emission_scale` | 1 | multiplies `emission` |
//! | `paraview` | none | a ParaView colour-map JSON (a preset, or "Export" from the colour-map editor): `RGBPoints` gives `color`, `Points` (x, α, midpoint, sharpness) gives `opacity`; TOML keys override it |
//! | `paraview_name` | first entry | which entry of a JSON file holding several |
//! | `rescale` | false | map the points' value range onto the data's range, as applying a ParaView preset does |
//! | `mode` | `"post"` | `"post"`-interpolative or `"pre"`-interpolative |
//! | `prefilter` | `"none"` | `"pre"` mode only: `"box"` averages the classified voxels over 3³ before interpolation |
//!
//! Both backends classify (the GPU keeps the points in its constants
//! buffer, `gpu/src/wgsl/medium.wgsl` `classify`).
//!
//! Values are in the file's units (Hounsfield units for CT, after NIfTI's
//! `scl_slope`/`scl_inter`); points are linear segments, clamped outside
//! their range; two points at one value make a step. Colours interpolate
//! linearly in RGB whatever the JSON's `ColorSpace` says (presets with many
//! points look the same; two-point diverging maps differ in the middle).

use crate::error::SceneError;
use fogbank_math::{PiecewiseLinear, Vec3};
use fogbank_volume::{BrickGrid, DensityData, Precision};
use serde::{Deserialize, Serialize};
use std::path::Path;

#[derive(Clone, Debug, Default, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct TransferDesc {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub opacity: Option<Vec<[f32; 2]>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub color: Option<Vec<[f32; 4]>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub emission: Option<Vec<[f32; 4]>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub emission_scale: Option<f32>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub paraview: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub paraview_name: Option<String>,
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub rescale: bool,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mode: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub prefilter: Option<String>,
}

/// Where classification happens relative to interpolation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TransferMode {
    /// Interpolate the scalar, then classify (the paper's and ParaView's).
    Post,
    /// Classify the voxels, then interpolate; `box_filter`: average the
    /// classified voxels over 3³ first.
    Pre { box_filter: bool },
}

/// A built transfer function, its points in the grid's stored units.
#[derive(Clone, Debug)]
pub struct Transfer {
    pub opacity: PiecewiseLinear<1>,
    pub color: PiecewiseLinear<3>,
    /// Already multiplied by `emission_scale`.
    pub emission: Option<PiecewiseLinear<3>>,
    pub mode: TransferMode,
}

/// The classification a post-interpolative medium evaluates at scattering
/// vertices (its extinction is classified inside the volume layer).
#[derive(Clone, Debug)]
pub struct TransferLookup {
    pub color: PiecewiseLinear<3>,
    pub emission: Option<PiecewiseLinear<3>>,
}

impl TransferLookup {
    #[inline]
    pub fn color(&self, s: f32) -> Vec3 {
        Vec3::from(self.color.eval(s))
    }

    #[inline]
    pub fn emission(&self, s: f32) -> Option<Vec3> {
        self.emission.as_ref().map(|e| Vec3::from(e.eval(s)))
    }
}

/// The classified grids of a pre-interpolative medium.
pub struct Classified {
    pub sigma: DensityData,
    pub color: [DensityData; 3],
    pub emission: Option<[DensityData; 3]>,
}

/// Post-interpolative (classify per lookup) or pre-interpolative (classify
/// the voxels, with an optional box prefilter).
fn transfer_mode(d: &TransferDesc, key: &str) -> Result<TransferMode, SceneError> {
    Ok(
        match (
            d.mode.as_deref().unwrap_or("post"),
            d.prefilter.as_deref().unwrap_or("none"),
        ) {
            ("post", "none") => TransferMode::Post,
            ("post", _) => {
                return Err(SceneError(format!(
                    "{key}.prefilter: only used with mode = \"pre\""
                )))
            }
            ("pre", f @ ("none" | "box")) => TransferMode::Pre {
                box_filter: f == "box",
            },
            ("pre", f) => {
                return Err(SceneError(format!(
                    "{key}.prefilter: `{f}` is not none or box"
                )))
            }
            (m, _) => return Err(SceneError(format!("{key}.mode: `{m}` is not post or pre"))),
        },
    )
}

/// The map s = a·v + b from the points' values to stored units: file units
/// → stored, s = (v − lo)/(hi − lo) for stored values that stand for the
/// file range `units`; with `rescale`, the points' own range `points` onto
/// the data's `stored_range`.
fn value_map(
    rescale: bool,
    units: Option<(f32, f32)>,
    points: (f32, f32),
    stored_range: (f32, f32),
    key: &str,
) -> Result<(f32, f32), SceneError> {
    // File units → stored units: s = (v − lo)/(hi − lo).
    let (lo, hi) = units.unwrap_or((0.0, 1.0));
    let (mut a, mut b) = if hi > lo {
        (1.0 / (hi - lo), -lo / (hi - lo))
    } else {
        (1.0, -lo)
    };
    if rescale {
        // The points' own range onto the data's (stored) range.
        let (x0, x1) = points;
        let (s0, s1) = stored_range;
        let k = if x1 > x0 { (s1 - s0) / (x1 - x0) } else { 1.0 };
        (a, b) = (k, s0 - k * x0);
    }
    if !(a > 0.0 && a.is_finite() && b.is_finite()) {
        return Err(SceneError(format!(
            "{key}: the value range cannot be mapped"
        )));
    }
    Ok((a, b))
}

impl Transfer {
    /// Builds `d` (scene key `key`) for data whose stored values stand for
    /// the file range `units` (`None`: stored values are the file's) and
    /// span `stored_range`.
    pub fn build(
        d: &TransferDesc,
        key: &str,
        base: &Path,
        units: Option<(f32, f32)>,
        stored_range: (f32, f32),
    ) -> Result<Transfer, SceneError> {
        let (mut opacity, mut color) = (None, None);
        if let Some(f) = &d.paraview {
            let path = base.join(f);
            let text = std::fs::read_to_string(&path)
                .map_err(|e| SceneError(format!("{key}.paraview: {}: {e}", path.display())))?;
            (opacity, color) = paraview(&text, d.paraview_name.as_deref())
                .map_err(|e| SceneError(format!("{key}.paraview: {}: {e}", path.display())))?;
        }
        if let Some(p) = &d.opacity {
            opacity = Some(curve(
                p.iter().map(|q| (q[0], [q[1]])),
                &format!("{key}.opacity"),
            )?);
        }
        if let Some(p) = &d.color {
            color = Some(curve(
                p.iter().map(|q| (q[0], [q[1], q[2], q[3]])),
                &format!("{key}.color"),
            )?);
        }
        let emission = d
            .emission
            .as_ref()
            .map(|p| {
                curve(
                    p.iter().map(|q| (q[0], [q[1], q[2], q[3]])),
                    &format!("{key}.emission"),
                )
            })
            .transpose()?;
        let opacity = opacity.ok_or_else(|| {
            SceneError(format!(
                "{key}: give `opacity` points (or a `paraview` file with `Points`)"
            ))
        })?;
        let color = color.unwrap_or_else(|| PiecewiseLinear::constant([1.0; 3]));
        check_values(&opacity, &format!("{key}.opacity"), f32::INFINITY)?;
        check_values(&color, &format!("{key}.color"), 1.0)?;
        let scale = d.emission_scale.unwrap_or(1.0);
        if !(scale.is_finite() && scale >= 0.0) {
            return Err(SceneError(format!(
                "{key}.emission_scale: must be finite and ≥ 0"
            )));
        }
        let emission = match emission {
            Some(e) => {
                check_values(&e, &format!("{key}.emission"), f32::INFINITY)?;
                let pts = e.points().map(|(x, y)| (x, y.map(|v| v * scale))).collect();
                Some(
                    PiecewiseLinear::new(pts)
                        .map_err(|m| SceneError(format!("{key}.emission: {m}")))?,
                )
            }
            None => None,
        };
        let mode = transfer_mode(d, key)?;
        let points = point_range(&opacity, &color, emission.as_ref());
        let (a, b) = value_map(d.rescale, units, points, stored_range, key)?;
        Ok(Transfer {
            opacity: opacity.remapped(a, b),
            color: color.remapped(a, b),
            emission: emission.map(|e| e.remapped(a, b)),
            mode,
        })
    }

    pub fn lookup(&self) -> TransferLookup {
        TransferLookup {
            color: self.color.clone(),
            emission: self.emission.clone(),
        }
    }

    /// Pre-interpolative classification of `data`'s voxels: α, albedo and
    /// emission grids (each optionally box-filtered), in `precision`.
    pub fn classify(&self, data: &DensityData, precision: Precision) -> Result<Classified, String> {
        let box_filter = matches!(self.mode, TransferMode::Pre { box_filter: true });
        let grid = |f: &(dyn Fn(f32) -> f32 + Sync)| -> Result<DensityData, String> {
            let g = match data {
                DensityData::F16(g) => classify_grid(g, f, box_filter),
                DensityData::F32(g) => classify_grid(g, f, box_filter),
                DensityData::Analytic(_) => {
                    Err("analytic fields have no voxels to classify".into())
                }
            }?;
            Ok(DensityData::from_f32(g, precision))
        };
        let rgb = |c: &PiecewiseLinear<3>| -> Result<[DensityData; 3], String> {
            Ok([
                grid(&|s| c.eval(s)[0])?,
                grid(&|s| c.eval(s)[1])?,
                grid(&|s| c.eval(s)[2])?,
            ])
        };
        Ok(Classified {
            sigma: grid(&|s| self.opacity.eval(s)[0])?,
            color: rgb(&self.color)?,
            emission: self.emission.as_ref().map(rgb).transpose()?,
        })
    }
}

fn classify_grid<T: fogbank_volume::Voxel>(
    g: &BrickGrid<T>,
    f: &(dyn Fn(f32) -> f32 + Sync),
    box_filter: bool,
) -> Result<BrickGrid<f32>, String> {
    let dims = g.dims();
    let c = BrickGrid::<f32>::from_fn(dims, |i, j, k| f(g.fetch(i as i32, j as i32, k as i32)))
        .map_err(|e| e.to_string())?;
    if !box_filter {
        return Ok(c);
    }
    // 3³ box with clamped borders, like the lookups.
    BrickGrid::from_fn(dims, |i, j, k| {
        let mut sum = 0.0;
        for n in 0..27 {
            let (di, dj, dk) = (n % 3 - 1, (n / 3) % 3 - 1, n / 9 - 1);
            sum += c.fetch(i as i32 + di, j as i32 + dj, k as i32 + dk);
        }
        sum / 27.0
    })
    .map_err(|e| e.to_string())
}

fn curve<const N: usize>(
    points: impl Iterator<Item = (f32, [f32; N])>,
    key: &str,
) -> Result<PiecewiseLinear<N>, SceneError> {
    PiecewiseLinear::new(points.collect()).map_err(|m| SceneError(format!("{key}: {m}")))
}

fn check_values<const N: usize>(
    c: &PiecewiseLinear<N>,
    key: &str,
    max: f32,
) -> Result<(), SceneError> {
    match c
        .points()
        .position(|(_, y)| y.iter().any(|&v| !(v >= 0.0 && v <= max)))
    {
        None => Ok(()),
        Some(i) if max.is_finite() => Err(SceneError(format!(
            "{key}: point {i} has a value outside [0, {max}]"
        ))),
        Some(i) => Err(SceneError(format!("{key}: point {i} has a negative value"))),
    }
}

fn point_range(
    o: &PiecewiseLinear<1>,
    c: &PiecewiseLinear<3>,
    e: Option<&PiecewiseLinear<3>>,
) -> (f32, f32) {
    let xs = o
        .points()
        .map(|p| p.0)
        .chain(c.points().map(|p| p.0).filter(|_| c.len() > 1))
        .chain(e.into_iter().flat_map(|e| e.points().map(|p| p.0)));
    xs.fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), x| {
        (lo.min(x), hi.max(x))
    })
}

/// Opacity and colour of a ParaView colour-map JSON: a list of presets (or
/// one object) with `RGBPoints` = [x, r, g, b, …] and optionally `Points` =
/// [x, α, midpoint, sharpness, …]. Only linear segments (midpoint ½,
/// sharpness 0) are read: others are refused rather than approximated.
pub fn paraview(
    text: &str,
    name: Option<&str>,
) -> Result<(Option<PiecewiseLinear<1>>, Option<PiecewiseLinear<3>>), String> {
    let v: serde_json::Value = serde_json::from_str(text).map_err(|e| format!("not JSON: {e}"))?;
    let entries: Vec<&serde_json::Value> = match &v {
        serde_json::Value::Array(a) => a.iter().collect(),
        o @ serde_json::Value::Object(_) => vec![o],
        _ => return Err("expected a list of colour maps or one colour map".into()),
    };
    let entry = match name {
        None => entries
            .first()
            .copied()
            .ok_or("the file holds no colour map")?,
        Some(n) => entries
            .iter()
            .copied()
            .find(|e| e.get("Name").and_then(|v| v.as_str()) == Some(n))
            .ok_or_else(|| {
                let names: Vec<&str> = entries
                    .iter()
                    .filter_map(|e| e.get("Name").and_then(|v| v.as_str()))
                    .take(20)
                    .collect();
                format!("no colour map named `{n}` (has: {})", names.join(", "))
            })?,
    };
    let numbers = |k: &str, stride: usize| -> Result<Option<Vec<f32>>, String> {
        let Some(v) = entry.get(k) else {
            return Ok(None);
        };
        let a = v.as_array().ok_or_else(|| format!("`{k}` is not a list"))?;
        if a.is_empty() || a.len() % stride != 0 {
            return Err(format!(
                "`{k}` has {} numbers, not a positive multiple of {stride}",
                a.len()
            ));
        }
        let n: Option<Vec<f32>> = a.iter().map(|x| x.as_f64().map(|x| x as f32)).collect();
        n.map(Some)
            .ok_or_else(|| format!("`{k}` holds something that is not a number"))
    };
    let color = numbers("RGBPoints", 4)?
        .map(|n| PiecewiseLinear::new(n.chunks(4).map(|c| (c[0], [c[1], c[2], c[3]])).collect()))
        .transpose()
        .map_err(|m| format!("RGBPoints: {m}"))?;
    let opacity = match numbers("Points", 4)? {
        Some(n) => {
            if let Some(i) = n.chunks(4).position(|c| c[2] != 0.5 || c[3] != 0.0) {
                return Err(format!(
                    "Points: point {i} has midpoint {} and sharpness {}; fogbank reads linear segments only (0.5, 0)",
                    n[4 * i + 2],
                    n[4 * i + 3]
                ));
            }
            Some(
                PiecewiseLinear::new(n.chunks(4).map(|c| (c[0], [c[1]])).collect())
                    .map_err(|m| format!("Points: {m}"))?,
            )
        }
        None => None,
    };
    if color.is_none() && opacity.is_none() {
        return Err("the colour map has neither `RGBPoints` nor `Points`".into());
    }
    Ok((opacity, color))
}

#[cfg(test)]
mod transfer_test {
    use super::*;

    #[test]
    fn paraview_presets_and_exports_parse() {
        let preset = r#"[{"ColorSpace": "Diverging", "Name": "Cool to Warm",
            "NanColor": [1, 1, 0], "RGBPoints": [0, 0.23, 0.299, 0.754, 1, 0.706, 0.016, 0.15]},
            {"Name": "ramp", "RGBPoints": [-1, 0, 0, 0, 1, 1, 1, 1],
             "Points": [-1, 0, 0.5, 0, 0, 0.2, 0.5, 0, 1, 1, 0.5, 0]}]"#;
        let (o, c) = paraview(preset, None).unwrap();
        assert!(o.is_none());
        let mid = c.unwrap().eval(0.5);
        for (a, b) in mid.iter().zip([0.468, 0.1575, 0.452]) {
            assert!((a - b).abs() < 1e-6, "{mid:?}");
        }
        let (o, c) = paraview(preset, Some("ramp")).unwrap();
        assert_eq!(o.unwrap().eval(0.5), [0.6]);
        assert_eq!(c.unwrap().eval(0.0), [0.5; 3]);
        let e = paraview(preset, Some("nope")).unwrap_err();
        assert!(e.contains("Cool to Warm") && e.contains("ramp"), "{e}");
        for (bad, what) in [
            ("{", "not JSON"),
            ("3", "expected a list"),
            (r#"{"RGBPoints": [0, 1, 1]}"#, "multiple of 4"),
            (r#"{"RGBPoints": [1, 0, 0, 0, 0, 1, 1, 1]}"#, "sorted"),
            (r#"{"Points": [0, 0, 0.3, 0]}"#, "linear segments only"),
            (r#"{"Name": "x"}"#, "neither"),
            (r#"{"RGBPoints": [0, "a", 0, 0]}"#, "not a number"),
        ] {
            let e = paraview(bad, None).unwrap_err();
            assert!(e.contains(what), "{bad}: {e}");
        }
    }

    /// Truncations and byte flips of a valid colour map give a result or
    /// an error, never a panic (the parser sits on serde_json; this covers
    /// fogbank's own checks on what it returns).
    #[test]
    fn mangled_colour_maps_never_panic() {
        let good = br#"[{"Name": "m", "RGBPoints": [-1, 0, 0, 0, 0, 0.5, 0.2, 0.1, 1, 1, 1, 1],
            "Points": [-1, 0, 0.5, 0, 1, 1, 0.5, 0]}]"#;
        let mut rng = fogbank_math::Pcg32::new(9, 9);
        let mut tried = 0;
        for n in 0..good.len() {
            let _ = paraview(&String::from_utf8_lossy(&good[..n]), None);
            tried += 1;
        }
        for _ in 0..5000 {
            let mut b = good.to_vec();
            for _ in 0..1 + rng.next_u32() % 4 {
                let i = rng.next_u32() as usize % b.len();
                let alphabet = b"0123456789-.e,[]{}\": naN";
                b[i] = alphabet[rng.next_u32() as usize % alphabet.len()];
            }
            let text = String::from_utf8_lossy(&b);
            let r = std::panic::catch_unwind(|| paraview(&text, Some("m")).map(|_| ()));
            assert!(r.is_ok(), "panic on {text}");
            tried += 1;
        }
        assert!(tried > 5000);
    }

    fn desc(text: &str) -> TransferDesc {
        toml::from_str(text).unwrap()
    }

    #[test]
    fn points_map_from_file_units_to_stored_units() {
        // A CT-like file: stored [0, 1] stands for [−1000, 3000] HU.
        let d = desc("opacity = [[-1000, 0], [200, 0], [400, 0.8]]\ncolor = [[200, 1, 0.5, 0.25]]");
        let t =
            Transfer::build(&d, "t", Path::new("."), Some((-1000.0, 3000.0)), (0.0, 1.0)).unwrap();
        let s = |hu: f32| (hu + 1000.0) / 4000.0;
        assert!((t.opacity.eval(s(300.0))[0] - 0.4).abs() < 1e-5);
        assert_eq!(t.opacity.eval(s(-500.0))[0], 0.0);
        assert_eq!(t.color.eval(s(0.0)), [1.0, 0.5, 0.25]);
        assert_eq!(t.mode, TransferMode::Post);
        // Rescaled: the points' range [−1000, 400] onto the stored [0.2, 0.6].
        let d = desc("opacity = [[-1000, 0], [400, 1]]\nrescale = true");
        let t = Transfer::build(&d, "t", Path::new("."), None, (0.2, 0.6)).unwrap();
        assert!((t.opacity.eval(0.4)[0] - 0.5).abs() < 1e-6);
    }

    #[test]
    fn bad_tables_name_the_key() {
        let err = |text: &str| {
            Transfer::build(
                &desc(text),
                "media.0.transfer",
                Path::new("."),
                None,
                (0.0, 1.0),
            )
            .unwrap_err()
            .0
        };
        assert!(err("color = [[0, 1, 1, 1]]").contains("media.0.transfer: give `opacity`"));
        assert!(err("opacity = [[1, 0], [0, 1]]")
            .contains("media.0.transfer.opacity: points must be sorted"));
        assert!(err("opacity = [[0, -1]]").contains("negative"));
        assert!(
            err("opacity = [[0, 1]]\ncolor = [[0, 2, 0, 0]]").contains("transfer.color: point 0")
        );
        assert!(err("opacity = [[0, 1]]\nmode = \"mid\"").contains("transfer.mode"));
        assert!(err("opacity = [[0, 1]]\nprefilter = \"box\"").contains("only used with mode"));
        assert!(
            err("opacity = [[0, 1]]\nparaview = \"missing.json\"").contains("transfer.paraview")
        );
    }

    #[test]
    fn pre_classification_filters_classified_voxels() {
        let g = BrickGrid::<f32>::from_fn([4, 3, 2], |i, _, _| i as f32 / 3.0).unwrap();
        let d = desc("opacity = [[0, 0], [0.5, 1], [1, 0]]\nmode = \"pre\"");
        let t = Transfer::build(&d, "t", Path::new("."), None, (0.0, 1.0)).unwrap();
        let c = t
            .classify(&DensityData::F32(g.clone()), Precision::F32)
            .unwrap();
        let DensityData::F32(sigma) = &c.sigma else {
            panic!()
        };
        // Voxels 1/3 and 2/3 classify to 2/3 each: a tent of the voxels.
        assert!((sigma.fetch(1, 0, 0) - 2.0 / 3.0).abs() < 1e-6);
        assert_eq!(sigma.fetch(0, 0, 0), 0.0);
        let d = desc("opacity = [[0, 0], [0.5, 1], [1, 0]]\nmode = \"pre\"\nprefilter = \"box\"");
        let t = Transfer::build(&d, "t", Path::new("."), None, (0.0, 1.0)).unwrap();
        let c = t.classify(&DensityData::F32(g), Precision::F32).unwrap();
        let DensityData::F32(boxed) = &c.sigma else {
            panic!()
        };
        // x-neighbours 0, 2/3, 2/3 (constant in y and z).
        assert!((boxed.fetch(1, 1, 0) - 4.0 / 9.0).abs() < 1e-6);
    }
}
