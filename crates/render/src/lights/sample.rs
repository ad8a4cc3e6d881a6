//! Sampling the scene's lights from a point in a medium or on a surface
//! (next-event estimation): one light picked in proportion to what it
//! delivers there ([`LightSampler`]), then a
//! direction towards it with its solid-angle pdf (delta lights report
//! `is_delta` and pdf 1).

use super::bvh::LightBvh;
use super::light_bounds::LightBounds;
use super::{Light, SpotCurve};
use fogbank_math::warp::uniform_sphere;
use fogbank_math::Vec3;
use serde::{Deserialize, Serialize};
use std::f32::consts::PI;

#[derive(Clone, Copy, Debug)]
pub struct LightSample {
    pub wi: Vec3,
    /// Incident radiance (delta lights: irradiance-like term, already
    /// divided by the squared distance for point lights).
    pub radiance: Vec3,
    pub pdf: f32,
    /// Distance to the light (∞ for environment and directional lights).
    pub distance: f32,
    pub is_delta: bool,
}

fn luminance(c: Vec3) -> f32 {
    0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z
}

impl Light {
    /// A power proxy for light selection; `radius` is the scene's bounding
    /// radius (distant lights deliver power over its cross-section).
    pub fn power(&self, radius: f32) -> f32 {
        let area = PI * radius * radius;
        match self {
            Light::Constant { radiance } => 4.0 * PI * area * luminance(*radiance),
            Light::Envmap(e) => area * e.power_proxy(),
            Light::Point { intensity, .. } => 4.0 * PI * luminance(*intensity),
            Light::Directional { irradiance, .. } => area * luminance(*irradiance),
            Light::Spot {
                intensity,
                cos_falloff_start,
                cos_total,
                ..
            } => 2.0 * PI * (1.0 - 0.5 * (cos_falloff_start + cos_total)) * luminance(*intensity),
            Light::Area(a) => PI * a.area * luminance(a.radiance),
            Light::Sphere(l) => PI * l.area() * luminance(l.radiance),
            Light::Disk(l) => PI * l.area * luminance(l.radiance),
        }
    }

    /// Radiance arriving along `-dir` from infinity (environment lights only).
    pub fn le(&self, dir: Vec3) -> Vec3 {
        match self {
            Light::Constant { radiance } => *radiance,
            Light::Envmap(e) => e.eval(dir),
            _ => Vec3::ZERO,
        }
    }

    pub fn is_environment(&self) -> bool {
        matches!(self, Light::Constant { .. } | Light::Envmap(_))
    }

    /// Whether the light has one direction from every point (point, spot,
    /// directional): what [`Light::sample_li`] marks `is_delta`.
    pub fn is_delta(&self) -> bool {
        matches!(
            self,
            Light::Point { .. } | Light::Spot { .. } | Light::Directional { .. }
        )
    }

    /// Solid-angle pdf of sampling `wi` with [`Light::sample_li`] (0 for delta lights).
    pub fn pdf_li(&self, wi: Vec3) -> f32 {
        match self {
            Light::Constant { .. } => 1.0 / (4.0 * PI),
            Light::Envmap(e) => e.pdf(wi),
            _ => 0.0,
        }
    }

    /// Solid-angle density at `p` of sampling the point `q` of an
    /// emitting shape seen along unit `wi` (0 for other lights).
    pub fn pdf_solid(&self, p: Vec3, q: Vec3, wi: Vec3) -> f32 {
        match self {
            Light::Area(a) => a.pdf_solid(p, q, wi),
            Light::Sphere(l) => l.pdf_solid(p, q, wi),
            Light::Disk(l) => l.pdf_solid(p, q, wi),
            _ => 0.0,
        }
    }

    /// The sample toward the point `q` of an emitting shape, seen from `p`,
    /// radiance `le(wi)`; the shadow ray stops short of the emitter.
    fn sample_shape(&self, p: Vec3, q: Vec3, le: impl Fn(Vec3) -> Vec3) -> Option<LightSample> {
        let d = q - p;
        let dist = d.length();
        let wi = d / dist;
        let pdf = self.pdf_solid(p, q, wi);
        let radiance = le(wi);
        (dist > 0.0 && pdf > 0.0 && pdf.is_finite() && radiance != Vec3::ZERO).then_some(
            LightSample {
                wi,
                radiance,
                pdf,
                distance: dist * (1.0 - super::area::SHADOW_SHORTEN),
                is_delta: false,
            },
        )
    }

    /// The point of an emitting shape that [`Light::sample_li`] draws from
    /// `p` with `u`, and that sample (`None` for other lights).
    pub fn sample_point_li(&self, p: Vec3, u: [f32; 2]) -> Option<(Vec3, LightSample)> {
        let q = match self {
            Light::Area(a) => a.sample_point(u),
            Light::Sphere(l) => l.sample(p, u)?.q,
            Light::Disk(l) => l.sample_point(u),
            _ => return None,
        };
        let s = self.sample_shape(p, q, |wi| self.le_at(q, wi))?;
        Some((q, s))
    }

    /// Radiance an emitting shape's point `q` sends toward `-wi` (zero on
    /// its dark side and for other lights).
    fn le_at(&self, q: Vec3, wi: Vec3) -> Vec3 {
        match self {
            Light::Area(a) => a.le(wi),
            Light::Sphere(l) => l.le(q, wi),
            Light::Disk(l) => l.le(wi),
            _ => Vec3::ZERO,
        }
    }

    /// The point `q` of an emitting shape seen from `p`, in the area
    /// measure of `q`: the direction toward it, L_e(q → p)·|cos θ_q|/|q − p|²
    /// and the shadow ray's length (stopping short of the emitter). A path
    /// that keeps its point on an area light under reuse (Lin et al. 2021 §4.2)
    /// evaluates its last segment so. `None` for other lights or a
    /// degenerate segment.
    pub fn toward_point(&self, p: Vec3, q: Vec3) -> Option<(Vec3, Vec3, f32)> {
        let g = self.area_factor(p, q);
        if !(g > 0.0 && g.is_finite()) {
            return None;
        }
        let d = q - p;
        let dist = d.length();
        let wi = d / dist;
        Some((
            wi,
            self.le_at(q, wi) * g,
            dist * (1.0 - super::area::SHADOW_SHORTEN),
        ))
    }

    /// |cos θ_q|/|q − p|²: the solid angle at `p` per unit area of an
    /// emitting shape at its point `q` (0 for other lights).
    pub fn area_factor(&self, p: Vec3, q: Vec3) -> f32 {
        let n = match self {
            Light::Area(a) => a.n,
            Light::Disk(l) => l.n,
            Light::Sphere(l) => (q - l.centre) / l.radius,
            _ => return 0.0,
        };
        let d = q - p;
        let dist2 = d.length_squared();
        if dist2 <= 0.0 || dist2.is_nan() {
            return 0.0;
        }
        n.dot(d).abs() / (dist2 * dist2.sqrt())
    }

    pub fn sample_li(&self, p: Vec3, u: [f32; 2]) -> Option<LightSample> {
        match self {
            Light::Constant { radiance } => Some(LightSample {
                wi: uniform_sphere(u),
                radiance: *radiance,
                pdf: 1.0 / (4.0 * PI),
                distance: f32::INFINITY,
                is_delta: false,
            }),
            Light::Envmap(e) => {
                let (wi, radiance, pdf) = e.sample(u);
                (pdf > 0.0).then_some(LightSample {
                    wi,
                    radiance,
                    pdf,
                    distance: f32::INFINITY,
                    is_delta: false,
                })
            }
            Light::Point {
                position,
                intensity,
            } => {
                let d = *position - p;
                let dist2 = d.length_squared();
                (dist2 > 0.0).then(|| {
                    let dist = dist2.sqrt();
                    LightSample {
                        wi: d / dist,
                        radiance: *intensity / dist2,
                        pdf: 1.0,
                        distance: dist,
                        is_delta: true,
                    }
                })
            }
            Light::Spot {
                position,
                direction,
                intensity,
                cos_falloff_start,
                cos_total,
                curve,
            } => {
                let d = *position - p;
                let dist2 = d.length_squared();
                if dist2 <= 0.0 {
                    return None;
                }
                let dist = dist2.sqrt();
                let wi = d / dist;
                let k = spot_falloff(direction.dot(-wi), *cos_falloff_start, *cos_total, *curve);
                (k > 0.0).then(|| LightSample {
                    wi,
                    radiance: *intensity * (k / dist2),
                    pdf: 1.0,
                    distance: dist,
                    is_delta: true,
                })
            }
            Light::Area(_) | Light::Sphere(_) | Light::Disk(_) => {
                self.sample_point_li(p, u).map(|(_, s)| s)
            }
            Light::Directional {
                direction,
                irradiance,
            } => Some(LightSample {
                wi: -*direction,
                radiance: *irradiance,
                pdf: 1.0,
                distance: f32::INFINITY,
                is_delta: true,
            }),
        }
    }
}

/// Falloff of a spotlight: 1 inside the falloff cone, 0 outside the total
/// cone, and in between smoothstep in cos θ (pbrt-v4) or linear in θ
/// (Mitsuba 3).
pub fn spot_falloff(
    cos_theta: f32,
    cos_falloff_start: f32,
    cos_total: f32,
    curve: SpotCurve,
) -> f32 {
    if cos_theta >= cos_falloff_start {
        return 1.0;
    }
    if cos_theta <= cos_total || cos_falloff_start <= cos_total {
        return 0.0;
    }
    match curve {
        SpotCurve::Smoothstep => {
            let x = (cos_theta - cos_total) / (cos_falloff_start - cos_total);
            x * x * (3.0 - 2.0 * x)
        }
        SpotCurve::Linear => {
            let total = cos_total.acos();
            (total - cos_theta.acos()) / (total - cos_falloff_start.acos())
        }
    }
}

/// Where next-event estimation picks a light: a scattering point in a
/// medium sees the whole sky, a surface only the hemisphere it faces.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Vertex {
    Medium = 0,
    Surface = 1,
}

/// How next-event estimation picks among the scene's lights
/// (`[render] light_sampler`).
#[derive(Clone, Copy, Debug, Default, Deserialize, Serialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum LightSelection {
    /// `bvh` once the scene has [`LIGHT_BVH_MIN`] emitting triangles,
    /// `power` below.
    #[default]
    Auto,
    /// In proportion to power alone (a CDF over all lights).
    Power,
    /// Emitting triangles through the light BVH ([`LightBvh`]), as one
    /// entry of the power CDF beside the other lights.
    Bvh,
}

impl LightSelection {
    pub fn is_auto(&self) -> bool {
        *self == LightSelection::Auto
    }
}

/// From this many emitting triangles with power on, `auto` picks them
/// through the light BVH. Its descent costs two importance evaluations
/// per level: on 300 triangles scattered in fog
/// (`scenes/mitsuba/fog_emitters.xml`) it lost at equal time (relMSE 1.21×
/// higher); on the 3200 windows of `scenes/street` it lowers relMSE 1.26×
/// and the variance in fog and on the road 1.36× at equal time
/// (`docs/results/surfaces/README.md`).
pub const LIGHT_BVH_MIN: usize = 1024;

/// Picks lights for next-event estimation (a 1D CDF per [`Vertex`]) in
/// proportion to what they deliver to an unoccluded point: their power
/// (flux onto the scene's bounding sphere). That is right for a point in a
/// medium, which gathers light from every direction, but an environment's
/// power (`4π·πR²·L` for a constant sky) is 4 times the irradiance it
/// gives a surface (`π·L`), which sees one hemisphere of it — so at
/// surfaces environments weigh a quarter of their power. (By power alone, a
/// sunlit ground under a sky drew too few sun samples: 2.7× the variance on
/// `scenes/mitsuba/null_mesh_medium.xml`. Mitsuba 3 picks lights uniformly,
/// pbrt-v4 lights at infinity uniformly.) Lights without power are never
/// picked. With a light BVH the emitting triangles share one CDF entry
/// (their summed power, at the first of them) and the tree picks among
/// them by their importance at the receiving point.
#[derive(Clone, Debug, Default)]
pub struct LightSampler {
    cdf: [Vec<f32>; 2],
    bvh: Option<LightBvh>,
}

impl LightSampler {
    pub fn new(lights: &[Light], radius: f32, selection: LightSelection) -> Self {
        let bvh = light_bvh(lights, radius, selection);
        let cdf = |at: Vertex| {
            let mut weights: Vec<f32> = (lights.iter())
                .map(|l| {
                    let hemisphere = at == Vertex::Surface && l.is_environment();
                    l.power(radius).max(0.0) * if hemisphere { 0.25 } else { 1.0 }
                })
                .collect();
            if let Some(b) = &bvh {
                let area: f32 = weights[b.first..].iter().sum();
                weights[b.first..].fill(0.0);
                weights[b.first] = area;
            }
            let mut acc = 0.0;
            let mut cdf: Vec<f32> = (weights.iter())
                .map(|w| {
                    acc += w;
                    acc
                })
                .collect();
            if acc > 0.0 {
                cdf.iter_mut().for_each(|c| *c /= acc);
            } else {
                cdf.clear();
            }
            cdf
        };
        LightSampler {
            cdf: [cdf(Vertex::Medium), cdf(Vertex::Surface)],
            bvh,
        }
    }

    /// (light index, selection probability) for a point `p` of kind `at`.
    pub fn pick(&self, u: f32, at: Vertex, p: Vec3) -> Option<(usize, f32)> {
        let cdf = &self.cdf[at as usize];
        let i = cdf
            .partition_point(|&c| c <= u)
            .min(cdf.len().checked_sub(1)?);
        match &self.bvh {
            Some(b) if b.holds(i) => {
                // The emitting triangles' shared entry: u rescaled within
                // it descends the tree.
                let lo = b.first.checked_sub(1).map_or(0.0, |k| cdf[k]);
                let width = cdf[b.first] - lo;
                if width <= 0.0 {
                    return None;
                }
                let u = ((u - lo) / width).clamp(0.0, 1.0 - f32::EPSILON / 2.0);
                let (j, pmf) = b.pick(u, p)?;
                Some((j, width * pmf))
            }
            _ => Some((i, self.cdf_pmf(i, at))),
        }
    }

    /// The normalised CDF over the scene's lights for points of kind `at`
    /// (empty when no light has power): what a GPU port needs to pick
    /// lights identically.
    pub fn cdf(&self, at: Vertex) -> &[f32] {
        &self.cdf[at as usize]
    }

    /// The light BVH, when emitting triangles are picked through one.
    pub fn bvh(&self) -> Option<&LightBvh> {
        self.bvh.as_ref()
    }

    /// The probability that [`LightSampler::pick`] at `p` returns light `i`.
    pub fn pmf(&self, i: usize, at: Vertex, p: Vec3) -> f32 {
        match &self.bvh {
            Some(b) if b.holds(i) => self.cdf_pmf(b.first, at) * b.pmf(i, p),
            _ => self.cdf_pmf(i, at),
        }
    }

    /// Light `i`'s entry of the CDF (with a light BVH, the emitting
    /// triangles' shared entry is at the first of them, the others' 0).
    pub fn cdf_pmf(&self, i: usize, at: Vertex) -> f32 {
        let cdf = &self.cdf[at as usize];
        match i {
            0 => cdf.first().copied().unwrap_or(0.0),
            _ => cdf.get(i).map_or(0.0, |c| c - cdf[i - 1]),
        }
    }
}

/// The light BVH over the emitting triangles (which follow the scene's
/// other lights), when `selection` asks for one.
fn light_bvh(lights: &[Light], radius: f32, selection: LightSelection) -> Option<LightBvh> {
    let first = lights.iter().position(|l| matches!(l, Light::Area(_)))?;
    let items: Vec<(u32, LightBounds)> = (lights[first..].iter().enumerate())
        .map(|(k, l)| match l {
            Light::Area(a) => Some((
                (first + k) as u32,
                LightBounds::triangle(
                    [a.p0, a.p0 + a.e1, a.p0 + a.e2],
                    a.n,
                    l.power(radius).max(0.0),
                ),
            )),
            _ => None,
        })
        .collect::<Option<_>>()?;
    let powered = items.iter().filter(|(_, b)| b.phi > 0.0).count();
    let wanted = match selection {
        LightSelection::Power => false,
        LightSelection::Bvh => true,
        LightSelection::Auto => powered >= LIGHT_BVH_MIN,
    };
    if !wanted {
        return None;
    }
    LightBvh::build(first, lights.len() - first, &items)
}
