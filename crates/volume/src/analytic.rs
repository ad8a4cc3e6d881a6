//! Analytic test media whose optical depth along any ray is known in closed
//! form: the exact references for the unbiased estimators' tests.
//!
//! Each field lives on the index box `[0, n]³` and is written in normalised
//! coordinates `x = p / n ∈ [0, 1]³`, so parameters do not depend on `n`.
//! Values are densities; the medium's `sigma_t_scale` multiplies them.

use crate::access::VolumeAccess;
use crate::supervoxel::{SuperVoxel, SuperVoxelGrid};
use crate::{Result, VolumeError};
use fogbank_math::{Ray, Vec3};
use std::f64::consts::TAU;

#[derive(Clone, Debug, PartialEq)]
pub enum AnalyticKind {
    /// μ(x) = 0.
    Empty,
    /// μ(x) = value.
    Constant { value: f32 },
    /// μ(x) = base + gradient · x, non-negative on the cube.
    Ramp { base: f32, gradient: [f32; 3] },
    /// μ(x) = mean + amplitude · sin(2π frequency · x + phase), mean ≥ |amplitude|.
    Sinusoid {
        mean: f32,
        amplitude: f32,
        frequency: [f32; 3],
        phase: f32,
    },
    /// `count` slabs perpendicular to `axis`, each `width` thick (in units of
    /// the cube), centred at (s + ½)/count, of density `value`; zero between.
    Slabs {
        value: f32,
        count: u32,
        width: f32,
        axis: usize,
    },
    /// μ(x) = value inside the ball of `radius` (in units of the cube)
    /// centred at the cube's centre, zero outside: a homogeneous sphere, the
    /// medium of the analytic single-scattering tests.
    Sphere { value: f32, radius: f32 },
}

#[derive(Clone, Debug)]
pub struct AnalyticField {
    pub kind: AnalyticKind,
    /// Resolution `n` of the index box; sets the super-voxel grid's extent.
    pub n: u32,
}

impl AnalyticField {
    pub fn new(kind: AnalyticKind, n: u32) -> Result<Self> {
        if n == 0 || n > 1 << 14 {
            return Err(VolumeError::Invalid(format!(
                "analytic medium resolution {n} out of range 1..=16384"
            )));
        }
        let bad = |m: &str| Err(VolumeError::Invalid(format!("analytic medium: {m}")));
        match &kind {
            AnalyticKind::Constant { value } if *value < 0.0 => {
                return bad("constant value must be ≥ 0")
            }
            AnalyticKind::Ramp { base, gradient } => {
                let min_corner = base + gradient.iter().map(|g| g.min(0.0)).sum::<f32>();
                if min_corner < 0.0 {
                    return bad(
                        "ramp must be non-negative on the unit cube (base + Σ min(g, 0) ≥ 0)",
                    );
                }
            }
            AnalyticKind::Sinusoid {
                mean, amplitude, ..
            } if *mean < amplitude.abs() => return bad("sinusoid needs mean ≥ |amplitude|"),
            AnalyticKind::Slabs {
                value,
                count,
                width,
                axis,
            } if *value < 0.0
                || *count == 0
                || *width <= 0.0
                || *width > 1.0 / *count as f32
                || *axis > 2 =>
            {
                return bad("slabs need value ≥ 0, count ≥ 1, 0 < width ≤ 1/count, axis 0..=2");
            }
            AnalyticKind::Sphere { value, radius }
                if *value < 0.0 || !(*radius > 0.0 && *radius <= 0.5) =>
            {
                return bad("sphere needs value ≥ 0 and 0 < radius ≤ 0.5")
            }
            _ => {}
        }
        Ok(AnalyticField { kind, n })
    }

    pub fn name(&self) -> &'static str {
        match self.kind {
            AnalyticKind::Empty => "empty",
            AnalyticKind::Constant { .. } => "constant",
            AnalyticKind::Ramp { .. } => "ramp",
            AnalyticKind::Sinusoid { .. } => "sinusoid",
            AnalyticKind::Slabs { .. } => "slabs",
            AnalyticKind::Sphere { .. } => "sphere",
        }
    }

    /// Density at normalised position `x`.
    pub fn density(&self, x: Vec3) -> f32 {
        match &self.kind {
            AnalyticKind::Empty => 0.0,
            AnalyticKind::Constant { value } => *value,
            AnalyticKind::Ramp { base, gradient } => base + Vec3::from(*gradient).dot(x),
            AnalyticKind::Sinusoid {
                mean,
                amplitude,
                frequency,
                phase,
            } => sinusoid(*mean, *amplitude, *frequency, *phase, x),
            AnalyticKind::Slabs {
                value,
                count,
                width,
                axis,
            } => {
                let s = x[*axis] * *count as f32;
                let centre = s.floor() + 0.5;
                if (s - centre).abs() <= 0.5 * width * *count as f32
                    && (0.0..=1.0).contains(&x[*axis])
                {
                    *value
                } else {
                    0.0
                }
            }
            AnalyticKind::Sphere { value, radius } => {
                if (x - Vec3::splat(0.5)).length_squared() <= radius * radius {
                    *value
                } else {
                    0.0
                }
            }
        }
    }

    /// Conservative (min, max) of the density over the box `[lo, hi]` in
    /// normalised coordinates.
    pub fn range(&self, lo: Vec3, hi: Vec3) -> (f32, f32) {
        match &self.kind {
            AnalyticKind::Empty => (0.0, 0.0),
            AnalyticKind::Constant { value } => (*value, *value),
            AnalyticKind::Ramp { base, gradient } => {
                let (mut mn, mut mx) = (*base, *base);
                for a in 0..3 {
                    let (l, h) = (gradient[a] * lo[a], gradient[a] * hi[a]);
                    mn += l.min(h);
                    mx += l.max(h);
                }
                (mn.max(0.0), mx)
            }
            AnalyticKind::Sinusoid {
                mean,
                amplitude,
                frequency,
                phase,
            } => {
                let c = 0.5 * (lo + hi);
                let half_span: f32 = (0..3)
                    .map(|a| std::f32::consts::TAU * frequency[a].abs() * 0.5 * (hi[a] - lo[a]))
                    .sum();
                let a = amplitude.abs();
                let centre = sinusoid(*mean, *amplitude, *frequency, *phase, c);
                let slack = a * half_span * 1.0001;
                (
                    (centre - slack).max(mean - a),
                    (centre + slack).min(mean + a),
                )
            }
            AnalyticKind::Slabs {
                value,
                count,
                width,
                axis,
            } => {
                let (l, h) = (lo[*axis], hi[*axis]);
                let mut touches = false;
                let mut covers = false;
                for s in 0..*count {
                    let c = (s as f32 + 0.5) / *count as f32;
                    let (a, b) = (c - 0.5 * width, c + 0.5 * width);
                    touches |= b >= l && a <= h;
                    covers |= a <= l && b >= h;
                }
                (
                    if covers { *value } else { 0.0 },
                    if touches { *value } else { 0.0 },
                )
            }
            AnalyticKind::Sphere { value, radius } => {
                let c = Vec3::splat(0.5);
                let nearest = c.clamp(lo, hi);
                let farthest = Vec3::select((c - lo).cmpgt(hi - c), lo, hi);
                let r2 = radius * radius;
                // Slack so f32 rounding of positions on the surface never
                // escapes the bounds.
                (
                    if (farthest - c).length_squared() < r2 * 0.9999 {
                        *value
                    } else {
                        0.0
                    },
                    if (nearest - c).length_squared() <= r2 * 1.0001 {
                        *value
                    } else {
                        0.0
                    },
                )
            }
        }
    }

    /// Exact optical depth in density units of the index-space ray over
    /// `[t0, t1]`, clipped to the cube `[0, n]³`.
    pub fn optical_depth(&self, ray: &Ray, t0: f32, t1: f32) -> f64 {
        let n = self.n as f64;
        let cube = fogbank_math::Aabb::new(Vec3::ZERO, Vec3::splat(self.n as f32));
        let Some((a, b)) = cube.intersect(ray, t0, t1) else {
            return 0.0;
        };
        let (a, b) = (a as f64, b as f64);
        let len = b - a;
        if len <= 0.0 {
            return 0.0;
        }
        let o = ray.o.as_dvec3() / n;
        let d = ray.d.as_dvec3() / n;
        match &self.kind {
            AnalyticKind::Empty => 0.0,
            AnalyticKind::Constant { value } => *value as f64 * len,
            AnalyticKind::Ramp { base, gradient } => {
                let g = Vec3::from(*gradient).as_dvec3();
                *base as f64 * len + g.dot(o) * len + g.dot(d) * 0.5 * (b * b - a * a)
            }
            AnalyticKind::Sinusoid {
                mean,
                amplitude,
                frequency,
                phase,
            } => {
                let f = Vec3::from(*frequency).as_dvec3();
                let alpha = TAU * f.dot(o) + *phase as f64;
                let beta = TAU * f.dot(d);
                let integral_sin = if (beta * len).abs() < 1e-6 {
                    (alpha + beta * 0.5 * (a + b)).sin() * len
                } else {
                    ((alpha + beta * a).cos() - (alpha + beta * b).cos()) / beta
                };
                *mean as f64 * len + *amplitude as f64 * integral_sin
            }
            AnalyticKind::Slabs {
                value,
                count,
                width,
                axis,
            } => {
                let (oa, da) = (o[*axis], d[*axis]);
                let mut inside = 0.0;
                for s in 0..*count {
                    let c = (s as f64 + 0.5) / *count as f64;
                    let (lo, hi) = (c - 0.5 * *width as f64, c + 0.5 * *width as f64);
                    let (sa, sb) = if da == 0.0 {
                        if oa >= lo && oa <= hi {
                            (a, b)
                        } else {
                            continue;
                        }
                    } else {
                        let (u, v) = ((lo - oa) / da, (hi - oa) / da);
                        (u.min(v).max(a), u.max(v).min(b))
                    };
                    inside += (sb - sa).max(0.0);
                }
                *value as f64 * inside
            }
            AnalyticKind::Sphere { value, radius } => {
                // Chord of the ray (in normalised units, parameter t) through
                // the ball, clipped to [a, b].
                let oc = o - glam::DVec3::splat(0.5);
                let (dd, od) = (d.dot(d), oc.dot(d));
                let disc = od * od - dd * (oc.dot(oc) - (*radius as f64).powi(2));
                if disc <= 0.0 {
                    return 0.0;
                }
                let s = disc.sqrt();
                let (u, v) = ((-od - s) / dd, (-od + s) / dd);
                *value as f64 * (v.min(b) - u.max(a)).max(0.0)
            }
        }
    }

    /// Super-voxel statistics of edge `size` (in index units), in density
    /// units: min/max from the analytic bounds, mean and Eq. 5 importance from
    /// an 8³ sample lattice (they steer sampling only, never correctness).
    pub fn supervoxels(&self, size: u32) -> SuperVoxelGrid {
        let size = size.max(1);
        let sdims = [self.n.div_ceil(size); 3];
        let mut cells = Vec::with_capacity(sdims.iter().map(|&d| d as usize).product());
        let n = self.n as f32;
        for cz in 0..sdims[2] {
            for cy in 0..sdims[1] {
                for cx in 0..sdims[0] {
                    let lo = Vec3::new(cx as f32, cy as f32, cz as f32) * size as f32 / n;
                    let hi = (lo + Vec3::splat(size as f32 / n)).min(Vec3::ONE);
                    let (mn, mx) = self.range(lo, hi);
                    const K: u32 = 8;
                    let samples = (0..K * K * K).map(|s| {
                        let f =
                            Vec3::new((s % K) as f32, ((s / K) % K) as f32, (s / (K * K)) as f32)
                                + Vec3::splat(0.5);
                        self.density(lo + (hi - lo) * f / K as f32).clamp(mn, mx)
                    });
                    let stats = SuperVoxel::from_values(samples.clone());
                    let sq: f64 = samples.map(|v| ((v - mn) as f64).powi(2)).sum::<f64>()
                        / (K * K * K) as f64;
                    cells.push(SuperVoxel {
                        min: mn,
                        max: mx,
                        mean: stats.mean.clamp(mn + 0.05 * (mx - mn), mx),
                        // Never zero where the field may exceed its minimum: the sample
                        // lattice can miss a thin slab, and zero importance there
                        // would leave part of the integrand unsampled.
                        importance: (sq.sqrt() as f32).max(0.01 * mn).max(0.05 * (mx - mn)),
                    });
                }
            }
        }
        // min/max bound the continuous field over the cell: apron 1.
        SuperVoxelGrid::new(size, sdims, cells, 1)
    }
}

/// `mean + amplitude · sin(2π frequency · x + phase)`.
#[inline]
fn sinusoid(mean: f32, amplitude: f32, frequency: [f32; 3], phase: f32, x: Vec3) -> f32 {
    let arg = std::f32::consts::TAU * Vec3::from(frequency).dot(x) + phase;
    mean + amplitude * arg.sin()
}

/// An analytic field seen as extinction (scaled density).
pub struct AnalyticView<'a> {
    pub field: &'a AnalyticField,
    pub scale: f32,
    pub supervoxels: &'a SuperVoxelGrid,
}

impl VolumeAccess for AnalyticView<'_> {
    #[inline]
    fn sigma_t(&self, p: Vec3, _u: Vec3) -> f32 {
        self.scale * self.field.density(p / self.field.n as f32)
    }
    fn needs_jitter(&self) -> bool {
        false
    }
    fn supervoxels(&self) -> &SuperVoxelGrid {
        self.supervoxels
    }
    fn dims(&self) -> [u32; 3] {
        [self.field.n; 3]
    }
}

#[cfg(test)]
mod analytic_test {
    use super::*;
    use fogbank_math::Pcg32;

    fn quadrature(f: &AnalyticField, ray: &Ray, t0: f32, t1: f32) -> f64 {
        let cube = fogbank_math::Aabb::new(Vec3::ZERO, Vec3::splat(f.n as f32));
        let Some((a, b)) = cube.intersect(ray, t0, t1) else {
            return 0.0;
        };
        let m = 200_000;
        let h = (b - a) as f64 / m as f64;
        (0..m)
            .map(|i| {
                let t = a as f64 + (i as f64 + 0.5) * h;
                let p = ray.o.as_dvec3() + t * ray.d.as_dvec3();
                f.density((p / f.n as f64).as_vec3()) as f64
            })
            .sum::<f64>()
            * h
    }

    #[test]
    fn closed_forms_match_quadrature() {
        let kinds = [
            AnalyticKind::Constant { value: 1.5 },
            AnalyticKind::Ramp {
                base: 0.2,
                gradient: [1.0, -0.1, 0.5],
            },
            AnalyticKind::Sinusoid {
                mean: 1.0,
                amplitude: 0.8,
                frequency: [2.0, 1.0, 3.0],
                phase: 0.3,
            },
            AnalyticKind::Slabs {
                value: 4.0,
                count: 3,
                width: 0.05,
                axis: 1,
            },
            AnalyticKind::Sphere {
                value: 2.0,
                radius: 0.4,
            },
        ];
        let mut rng = Pcg32::new(1, 2);
        for kind in kinds {
            let f = AnalyticField::new(kind, 32).unwrap();
            for _ in 0..20 {
                let o = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 64.0
                    - Vec3::splat(16.0);
                let target = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 32.0;
                let ray = Ray::new(o, (target - o).normalize());
                let exact = f.optical_depth(&ray, 0.0, 1e3);
                let q = quadrature(&f, &ray, 0.0, 1e3);
                assert!(
                    (exact - q).abs() <= 1e-3 * q.abs().max(1e-2),
                    "{}: {exact} vs {q}",
                    f.name()
                );
            }
        }
    }

    /// Calls `check(density, super-voxel)` at 20 000 random points of the
    /// 16³ field `f`, whose super-voxels have edge 4.
    fn for_random_points(f: &AnalyticField, stream: u64, mut check: impl FnMut(f32, &SuperVoxel)) {
        let sv = f.supervoxels(4);
        let mut rng = Pcg32::new(5, stream);
        for _ in 0..20_000 {
            let p = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 16.0;
            let c = (p / 4.0).floor().as_ivec3().min(glam::IVec3::splat(3));
            check(f.density(p / 16.0), sv.get([c.x, c.y, c.z]));
        }
    }

    #[test]
    fn bounds_are_conservative() {
        let f = AnalyticField::new(
            AnalyticKind::Sinusoid {
                mean: 1.0,
                amplitude: 0.9,
                frequency: [3.0, 0.0, 1.0],
                phase: 0.0,
            },
            16,
        )
        .unwrap();
        for_random_points(&f, 5, |v, s| {
            assert!(v >= s.min - 1e-5 && v <= s.max + 1e-5);
        });
    }

    #[test]
    fn sphere_bounds_are_conservative() {
        let f = AnalyticField::new(
            AnalyticKind::Sphere {
                value: 3.0,
                radius: 0.37,
            },
            16,
        )
        .unwrap();
        let (mut inside, mut outside) = (0, 0);
        for_random_points(&f, 6, |v, s| {
            assert!(
                v >= s.min && v <= s.max,
                "{v} outside [{}, {}]",
                s.min,
                s.max
            );
            if v > 0.0 {
                inside += 1
            } else {
                outside += 1
            }
        });
        assert!(inside > 1000 && outside > 1000);
    }

    #[test]
    fn invalid_parameters_are_errors() {
        assert!(AnalyticField::new(
            AnalyticKind::Ramp {
                base: 0.0,
                gradient: [-1.0, 0.0, 0.0]
            },
            8
        )
        .is_err());
        assert!(AnalyticField::new(AnalyticKind::Constant { value: 1.0 }, 0).is_err());
    }
}
