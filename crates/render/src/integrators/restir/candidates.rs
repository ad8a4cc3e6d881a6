//! Candidate generation (Lin et al. 2021 §3.2–3.3, §4.1, Fig. 3): M random walks
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
//! (§6.1) enters p. A walk that reaches a surface before its next
//! collision (probability T* up to it) makes it a vertex ([`super::surface`]):
//! an emitter seen from the camera is a candidate, light sampling leaves
//! from it with the BSDF, and BSDF sampling continues the walk. Surfaces
//! veto the NEE and escape candidates they block.

use super::integrator::{FrameData, Restir};
use super::path::{PathEnd, PathSample};
use super::reservoir::Reservoir;
use super::surface::SurfaceVertex;
use super::target::{environment, luminance};
use super::volume::{sigma_t, track, SegmentT};
use crate::integrators::shared::occluders::visible;
use crate::lights::sample::Vertex;
use fogbank_estimators::distance::TrackedFlight;
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
        let mut s = Stream {
            data,
            rng,
            res: &mut res,
            lookups: &mut *lookups,
        };
        for _ in 0..self.params.candidates {
            s.res.count(1.0);
            self.walk(&mut s, ray0);
        }
        if let Some(y) = res.y {
            let p_hat = self.p_hat(data, pixel, ray0, &y, lookups);
            res.retarget(p_hat);
        }
        res
    }

    /// One random walk, streaming its candidates into the reservoir.
    fn walk(&self, s: &mut Stream, ray0: &Ray) {
        let (p, data) = (&self.params, s.data);
        let world = data.world;
        let full = &world.media[0].medium;
        let mut y = PathSample::BACKGROUND;
        if p.vertex_reuse {
            y.fixed_from = 1;
        }
        let mut w = Walk {
            g_fixed: 1.0,
            ray: *ray0,
            beta: Vec3::ONE,
            p_walk: 1.0,
        };
        for k in 1..=p.max_depth as usize {
            let level = if k == 1 {
                p.primary_mip
            } else {
                p.indirect_mip
            };
            let ray = w.ray;
            let surface = SurfaceVertex::closest(world, &ray);
            let t_surface = surface.map_or(f32::INFINITY, |v| v.hit.t);
            let flight = track(
                data.mips.level(full, level),
                level == 0,
                &ray,
                t_surface,
                s.rng,
            );
            *s.lookups += flight.lookups;
            let Some(t) = flight.t.filter(|&t| t < t_surface) else {
                // The walk passes every collision up to the surface (or
                // out of the medium): probability T* of the range.
                let p_pass = (-flight.tau).exp();
                let Some(v) = surface else {
                    if k == 1 {
                        // p = T* of the whole ray, p̂ = T*·lum(L_env): w = lum(L_env).
                        let w = luminance(environment(world, ray.d));
                        let u = s.rng.next_f32();
                        s.res
                            .stream(PathSample::BACKGROUND, w, w * p_pass as f32, u);
                    }
                    return;
                };
                w.p_walk *= p_pass;
                if !self.surface_vertex(s, &mut y, &mut w, &v, k) {
                    return;
                }
                continue;
            };
            if !self.medium_vertex(s, &mut y, &mut w, t, &flight, k) {
                return;
            }
        }
    }

    /// Vertex x_k of the walk in the medium, at distance `t` along the
    /// walk's ray where `flight` collided: emission (an emitter is kept
    /// fixed in space under reuse), next-event estimation with the phase
    /// function, then phase sampling. Returns whether the walk goes on.
    fn medium_vertex(
        &self,
        s: &mut Stream,
        y: &mut PathSample,
        w: &mut Walk,
        t: f32,
        flight: &TrackedFlight,
        k: usize,
    ) -> bool {
        let m = &s.data.world.media[0];
        let full = &m.medium;
        let hg = m.phase;
        let ray = w.ray;
        let x = ray.at(t);
        w.p_walk *= (-flight.tau).exp() * flight.sigma_t;
        let sigma = sigma_t(full, x);
        if sigma <= 0.0 || flight.sigma_t <= 0.0 {
            // F is 0 for every path through x_k.
            return false;
        }
        let albedo = m.albedo_at(x);
        y.k = k as u8;
        y.z[k - 1] = t;
        y.x[k - 1] = x;
        if y.is_fixed(k - 1) {
            // As `evaluate` computes it: 1/z² in f32.
            w.g_fixed *= (1.0 / (t * t)) as f64;
        }
        let inv_sigma_star = 1.0 / flight.sigma_t as f32;
        if m.emission.is_some() {
            let mut ye = *y;
            ye.end = PathEnd::Emission;
            let mut p_e = w.p_walk * w.g_fixed;
            if k >= 2 && !ye.is_fixed(k - 1) {
                ye.fixed_from = (k - 1) as u8;
                p_e *= (1.0 / (t * t)) as f64;
            }
            let we = luminance(w.beta * m.emitted(x, albedo) * (sigma * inv_sigma_star));
            let u = s.rng.next_f32();
            s.res.stream(ye, we, we * p_e as f32, u);
        }
        let scatter = |wi: Vec3| Vec3::splat(hg.pdf(-ray.d, wi));
        let at = NeeVertex {
            from: Ray::new(x, ray.d),
            surface: None,
            beta: w.beta * albedo * (sigma * inv_sigma_star),
            p_walk: w.p_walk * w.g_fixed,
        };
        self.nee_candidate(s, y, &at, &scatter);
        w.beta *= albedo * (sigma * inv_sigma_star);
        if k == self.params.max_depth as usize {
            return false;
        }
        let (wi, pdf) = hg.sample(-ray.d, [s.rng.next_f32(), s.rng.next_f32()]);
        w.p_walk *= pdf as f64;
        y.dir[k - 1] = wi;
        if !self.roulette(w, k, albedo, s.rng) {
            return false;
        }
        w.ray = Ray::new(x, wi);
        true
    }

    /// Vertex x_k of the walk on surface `v`: an emitter seen straight from
    /// the camera is a candidate (k = 1; later vertices reach emitters by
    /// light sampling), then next-event estimation with the BSDF, then BSDF
    /// sampling. Returns whether the walk goes on.
    fn surface_vertex(
        &self,
        s: &mut Stream,
        y: &mut PathSample,
        w: &mut Walk,
        v: &SurfaceVertex,
        k: usize,
    ) -> bool {
        let d = w.ray.d;
        y.k = k as u8;
        y.surface |= 1 << (k - 1);
        y.z[k - 1] = v.hit.t;
        y.x[k - 1] = v.hit.p;
        if k == 1 {
            // p = T* up to the surface, p̂ = T*·lum(L_e): w = lum(L_e).
            let we = luminance(v.emitted(s.data.world, d));
            if we > 0.0 {
                let mut ye = *y;
                ye.end = PathEnd::Emission;
                let u = s.rng.next_f32();
                s.res.stream(ye, we, we * w.p_walk as f32, u);
            }
        }
        let scatter = |wi: Vec3| v.scatter(d, wi);
        let at = NeeVertex {
            from: Ray::new(v.hit.p, d),
            surface: Some(v),
            beta: w.beta,
            p_walk: w.p_walk,
        };
        self.nee_candidate(s, y, &at, &scatter);
        if k == self.params.max_depth as usize {
            return false;
        }
        let rng = &mut *s.rng;
        let wo = v.frame.to_local(-d);
        let uc = rng.next_f32();
        let Some(bs) = v.bsdf.sample(wo, uc, [rng.next_f32(), rng.next_f32()]) else {
            return false;
        };
        let weight = bs.weight();
        if bs.delta || !(bs.pdf > 0.0 && weight.is_finite() && weight.max_element() > 0.0) {
            return false;
        }
        let wi = v.frame.to_world(bs.wi);
        w.p_walk *= bs.pdf as f64;
        w.beta *= weight;
        y.dir[k - 1] = wi;
        if !self.roulette(w, k, weight, rng) {
            return false;
        }
        w.ray = v.leave(wi);
        true
    }

    /// Russian roulette after vertex x_k from `rr_depth` on (§6.1), on the
    /// vertex's albedo (a surface's f·|cos|/pdf); it enters p.
    fn roulette(&self, w: &mut Walk, k: usize, albedo: Vec3, rng: &mut Pcg32) -> bool {
        if (k as u32) < self.params.rr_depth {
            return true;
        }
        let q = albedo.max_element().clamp(0.0, 1.0);
        if rng.next_f32() >= q {
            return false;
        }
        w.p_walk *= q as f64;
        w.beta /= q;
        true
    }

    /// The scattering candidate at vertex `at` (see [`NeeVertex`]): next-event estimation toward one light
    /// picked by power, with the vertex's `scatter` factor (phase function,
    /// or f_s·|cos θ|) and T̃ of the NEE mip on the shadow segment (Fig. 11).
    /// An emitting shape's sampled point is kept with the path, in its area
    /// measure: p̂ and p both carry |cos θ_q|/|q − x|², so w is unchanged.
    fn nee_candidate(
        &self,
        s: &mut Stream,
        y: &PathSample,
        at: &NeeVertex,
        scatter: &dyn Fn(Vec3) -> Vec3,
    ) {
        let (data, rng) = (s.data, &mut *s.rng);
        let (from, surface, beta, p_walk) = (&at.from, at.surface, at.beta, at.p_walk);
        let world = data.world;
        let full = &world.media[0].medium;
        let x = from.o;
        let u_pick = rng.next_f32();
        let u = [rng.next_f32(), rng.next_f32()];
        let u_keep = rng.next_f32();
        let at = if surface.is_some() {
            Vertex::Surface
        } else {
            Vertex::Medium
        };
        let Some((li, pmf)) = data.lights.pick(u_pick, at, x) else {
            return;
        };
        let light = &world.lights[li];
        let (ls, q) = if light.is_shape() {
            let Some((q, ls)) = light.sample_point_li(x, u) else {
                return;
            };
            (ls, Some(q))
        } else {
            let Some(ls) = light.sample_li(x, u) else {
                return;
            };
            (ls, None)
        };
        let fs = scatter(ls.wi);
        let shadow = surface.map_or(Ray::new(x, ls.wi), |v| v.leave(ls.wi));
        if fs == Vec3::ZERO || ls.radiance == Vec3::ZERO || !visible(world, &shadow, ls.distance) {
            return;
        }
        let t_nee = if self.params.nee_transmittance {
            SegmentT::Marched {
                medium: data.mips.level(full, self.params.nee_mip),
                step: 1.0,
                primary: None,
            }
            .eval(full, &shadow, ls.distance, s.lookups)
        } else {
            1.0
        };
        let p_light = pmf * if ls.is_delta { 1.0 } else { ls.pdf };
        let w = luminance(beta * ls.radiance * (fs * t_nee)) / p_light;
        let mut yl = *y;
        yl.end = PathEnd::Light;
        yl.light = li as u16;
        yl.light_dir = ls.wi;
        // The area measure of a point on a shape: |cos θ_q|/|q − x|².
        let mut p_y = p_walk * p_light as f64;
        if let Some(q) = q {
            yl.light_point = q;
            p_y *= light.area_factor(x, q) as f64;
        }
        s.res.stream(yl, w, w * p_y as f32, u_keep);
    }
}

/// What the vertices of one pixel's walks share: the frame, the pixel's
/// reservoir the candidates stream into, the random stream and the lookup
/// counter.
struct Stream<'a> {
    data: &'a FrameData<'a>,
    rng: &'a mut Pcg32,
    res: &'a mut Reservoir<PathSample>,
    lookups: &'a mut u32,
}

/// A vertex offering a next-event candidate: `from.o`, reached along
/// `from.d`, on `surface` or (`None`) in the medium; `beta` already holds
/// the vertex's σ_s/σ_t*, `p_walk` the walk's pdf up to it.
struct NeeVertex<'v> {
    from: Ray,
    surface: Option<&'v SurfaceVertex>,
    beta: Vec3,
    p_walk: f64,
}

/// A walk's state between vertices: its ray, throughput ∏ σ_s/σ_t* (and
/// f·|cos|/pdf, 1/q), pdf in the (ω, z) measure and ∏ 1/z² over fixed
/// vertices (vertex reuse), so that p and p̂ are in the measure reuse
/// evaluates p̂ in.
struct Walk {
    ray: Ray,
    beta: Vec3,
    p_walk: f64,
    g_fixed: f64,
}
