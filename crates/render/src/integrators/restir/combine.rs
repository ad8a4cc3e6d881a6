//! Combining reservoirs into one pixel's (Lin et al. 2021 §2.5, §4.3–4.4; Eq. 8–11
//! with unequal M): the one rule temporal and spatial reuse share. Input 0
//! is the receiving pixel q (its reservoir's p̂ is p̂_q); every input i
//! carries its reservoir, its pixel's primary ray and the frame data its
//! target is evaluated with (the previous frame's camera, volume and lights
//! for the temporal input), so p̂_i(x) is pixel i's target at any path x.
//!
//! MIS weights (the resampling weight of input i is m_i·p̂_q(x_i)·W_i·ΣM):
//! - Talbot (default): m_i = M_i p̂_i(x_i) / Σ_j M_j p̂_j(x_i) (Eq. 11);
//! - stochastic (Eq. 10): M_i/ΣM while streaming, then the selected y from
//!   input r is re-weighted by M_r p̂_r(y) / Σ_j M_j p̂_j(y) · ΣM/M_r;
//! - uniform: M_i/ΣM (Eq. 9), biased where some p̂_j(y) = 0 (kept for the
//!   power check of the unbiasedness test);
//! - pairwise (beyond the paper): each neighbour shares a 1/N slice with
//!   the pixel only ([`pairwise_canonical`], [`pairwise_neighbour`]): 2N
//!   target evaluations for N neighbours instead of Talbot's N(N + 1); with
//!   one other input (temporal reuse) it is Talbot.

use super::integrator::{FrameData, Restir};
use super::params::ReuseMis;
use super::path::PathSample;
use super::reservoir::{pairwise_canonical, pairwise_neighbour, stream_input, talbot, Reservoir};
use fogbank_math::{Pcg32, Ray};

/// Most inputs of one combination: the pixel and up to 32 neighbours.
pub const MAX_INPUTS: usize = 33;

/// One input of a combination.
pub struct Input<'a> {
    pub res: Reservoir<PathSample>,
    /// The pixel's index (for its primary-ray T̃ table) and centre ray.
    pub pixel: usize,
    pub ray: Ray,
    pub data: &'a FrameData<'a>,
}

impl Restir {
    /// The combined reservoir of `inputs[0]`'s pixel.
    pub fn combine(
        &self,
        inputs: &[Input],
        mis: ReuseMis,
        rng: &mut Pcg32,
        lookups: &mut u32,
    ) -> Reservoir<PathSample> {
        let n = inputs.len();
        // Fixed-size scratch: no allocation per pixel (neighbours ≤ 32).
        assert!(n <= MAX_INPUTS, "at most {MAX_INPUTS} reuse inputs");
        let mut m_buf = [0.0f32; MAX_INPUTS];
        for (b, i) in m_buf.iter_mut().zip(inputs) {
            *b = i.res.m;
        }
        let m = &m_buf[..n];
        let m_total: f32 = m.iter().sum();
        // p̂_j(x_i) for the inputs j whose value mis needs.
        let p_hat_at = |i: usize, j: usize, lookups: &mut u32| -> f32 {
            let (xi, into) = (&inputs[i], &inputs[j]);
            match xi.res.y {
                None => 0.0,
                Some(_) if i == j => xi.res.p_hat,
                Some(y) => self.p_hat(into.data, Some(into.pixel), &into.ray, &y, lookups),
            }
        };
        let mut out = Reservoir::default();
        let mut chosen = None;
        let mut row_buf = [0.0f32; MAX_INPUTS];
        let row = &mut row_buf[..n];
        for i in 0..n {
            let u = rng.next_f32();
            let Some(y) = inputs[i].res.y else { continue };
            let w_i = inputs[i].res.contribution_weight();
            if w_i <= 0.0 {
                continue;
            }
            let (p_hat_q, weight) = match mis {
                ReuseMis::Talbot => {
                    for (j, r) in row.iter_mut().enumerate() {
                        *r = p_hat_at(i, j, lookups);
                    }
                    (row[0], talbot(i, m, row))
                }
                ReuseMis::Pairwise if i == 0 => {
                    for (j, r) in row.iter_mut().enumerate() {
                        *r = p_hat_at(0, j, lookups);
                    }
                    (row[0], pairwise_canonical(m, row))
                }
                ReuseMis::Pairwise => {
                    let p_hat_0 = p_hat_at(i, 0, lookups);
                    let own = inputs[i].res.p_hat;
                    (p_hat_0, pairwise_neighbour(i, m, own, p_hat_0))
                }
                ReuseMis::Stochastic | ReuseMis::Uniform => {
                    (p_hat_at(i, 0, lookups), m[i] / m_total)
                }
            };
            if stream_input(&mut out, y, w_i, weight, m_total, p_hat_q, u) {
                chosen = Some(i);
            }
        }
        out.count(m_total);
        if let (ReuseMis::Stochastic, Some(r), Some(_)) = (mis, chosen, out.y) {
            // Eq. 10 for unequal M: W = m_r(y)·w_sum/(M_r p̂_q(y)).
            let den: f32 = (0..n).map(|j| m[j] * p_hat_at(r, j, lookups)).sum();
            let num = m_total * inputs[r].res.p_hat;
            out.w_sum = if den > 0.0 {
                out.w_sum * num / den
            } else {
                0.0
            };
        }
        out
    }
}
