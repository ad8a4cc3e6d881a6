//! Candidate generation (seed 002 §3.2–3.3, §4.1, Fig. 3): M random walks
//! per pixel, each a source of several candidate paths streamed into the
//! pixel's reservoir. Distances come from regular tracking through the
//! conservative mips (mip 1 on the primary segment, mip 2 after it), whose
//! pdf p(z) = T*(z)·σ_t*(z) has a closed form that reuse needs (§3.3).
//!
//! At every vertex x_k a walk offers a scattering path (next-event
//! estimation toward one light picked by power, p = p_walk·pmf·pdf) and, in
//! an emissive medium, an emission path; a primary ray that escapes offers
//! the environment behind the medium (Eq. 1, second term; p = T* of the
//! whole ray). The candidate target p̂ is F with T* on walk segments (the
//! same T* as in p, so it cancels), the full-resolution σ_s at vertices and
//! T̃ of mip 2 on the NEE segment; the resampling weight is w = p̂/p. The
//! candidates of one walk lie in disjoint path spaces and are each drawn
//! once per walk, so the walk's sum Σ p̂/p needs no 1/n_j, and a walk counts
//! M = 1 (Eq. 19–21). Russian roulette by albedo after x_3 when K > 3
//! (§6.1) enters p. Surfaces (opaque occluders, `shared/occluders.rs`) end
//! a walk and veto the NEE and escape candidates they block.

use super::integrator::{FrameData, Restir};
use super::path::{PathEnd, PathSample};
use super::reservoir::Reservoir;
use super::target::{environment, luminance};
use super::volume::{sigma_t, track, SegmentT};
use crate::integrators::shared::occluders::{first_surface, visible};
use crate::lights::sample::Vertex;
use crate::world::phase::HenyeyGreenstein;
use fogbank_math::{Pcg32, Ray, Vec3};

impl Restir {
    /// The pixel's reservoir after its M walks, moved to the reuse target
    /// (the authors' code re-targets the chosen path at the end of the
    /// candidate pass, §4.3) so that temporal and spatial reuse combine
    /// weights of one target.
    pub fn candidates(
        &self,
        data: &FrameData,
        pixel: Option<usize>,
        ray0: &Ray,
        rng: &mut Pcg32,
        lookups: &mut u32,
    ) -> Reservoir<PathSample> {
        let mut res = Reservoir::default();
        for _ in 0..self.params.candidates {
            res.count(1.0);
            self.walk(data, ray0, rng, &mut res, lookups);
        }
        if let Some(y) = res.y {
            let p_hat = self.p_hat(data, pixel, ray0, &y, lookups);
            res.retarget(p_hat);
        }
        res
    }

    /// One random walk, streaming its candidates into `res`.
    fn walk(
        &self,
        data: &FrameData,
        ray0: &Ray,
        rng: &mut Pcg32,
        res: &mut Reservoir<PathSample>,
        lookups: &mut u32,
    ) {
        let p = &self.params;
        let world = data.world;
        let m = &world.media[0];
        let full = &m.medium;
        let hg = HenyeyGreenstein { g: m.phase_g };
        let mut y = PathSample::BACKGROUND;
        if p.vertex_reuse {
            y.fixed_from = 1;
        }
        // ∏ 1/z_i² over the fixed vertices (vertex reuse): p and p̂ in the
        // volume measure of a fixed vertex, so that the retargeting ratio
        // compares values in the measure reuse evaluates p̂ in.
        let mut g_fixed = 1.0f64;
        let mut ray = *ray0;
        // ∏ σ_s/σ_t* (and 1/q of roulette) up to the current vertex, RGB.
        let mut beta = Vec3::ONE;
        // The walk's pdf up to the current vertex, in (ω, z) measure.
        let mut p_walk = 1.0f64;
        for k in 1..=p.max_depth as usize {
            let level = if k == 1 {
                p.primary_mip
            } else {
                p.indirect_mip
            };
            let flight = track(data.mips.level(full, level), level == 0, &ray, rng);
            *lookups += flight.lookups;
            // A surface ends the walk: F is 0 past it (occluders.rs).
            let t_surface = first_surface(world, &ray);
            let Some(t) = flight.t.filter(|&t| t < t_surface) else {
                if k == 1 && t_surface == f32::INFINITY {
                    // p = T* of the whole ray, p̂ = T*·lum(L_env): w = lum(L_env).
                    let w = luminance(environment(world, ray.d));
                    let p_escape = (-flight.tau).exp();
                    res.stream(
                        PathSample::BACKGROUND,
                        w,
                        w * p_escape as f32,
                        rng.next_f32(),
                    );
                }
                return;
            };
            let x = ray.at(t);
            p_walk *= (-flight.tau).exp() * flight.sigma_t;
            let sigma = sigma_t(full, x);
            if sigma <= 0.0 || flight.sigma_t <= 0.0 {
                // F is 0 for every path through x_k.
                return;
            }
            let albedo = m.albedo_at(x);
            y.k = k as u8;
            y.z[k - 1] = t;
            y.x[k - 1] = x;
            if y.is_fixed(k - 1) {
                // As `evaluate` computes it: 1/z² in f32.
                g_fixed *= (1.0 / (t * t)) as f64;
            }
            let inv_sigma_star = 1.0 / flight.sigma_t as f32;
            if m.emission.is_some() {
                let mut ye = y;
                ye.end = PathEnd::Emission;
                let mut p_e = p_walk * g_fixed;
                if k >= 2 && !ye.is_fixed(k - 1) {
                    // An emitter is kept fixed in space under reuse.
                    ye.fixed_from = (k - 1) as u8;
                    p_e *= (1.0 / (t * t)) as f64;
                }
                let w = luminance(beta * m.emitted(x, albedo) * (sigma * inv_sigma_star));
                res.stream(ye, w, w * p_e as f32, rng.next_f32());
            }
            self.nee_candidate(
                data,
                &y,
                x,
                ray.d,
                beta * albedo * (sigma * inv_sigma_star),
                p_walk * g_fixed,
                &hg,
                rng,
                res,
                lookups,
            );
            beta *= albedo * (sigma * inv_sigma_star);
            if k == p.max_depth as usize {
                return;
            }
            let (wi, pdf) = hg.sample(-ray.d, [rng.next_f32(), rng.next_f32()]);
            p_walk *= pdf as f64;
            y.dir[k - 1] = wi;
            if k as u32 >= p.rr_depth {
                let q = albedo.max_element().clamp(0.0, 1.0);
                if rng.next_f32() >= q {
                    return;
                }
                p_walk *= q as f64;
                beta /= q;
            }
            ray = Ray::new(x, wi);
        }
    }

    /// The scattering candidate at `x` (reached along `d`; `beta` already
    /// holds the σ_s/σ_t* of x): next-event estimation toward one light
    /// picked by power, T̃ of the NEE mip on the shadow segment (Fig. 11).
    #[allow(clippy::too_many_arguments)]
    fn nee_candidate(
        &self,
        data: &FrameData,
        y: &PathSample,
        x: Vec3,
        d: Vec3,
        beta: Vec3,
        p_walk: f64,
        hg: &HenyeyGreenstein,
        rng: &mut Pcg32,
        res: &mut Reservoir<PathSample>,
        lookups: &mut u32,
    ) {
        let world = data.world;
        let full = &world.media[0].medium;
        let u_pick = rng.next_f32();
        let u = [rng.next_f32(), rng.next_f32()];
        let u_keep = rng.next_f32();
        let Some((li, pmf)) = data.lights.pick(u_pick, Vertex::Medium, x) else {
            return;
        };
        let Some(ls) = world.lights[li].sample_li(x, u) else {
            return;
        };
        let fp = hg.pdf(-d, ls.wi);
        if fp <= 0.0
            || ls.radiance == Vec3::ZERO
            || !visible(world, &Ray::new(x, ls.wi), ls.distance)
        {
            return;
        }
        let t_nee = if self.params.nee_transmittance {
            SegmentT::Marched {
                medium: data.mips.level(full, self.params.nee_mip),
                step: 1.0,
                primary: None,
            }
            .eval(full, &Ray::new(x, ls.wi), ls.distance, lookups)
        } else {
            1.0
        };
        let p_light = pmf * if ls.is_delta { 1.0 } else { ls.pdf };
        let w = luminance(beta * ls.radiance * (fp * t_nee)) / p_light;
        let mut yl = *y;
        yl.end = PathEnd::Light;
        yl.light = li as u16;
        yl.light_dir = ls.wi;
        res.stream(yl, w, w * (p_walk * p_light as f64) as f32, u_keep);
    }
}
