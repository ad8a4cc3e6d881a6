// fogbank_render::integrators::restir::combine on the GPU (Lin et al. 2021 §2.5,
// §4.3–4.4; Eq. 8–11 with unequal M): the one rule temporal and spatial
// reuse share. Input 0 is the receiving pixel; input i has its stored
// reservoir (slot in_index[i]) and its pixel's centre ray (in_pixel[i]).
// In the temporal combination input 1 is the previous frame's reservoir,
// whose target p̂_1 needs the previous frame's data: p̂_1(x_1) is its own
// stored p̂ and p̂_1(x_0) was evaluated by the reprojection pass.

const MAX_INPUTS: u32 = 33u;

var<private> in_index: array<u32, 33>;
var<private> in_pixel: array<u32, 33>;
var<private> in_m: array<f32, 33>;
// Contribution weight W_i and own target p̂_i(x_i) of each input.
var<private> in_w: array<f32, 33>;
var<private> in_p_hat: array<f32, 33>;
var<private> in_has_y: array<bool, 33>;
var<private> combining_temporal: bool;
var<private> temporal_p_hat_prev: f32;

// Input i of a combination: slot `index`, pixel `pixel`, count M capped at
// `cap` (the temporal Q·M; W is unchanged by a cap).
fn set_input(i: u32, index: u32, pixel: u32, cap: f32) {
    let s = reservoirs[index];
    let has_y = ((s.head.x >> 16u) & 1u) != 0u;
    in_index[i] = index;
    in_pixel[i] = pixel;
    in_has_y[i] = has_y;
    in_w[i] = contribution_weight(has_y, s.w.x, s.w.y, s.w.z);
    in_p_hat[i] = s.w.z;
    var m = s.w.y;
    if (m > cap && cap > 0.0) {
        m = cap;
    }
    in_m[i] = m;
}

// p̂_j(x_i): pixel j's target at input i's sample `y` (its stored path,
// loaded once by the caller).
fn p_hat_at(i: u32, j: u32, y: ptr<function, Path>, lookups: ptr<function, u32>) -> f32 {
    if (!in_has_y[i]) {
        return 0.0;
    }
    if (i == j) {
        return in_p_hat[i];
    }
    if (combining_temporal && j == 1u) {
        return temporal_p_hat_prev;
    }
    let p = in_pixel[j];
    return p_hat_of(centre_ray(p % frame.width, p / frame.width), y, lookups);
}

// reservoir.rs pair_share: a/(a + b), 0 when both vanish or not finite.
fn pair_share(a: f32, b: f32) -> f32 {
    let d = a + b;
    if (d > 0.0 && is_finite1(d)) {
        return a / d;
    }
    return 0.0;
}

// Restir::combine: the combined reservoir of input 0's pixel. Pass i < n
// streams input i; with stochastic MIS, pass n evaluates the chosen
// sample's denominator. Every p̂ is evaluated at the one call of p_hat_at
// (each call site inlines evaluate again: lavapipe's compile time).
fn combine(n: u32, rng: ptr<function, Pcg32>, lookups: ptr<function, u32>) -> Reservoir {
    var m_total = 0.0;
    for (var i = 0u; i < n; i++) {
        m_total += in_m[i];
    }
    var out = empty_reservoir();
    var chosen = MAX_INPUTS;
    for (var pass_i = 0u; pass_i <= n; pass_i++) {
        let finishing = pass_i == n;
        var i = pass_i;
        var u = 0.0;
        if (finishing) {
            if (chosen >= MAX_INPUTS || rp.mis != MIS_STOCHASTIC) {
                break;
            }
            i = chosen;
        } else {
            u = pcg32_next_f32(rng);
            if (!in_has_y[i] || in_w[i] <= 0.0) {
                continue;
            }
        }
        var y = load_reservoir(in_index[i]).y;
        // Σ_j M_j p̂_j(x_i) over every input for Talbot's weight and the
        // stochastic denominator, and p̂_j(x_0) for pairwise MIS's canonical
        // weight; p̂_0(x_i) alone for 1/M weights and a pairwise neighbour.
        var inputs = n;
        let pairwise_canonical = rp.mis == MIS_PAIRWISE && i == 0u;
        if (!finishing && rp.mis != MIS_TALBOT && !pairwise_canonical) {
            inputs = 1u;
        }
        // Pairwise MIS (reservoir.rs pairwise_canonical/_neighbour): N
        // neighbours, the canonical share b = (M_0/N)·p̂_0(x_0).
        let pairs = f32(max(n, 2u) - 1u);
        let b = in_m[0] / pairs * in_p_hat[0];
        var pair_sum = 0.0;
        var den = 0.0;
        var own = 0.0;
        var p_hat_q = 0.0;
        for (var j = 0u; j < inputs; j++) {
            let p = p_hat_at(i, j, &y, lookups);
            den += in_m[j] * p;
            if (j == i) {
                own = p;
            }
            if (j == 0u) {
                p_hat_q = p;
            } else {
                pair_sum += pair_share(b, in_m[j] * p);
            }
        }
        if (finishing) {
            // Eq. 10 for unequal M: W = m_r(y)·w_sum/(M_r p̂_q(y)).
            let num = m_total * in_p_hat[chosen];
            if (den > 0.0) {
                out.w_sum *= num / den;
            } else {
                out.w_sum = 0.0;
            }
            break;
        }
        var weight = 0.0;
        if (rp.mis == MIS_TALBOT) {
            // Generalised Talbot (Eq. 11): M_i p̂_i(x_i) / Σ_j M_j p̂_j(x_i).
            if (den > 0.0 && is_finite1(den)) {
                weight = in_m[i] * own / den;
            }
        } else if (pairwise_canonical) {
            weight = select(pair_sum / pairs, 1.0, n < 2u);
        } else if (rp.mis == MIS_PAIRWISE) {
            weight = pair_share(in_m[i] * in_p_hat[i], in_m[0] / pairs * p_hat_q) / pairs;
        } else {
            weight = in_m[i] / m_total;
        }
        // reservoir::stream_input
        let w = weight * p_hat_q * in_w[i] * m_total;
        if (!(w > 0.0) || !is_finite1(w)) {
            continue;
        }
        out.w_sum += w;
        if (u * out.w_sum < w) {
            chosen = i;
            out.p_hat = p_hat_q;
        }
    }
    out.m = m_total;
    if (chosen < MAX_INPUTS) {
        out.y = load_reservoir(in_index[chosen]).y;
        out.has_y = true;
    }
    return out;
}
