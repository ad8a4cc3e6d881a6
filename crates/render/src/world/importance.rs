//! Importance functions of Lerzer and Dachsbacher 2025 §4.2: a post-interpolative map from a
//! point of a medium to one of a few values in [0, 1], for the visibility
//! optimisation of `visopt` and its baselines. Evaluated at the point from
//! the interpolated data (the paper's default criterion is ranges of
//! extinction), never pre-classified per voxel unless asked (`pre`).
//!
//! A medium's `[[media.importance]]` is an ordered list of rules; a point
//! takes the `value` of the first rule whose every given predicate holds,
//! and 0 when none does (Fig. 10: "pelvis ∧ right half → 0.75, pelvis ∧
//! left half → 1" is two rules).
//!
//! | key | default | meaning |
//! |---|---|---|
//! | `value` | 1 | the importance where the rule holds, in [0, 1] |
//! | `extinction` | none | `[lo, hi]`: σ_t (per world unit, after the transfer function) in [lo, hi) |
//! | `scalar` | none | `[lo, hi]`: the density's value in the file's units in [lo, hi) |
//! | `gradient` | none | `[lo, hi]`: ‖∇σ_t‖ (per world unit²) in [lo, hi) |
//! | `box` | none | `[[x0, y0, z0], [x1, y1, z1]]`: the point lies in this world box |
//! | `half_space` | none | `[nx, ny, nz, c]`: n·x ≥ c (world) |
//! | `mask` | none | a second volume (keys as `density`, placed like it): its trilinear value ≥ `mask_threshold` |
//! | `mask_label` | none | the mask is a label volume: the voxels with this label are the segment, turned into a signed distance encoded so that ½ is its boundary (§6.6, Green 2007), interpolated trilinearly |
//! | `mask_threshold` | 0.5 | see `mask` |

use super::field::{Field, FieldDesc};
use crate::error::SceneError;
use fogbank_math::{DAffine3, DVec3, Vec3};
use fogbank_volume::distance::encoded_signed_distance;
use fogbank_volume::{BrickGrid, DensityData};
use serde::{Deserialize, Serialize};
use std::path::Path;

#[derive(Clone, Debug, Default, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ImportanceRuleDesc {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub value: Option<f32>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub extinction: Option<[f32; 2]>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scalar: Option<[f32; 2]>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gradient: Option<[f32; 2]>,
    #[serde(default, rename = "box", skip_serializing_if = "Option::is_none")]
    pub region: Option<[[f32; 3]; 2]>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub half_space: Option<[f32; 4]>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mask: Option<FieldDesc>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mask_label: Option<f32>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mask_threshold: Option<f32>,
}

/// One built rule; ranges are half-open [lo, hi).
#[derive(Clone, Debug)]
pub struct ImportanceRule {
    pub value: f32,
    pub extinction: Option<[f32; 2]>,
    /// In the grid's stored units.
    pub scalar: Option<[f32; 2]>,
    pub gradient: Option<[f32; 2]>,
    pub region: Option<[Vec3; 2]>,
    pub half_space: Option<(Vec3, f32)>,
    pub mask: Option<(Field, f32)>,
}

/// What a rule may look at, computed only when some rule needs it.
pub struct ImportanceInputs {
    pub p: Vec3,
    pub sigma_t: f32,
    pub scalar: f32,
    pub gradient: f32,
}

/// A medium's ordered importance rules.
#[derive(Clone, Debug, Default)]
pub struct Importance {
    pub rules: Vec<ImportanceRule>,
    /// Pre-interpolative mode: the rules classified per voxel.
    pub pre: Option<PreImportance>,
}

/// `importance_pre` of a medium: classify the importance per voxel, then
/// look it up with `filter` (`"trilinear"`, default, or `"nearest"`) after an
/// optional 3³ `box` filter — the previous work's pipeline Lerzer and Dachsbacher 2025 compares
/// against (Figs. 3, 11). Absent: post-interpolative (the paper's).
#[derive(Clone, Debug, Default, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ImportancePreDesc {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub filter: Option<String>,
    #[serde(default, rename = "box", skip_serializing_if = "Option::is_none")]
    pub box_filter: Option<bool>,
}

/// Importance classified at voxel centres, placed like the medium.
#[derive(Clone, Debug)]
pub struct PreImportance {
    field: Field,
    nearest: bool,
}

impl PreImportance {
    /// The classified field and whether it is looked up nearest (else
    /// trilinearly): what a GPU port uploads.
    pub fn parts(&self) -> (&Field, bool) {
        (&self.field, self.nearest)
    }
}

impl Importance {
    /// Builds `rules` (scene key `key`, e.g. `media.0.importance`); the
    /// medium's data stores file values `v` as `a·v + b` (`units`), masks
    /// are placed by `to_world` after their file's own transform.
    pub fn build(
        rules: &[ImportanceRuleDesc],
        key: &str,
        base: &Path,
        units: (f32, f32),
        to_world: DAffine3,
    ) -> Result<Importance, SceneError> {
        let rules = rules
            .iter()
            .enumerate()
            .map(|(i, r)| build_rule(r, &format!("{key}.{i}"), base, units, to_world))
            .collect::<Result<_, _>>()?;
        Ok(Importance { rules, pre: None })
    }

    /// The pre-interpolative version of these rules for a grid of `dims`
    /// voxels placed by `index_to_world`: each voxel centre classified from
    /// its own data (`inputs` at a world point: the medium's σ_t, scalar and
    /// gradient there), then box-filtered if asked.
    pub fn preclassified(
        &self,
        dims: [u32; 3],
        index_to_world: DAffine3,
        inputs: impl Fn(Vec3) -> ImportanceInputs + Sync,
        d: &ImportancePreDesc,
        key: &str,
    ) -> Result<Importance, SceneError> {
        let nearest = match d.filter.as_deref().unwrap_or("trilinear") {
            "trilinear" => false,
            "nearest" => true,
            other => {
                return Err(SceneError(format!(
                    "{key}.filter: `{other}` is not trilinear or nearest"
                )))
            }
        };
        let xf = index_to_world;
        let at = |i: u32, j: u32, k: u32| {
            let p = xf
                .transform_point3(DVec3::new(i as f64 + 0.5, j as f64 + 0.5, k as f64 + 0.5))
                .as_vec3();
            self.eval(p, || inputs(p))
        };
        let err = |e: fogbank_volume::VolumeError| SceneError(format!("{key}: {e}"));
        let mut grid = BrickGrid::<f32>::from_fn(dims, at).map_err(err)?;
        if d.box_filter.unwrap_or(false) {
            let c = grid;
            grid = BrickGrid::from_fn(dims, |i, j, k| {
                let sum: f32 = (0..27)
                    .map(|n| {
                        c.fetch(
                            i as i32 + n % 3 - 1,
                            j as i32 + (n / 3) % 3 - 1,
                            k as i32 + n / 9 - 1,
                        )
                    })
                    .sum();
                sum / 27.0
            })
            .map_err(err)?;
        }
        let field = Field::from_channels(
            vec![DensityData::F32(grid)],
            xf,
            format!("{key} (pre-interpolative)"),
        )?;
        Ok(Importance {
            rules: self.rules.clone(),
            pre: Some(PreImportance { field, nearest }),
        })
    }

    pub fn is_empty(&self) -> bool {
        self.rules.is_empty()
    }

    pub fn needs_gradient(&self) -> bool {
        self.pre.is_none() && self.rules.iter().any(|r| r.gradient.is_some())
    }

    /// How far apart two importance values may be and still merge in a list:
    /// exact for the post-interpolative step function, 10⁻³ for the
    /// continuous pre-interpolative one (checklist §1).
    pub fn tolerance(&self) -> f32 {
        if self.pre.is_some() {
            1e-3
        } else {
            0.0
        }
    }

    /// The importance at a point: the first rule that holds, else 0.
    /// `inputs` is called at most once, when a rule needs more than `p`.
    pub fn eval(&self, p: Vec3, inputs: impl FnOnce() -> ImportanceInputs) -> f32 {
        if let Some(pre) = &self.pre {
            let v = if pre.nearest {
                pre.field.eval_nearest(p)
            } else {
                pre.field.eval(p)
            };
            return v.x.clamp(0.0, 1.0);
        }
        let mut inputs = Some(inputs);
        let mut got: Option<ImportanceInputs> = None;
        for r in &self.rules {
            if !r.spatial(p) {
                continue;
            }
            if r.extinction.is_some() || r.scalar.is_some() || r.gradient.is_some() {
                let x = got.get_or_insert_with(|| (inputs.take().expect("called once"))());
                let within = |range: Option<[f32; 2]>, v: f32| {
                    range.is_none_or(|[lo, hi]| v >= lo && v < hi)
                };
                if !(within(r.extinction, x.sigma_t)
                    && within(r.scalar, x.scalar)
                    && within(r.gradient, x.gradient))
                {
                    continue;
                }
            }
            return r.value;
        }
        0.0
    }
}

impl ImportanceRule {
    /// The predicates that depend on the position only.
    fn spatial(&self, p: Vec3) -> bool {
        if let Some([lo, hi]) = self.region {
            if !(p.cmpge(lo).all() && p.cmple(hi).all()) {
                return false;
            }
        }
        if let Some((n, c)) = self.half_space {
            if n.dot(p) < c {
                return false;
            }
        }
        if let Some((mask, threshold)) = &self.mask {
            if mask.eval(p).x < *threshold {
                return false;
            }
        }
        true
    }
}

fn build_rule(
    r: &ImportanceRuleDesc,
    key: &str,
    base: &Path,
    (a, b): (f32, f32),
    to_world: DAffine3,
) -> Result<ImportanceRule, SceneError> {
    let value = r.value.unwrap_or(1.0);
    if !(0.0..=1.0).contains(&value) {
        return Err(SceneError(format!(
            "{key}.value: {value} is outside [0, 1]"
        )));
    }
    let range = |name: &str, v: Option<[f32; 2]>| -> Result<Option<[f32; 2]>, SceneError> {
        match v {
            Some([lo, hi]) if lo > hi || lo.is_nan() || hi.is_nan() => Err(SceneError(format!(
                "{key}.{name}: [{lo}, {hi}] is not a range"
            ))),
            other => Ok(other),
        }
    };
    let extinction = range("extinction", r.extinction)?;
    let scalar = range("scalar", r.scalar)?.map(|[lo, hi]| [a * lo + b, a * hi + b]);
    let gradient = range("gradient", r.gradient)?;
    let region = match r.region {
        Some([lo, hi]) if !(0..3).all(|i| lo[i] <= hi[i]) => {
            return Err(SceneError(format!(
                "{key}.box: min {lo:?} exceeds max {hi:?}"
            )))
        }
        other => other.map(|[lo, hi]| [Vec3::from(lo), Vec3::from(hi)]),
    };
    let half_space = match r.half_space {
        Some([x, y, z, c]) => {
            let n = Vec3::new(x, y, z);
            if !(n.length() > 0.0 && c.is_finite()) {
                return Err(SceneError(format!(
                    "{key}.half_space: the normal must be non-zero"
                )));
            }
            Some((n, c))
        }
        None => None,
    };
    let mask = match &r.mask {
        None => {
            if r.mask_label.is_some() || r.mask_threshold.is_some() {
                return Err(SceneError(format!(
                    "{key}: mask_label and mask_threshold need a `mask`"
                )));
            }
            None
        }
        Some(m) => {
            let mkey = format!("{key}.mask");
            let mut f = Field::load(m, &mkey, base, to_world)?;
            if let Some(label) = r.mask_label {
                f = label_mask(&f, label).map_err(|e| SceneError(format!("{mkey}: {e}")))?;
            }
            Some((f, r.mask_threshold.unwrap_or(0.5)))
        }
    };
    Ok(ImportanceRule {
        value,
        extinction,
        scalar,
        gradient,
        region,
        half_space,
        mask,
    })
}

/// The segment `label` of a label volume as a signed distance encoded so
/// that ½ is its boundary (Lerzer and Dachsbacher 2025 §6.6, Green 2007; spread 4 voxels),
/// interpolated trilinearly at lookup.
fn label_mask(f: &Field, label: f32) -> Result<Field, String> {
    let (channels, w2i) = f.parts();
    let dims = channels[0].dims();
    let inside: Vec<bool> = match &channels[0] {
        DensityData::F16(g) => cells(dims)
            .map(|(i, j, k)| g.fetch(i, j, k) == label)
            .collect(),
        DensityData::F32(g) => cells(dims)
            .map(|(i, j, k)| g.fetch(i, j, k) == label)
            .collect(),
        DensityData::Analytic(_) => return Err("a label mask needs a voxel grid".into()),
    };
    if !inside.iter().any(|&b| b) {
        return Err(format!("no voxel has the label {label}"));
    }
    let g = encoded_signed_distance(dims, &inside, 4.0).map_err(|e| e.to_string())?;
    Field::from_channels(vec![DensityData::F32(g)], w2i.inverse(), f.source.clone())
        .map_err(|e| e.0)
}

/// Voxel indices, x fastest.
fn cells(d: [u32; 3]) -> impl Iterator<Item = (i32, i32, i32)> {
    (0..d[2] as i32).flat_map(move |k| {
        (0..d[1] as i32).flat_map(move |j| (0..d[0] as i32).map(move |i| (i, j, k)))
    })
}

#[cfg(test)]
mod importance_test {
    use super::*;

    /// The rules of a `[[importance]]` TOML text, built as `media.0.importance`.
    fn build(text: &str) -> Result<Importance, SceneError> {
        #[derive(Deserialize)]
        struct T {
            importance: Vec<ImportanceRuleDesc>,
        }
        let t: T = toml::from_str(text).unwrap();
        let key = "media.0.importance";
        Importance::build(
            &t.importance,
            key,
            Path::new("."),
            (1.0, 0.0),
            DAffine3::IDENTITY,
        )
    }

    fn rules(text: &str) -> Importance {
        build(text).unwrap()
    }

    fn at(imp: &Importance, p: Vec3, sigma_t: f32) -> f32 {
        imp.eval(p, || ImportanceInputs {
            p,
            sigma_t,
            scalar: 0.0,
            gradient: 0.0,
        })
    }

    #[test]
    fn first_matching_rule_wins_and_none_gives_zero() {
        // Fig. 10: important matter ∧ right half → 0.75, ∧ left half → 1.
        let imp = rules(
            "[[importance]]\nvalue = 0.75\nextinction = [5.0, 1e9]\nhalf_space = [1.0, 0.0, 0.0, 0.0]\n\
             [[importance]]\nextinction = [5.0, 1e9]\n",
        );
        assert_eq!(at(&imp, Vec3::new(0.3, 0.0, 0.0), 10.0), 0.75);
        assert_eq!(at(&imp, Vec3::new(-0.3, 0.0, 0.0), 10.0), 1.0);
        assert_eq!(at(&imp, Vec3::new(0.3, 0.0, 0.0), 1.0), 0.0);
        let boxed =
            rules("[[importance]]\nbox = [[0.0, 0.0, 0.0], [1.0, 1.0, 1.0]]\nvalue = 0.5\n");
        assert_eq!(at(&boxed, Vec3::splat(0.5), 0.0), 0.5);
        assert_eq!(at(&boxed, Vec3::splat(1.5), 0.0), 0.0);
    }

    #[test]
    fn data_inputs_are_computed_only_when_needed() {
        let imp = rules("[[importance]]\nbox = [[0.0, 0.0, 0.0], [1.0, 1.0, 1.0]]\n");
        let v = imp.eval(Vec3::splat(0.5), || panic!("no data predicate, no lookup"));
        assert_eq!(v, 1.0);
    }

    /// A label volume (Mitsuba .vol, labels 0, 1 and 2) whose label 2 is a
    /// ball: the rule holds inside it, to within half a voxel of its radius.
    #[test]
    fn label_masks_follow_the_segment_boundary() {
        let (n, r) = (16u32, 5.2f32);
        let c = n as f32 / 2.0;
        let mut bytes = b"VOL\x03".to_vec();
        for v in [1i32, n as i32, n as i32, n as i32, 1] {
            bytes.extend(v.to_le_bytes());
        }
        for v in [0.0f32, 0.0, 0.0, n as f32, n as f32, n as f32] {
            bytes.extend(v.to_le_bytes());
        }
        for i in 0..n * n * n {
            let p = [i % n, (i / n) % n, i / (n * n)].map(|v| v as f32 + 0.5 - c);
            let d = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
            let label = if d < r {
                2.0f32
            } else if p[0] > 0.0 {
                1.0
            } else {
                0.0
            };
            bytes.extend(label.to_le_bytes());
        }
        let dir = std::env::temp_dir().join(format!("fogbank-label-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(dir.join("labels.vol"), bytes).unwrap();
        #[derive(Deserialize)]
        struct T {
            importance: Vec<ImportanceRuleDesc>,
        }
        let t: T =
            toml::from_str("[[importance]]\nmask = { vol = \"labels.vol\" }\nmask_label = 2.0")
                .unwrap();
        let imp =
            Importance::build(&t.importance, "i", &dir, (1.0, 0.0), DAffine3::IDENTITY).unwrap();
        let k = |x: f32| at(&imp, Vec3::new(c + x, c, c), 0.0);
        assert_eq!(k(0.0), 1.0);
        assert_eq!(k(r - 0.6), 1.0);
        assert_eq!(k(r + 0.6), 0.0);
        assert_eq!(k(-(r + 0.6)), 0.0);
        let t: T =
            toml::from_str("[[importance]]\nmask = { vol = \"labels.vol\" }\nmask_label = 7.0")
                .unwrap();
        let e = Importance::build(&t.importance, "i", &dir, (1.0, 0.0), DAffine3::IDENTITY)
            .unwrap_err();
        assert!(e.0.contains("no voxel has the label 7"), "{}", e.0);
        std::fs::remove_dir_all(&dir).ok();
    }

    #[test]
    fn bad_rules_name_the_key() {
        let err = |text: &str| build(text).unwrap_err().0;
        assert!(err("[[importance]]\nvalue = 2.0").contains("media.0.importance.0.value"));
        assert!(
            err("[[importance]]\n[[importance]]\nextinction = [3.0, 1.0]")
                .contains("media.0.importance.1.extinction")
        );
        assert!(err("[[importance]]\nhalf_space = [0.0, 0.0, 0.0, 1.0]").contains("half_space"));
        assert!(err("[[importance]]\nmask_label = 3.0").contains("need a `mask`"));
    }
}
