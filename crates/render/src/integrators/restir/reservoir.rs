//! The reservoir of weighted reservoir sampling (Lin et al. 2021 §2.5, Chao 1982)
//! and the rules that combine reservoirs (Eq. 8–11).
//!
//! Convention (as the authors' code): a candidate's resampling weight is
//! w = p̂/p (Eq. 5), the reservoir keeps one candidate y with probability
//! w/w_sum (Eq. 7) and the count M of candidates it stands for; its
//! unbiased contribution weight is W = w_sum / (M p̂(y)) (Eq. 6, 21), so
//! F(y)·W estimates ∫F. Combining reservoirs i (each with its sample x_i,
//! contribution weight W_i and count M_i) into pixel q's target p̂_q streams
//! w_i = m_i · p̂_q(x_i) · W_i · ΣM with the generalised Talbot weights
//! m_i = M_i p̂_i(x_i) / Σ_j M_j p̂_j(x_i) (Eq. 11 for unequal M), so that
//! the combined W stays w_sum / (M p̂(y)).

/// A reservoir holding at most one sample `y`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Reservoir<Y> {
    pub y: Option<Y>,
    /// Σ of the resampling weights streamed so far.
    pub w_sum: f32,
    /// Candidates the reservoir stands for (M; may be fractional after a cap).
    pub m: f32,
    /// p̂(y) under the reservoir's current target.
    pub p_hat: f32,
}

impl<Y> Default for Reservoir<Y> {
    fn default() -> Self {
        Reservoir {
            y: None,
            w_sum: 0.0,
            m: 0.0,
            p_hat: 0.0,
        }
    }
}

impl<Y: Copy> Reservoir<Y> {
    /// Streams candidate `y` with resampling weight `w` and target value
    /// `p_hat`, keeping it with probability w / w_sum (Eq. 7; `u` uniform in
    /// [0, 1)). A weight that is not finite and positive is never kept (it
    /// adds nothing to w_sum). Counts are added separately ([`Self::count`]):
    /// in Lin et al. 2021 a whole random walk counts M = 1 however many candidates
    /// it streams (Eq. 19–21). Returns whether `y` was kept.
    #[inline]
    pub fn stream(&mut self, y: Y, w: f32, p_hat: f32, u: f32) -> bool {
        if !(w > 0.0 && w.is_finite()) {
            return false;
        }
        self.w_sum += w;
        if u * self.w_sum < w {
            self.y = Some(y);
            self.p_hat = p_hat;
            true
        } else {
            false
        }
    }

    /// Adds `m` to the candidate count M.
    #[inline]
    pub fn count(&mut self, m: f32) {
        self.m += m;
    }

    /// The unbiased contribution weight W = w_sum / (M p̂(y)); 0 for an
    /// empty reservoir or p̂(y) = 0 (the checklist's recommendation).
    #[inline]
    pub fn contribution_weight(&self) -> f32 {
        if self.y.is_some() && self.p_hat > 0.0 && self.m > 0.0 {
            let w = self.w_sum / (self.m * self.p_hat);
            if w.is_finite() {
                return w;
            }
        }
        0.0
    }

    /// Caps M at `cap` (the temporal Q·M of §2.5), scaling w_sum alike so
    /// that W is unchanged.
    #[inline]
    pub fn cap(&mut self, cap: f32) {
        if self.m > cap && cap > 0.0 {
            self.w_sum *= cap / self.m;
            self.m = cap;
        }
    }

    /// Moves the reservoir to a new target whose value at `y` is `p_hat`,
    /// scaling w_sum by p̂_new / p̂_old (the authors' code, §4.3: the
    /// candidates' T* target re-weighted with the reuse T̃ before reuse).
    /// W = w_sum / (M p̂) is unchanged; the weights it will be combined with
    /// are then on the new target's scale.
    #[inline]
    pub fn retarget(&mut self, p_hat: f32) {
        if self.p_hat > 0.0 {
            self.w_sum *= p_hat / self.p_hat;
        } else {
            self.w_sum = 0.0;
        }
        self.p_hat = p_hat;
    }
}

/// Generalised Talbot MIS weight of input `i` at its own sample x_i:
/// M_i p̂_i(x_i) / Σ_j M_j p̂_j(x_i), where `p_hat_at_xi[j]` = p̂_j(x_i)
/// (each p̂_j evaluated on pixel j's ray) and `m[j]` = M_j. 0 when no input
/// could have produced x_i.
pub fn talbot(i: usize, m: &[f32], p_hat_at_xi: &[f32]) -> f32 {
    let den: f32 = m.iter().zip(p_hat_at_xi).map(|(m, p)| m * p).sum();
    if den > 0.0 && den.is_finite() {
        m[i] * p_hat_at_xi[i] / den
    } else {
        0.0
    }
}

/// Pairwise MIS (beyond Lin et al. 2021; Bitterli's 2022 dissertation, with the
/// confidence weights M of Lin et al. 2022): input 0 is the canonical
/// (receiving) pixel and each of the N = `m.len()` − 1 neighbours shares a
/// 1/N slice of the weight with it only, so a combination evaluates 2N
/// targets instead of Talbot's N(N + 1). For a neighbour i at its sample
/// x_i, with `own` = p̂_i(x_i) and `p_hat_0` = p̂_0(x_i):
/// m_i = (1/N)·M_i p̂_i / (M_i p̂_i + (M_0/N) p̂_0).
/// The weights sum to 1 wherever p̂_0 > 0 — the only paths the receiving
/// pixel's integral sees — so reuse stays unbiased.
pub fn pairwise_neighbour(i: usize, m: &[f32], own: f32, p_hat_0: f32) -> f32 {
    let n = (m.len() - 1) as f32;
    pair_share(m[i] * own, m[0] / n * p_hat_0) / n
}

/// [`pairwise_neighbour`]'s partner: the canonical input's weight at its
/// sample x_0, from `p_hat_at_x0[j]` = p̂_j(x_0):
/// m_0 = (1/N) Σ_{j≥1} (M_0/N) p̂_0 / (M_j p̂_j + (M_0/N) p̂_0); 1 without
/// neighbours.
pub fn pairwise_canonical(m: &[f32], p_hat_at_x0: &[f32]) -> f32 {
    if m.len() < 2 {
        return 1.0;
    }
    let n = (m.len() - 1) as f32;
    let own = m[0] / n * p_hat_at_x0[0];
    let sum: f32 = (1..m.len())
        .map(|j| pair_share(own, m[j] * p_hat_at_x0[j]))
        .sum();
    sum / n
}

/// a/(a + b), 0 when both vanish or the sum is not finite.
#[inline]
fn pair_share(a: f32, b: f32) -> f32 {
    let d = a + b;
    if d > 0.0 && d.is_finite() {
        a / d
    } else {
        0.0
    }
}

/// Streams input `i` of a combination into `into`: its sample `x` with
/// contribution weight `w_i` (W_i of its reservoir), MIS weight `mis`
/// ([`talbot`] or another that sums to 1 over the inputs), the total count
/// `m_total` = Σ M_j and `p_hat_q` = p̂_q(x) of the receiving pixel.
#[inline]
pub fn stream_input<Y: Copy>(
    into: &mut Reservoir<Y>,
    x: Y,
    w_i: f32,
    mis: f32,
    m_total: f32,
    p_hat_q: f32,
    u: f32,
) -> bool {
    into.stream(x, mis * p_hat_q * w_i * m_total, p_hat_q, u)
}
