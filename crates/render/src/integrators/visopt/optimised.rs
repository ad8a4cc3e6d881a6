//! The optimised extinction μ' of Lerzer and Dachsbacher 2025 Eq. 8 as a volume view: every
//! lookup returns μ_t(y) · p / (p + (1 − g(y))^{2λ} h(y)), with h from the
//! ray's importance list (Eq. 7, corrected) and g the exact importance at y
//! (checklist §1: its data is already fetched). μ' ≤ μ, so the medium's own
//! super-voxel majorants still bound it and delta/ratio tracking through
//! this view stay unbiased for μ'; μ'_n = μ̄ − μ'_t is implicit in them.
//!
//! Lengths in h are in the paper's normalised units: the medium scaled so
//! its longest side spans [−1, 1] (`unit` = 2 / longest world extent), so
//! p, q, r, λ = 1, 70, 30, 1 mean what they mean in the paper whatever the
//! file's units (a head in millimetres is not optimised 100× harder).

use super::segments::{self, Segment};
use crate::world::importance::ImportanceInputs;
use crate::world::medium::SceneMedium;
use fogbank_math::{Ray, Vec3};
use fogbank_volume::{SuperVoxelGrid, VolumeAccess};

/// The importance list of one ray and where its t axis lies.
#[derive(Clone, Copy, Debug)]
pub struct RayList<'a> {
    pub list: &'a [Segment],
    /// K(z) = ∫ₓᶻ k̃².
    pub big_k_z: f32,
    /// L, the ray's length inside the medium in normalised units.
    pub length: f32,
    /// Ray parameter of t = 0 (the volume entry x; for a light ray, the
    /// end on the light's side).
    pub origin: f32,
    /// +1: t grows with the ray parameter (camera rays); −1: it shrinks
    /// (light rays, whose x is on the light's side).
    pub sign: f32,
}

impl RayList<'_> {
    /// t in normalised units of ray parameter `s` (world units along a
    /// unit-direction ray).
    #[inline]
    pub fn t_of(&self, s: f32, unit: f32) -> f32 {
        ((s - self.origin) * self.sign * unit).clamp(0.0, self.length)
    }
}

/// The coefficients of Eq. 7–8.
#[derive(Clone, Copy, Debug)]
pub struct Weights {
    pub p: f32,
    pub q: f32,
    pub r: f32,
    pub lambda: f32,
}

/// μ'/μ at ray parameter `s` and world point `world`, given μ_t there.
#[inline]
pub fn factor(
    m: &SceneMedium,
    list: &RayList,
    w: Weights,
    unit: f32,
    s: f32,
    world: Vec3,
    sigma_t: f32,
) -> f32 {
    let t = list.t_of(s, unit);
    let h = segments::h(list.list, list.big_k_z, list.length, t, w.r, w.q);
    if h <= 0.0 {
        return 1.0;
    }
    let g = importance_at(m, world, sigma_t);
    segments::mu_factor(w.p, g, w.lambda, h)
}

/// The exact importance at a world point, σ_t already known. Rules give
/// extinction and gradients in world units.
#[inline]
pub fn importance_at(m: &SceneMedium, p: Vec3, sigma_t: f32) -> f32 {
    m.importance.eval(p, || ImportanceInputs {
        p,
        sigma_t,
        scalar: m.scalar_at(p),
        gradient: if m.importance.needs_gradient() {
            m.gradient_sigma_t(p).length()
        } else {
            0.0
        },
    })
}

/// A medium view whose extinction is μ' along one ray (index-space `ray`,
/// whose parameter equals the world ray's).
pub struct Optimised<'a, V> {
    pub inner: &'a V,
    pub medium: &'a SceneMedium,
    pub ray: Ray,
    pub list: RayList<'a>,
    pub weights: Weights,
    pub unit: f32,
}

impl<V: VolumeAccess> VolumeAccess for Optimised<'_, V> {
    #[inline]
    fn sigma_t(&self, p: Vec3, u: Vec3) -> f32 {
        let sigma = self.inner.sigma_t(p, u);
        if sigma <= 0.0 {
            return sigma;
        }
        // The lookup's ray parameter: p = o + s·d.
        let s = (p - self.ray.o).dot(self.ray.d) / self.ray.d.length_squared();
        let world = self
            .medium
            .medium
            .index_to_world
            .transform_point3(p.as_dvec3())
            .as_vec3();
        sigma
            * factor(
                self.medium,
                &self.list,
                self.weights,
                self.unit,
                s,
                world,
                sigma,
            )
    }
    fn needs_jitter(&self) -> bool {
        self.inner.needs_jitter()
    }
    fn supervoxels(&self) -> &SuperVoxelGrid {
        self.inner.supervoxels()
    }
    fn dims(&self) -> [u32; 3] {
        self.inner.dims()
    }
}
