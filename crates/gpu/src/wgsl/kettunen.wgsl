// fogbank_estimators::kettunen: biased and unbiased ray marching of
// Kettunen et al. 2021 over mean-importance super-voxels: N_CMF samples,
// exp(−X) (biased), or a power series of degree K ~ Russian roulette
// (p_Z = 0.9, K = 2, c = 2, degree ≤ 8) evaluated as a U-statistic of
// K + 1 estimates (unbiased).

const MAX_DEGREE: u32 = 8u;
const EXPECTED_ESTIMATES: f32 = 1.31945;

fn n_cmf(tau_bar: f32) -> u32 {
    let v = (tau_bar + 0.015) * (tau_bar + 0.65) * (tau_bar + 60.3);
    return max(u32(ceil(pow(v, 1.0 / 3.0))), 1u);
}

// P(degree ≥ k).
fn survival(k: u32) -> f32 {
    var p = 1.0;
    for (var i = 1u; i <= k; i++) {
        if (i <= 2u) {
            p = 0.1;
        } else {
            p *= min(2.0 / f32(i), 1.0);
        }
    }
    return p;
}

// Pcg32::next_f64 consumes two words; its value to f32 precision.
fn pcg32_next_f64_as_f32(rng: ptr<function, Pcg32>) -> f32 {
    let hi = pcg32_next_u32(rng) >> 5u;
    let lo = pcg32_next_u32(rng) >> 6u;
    return f32(hi) * (1.0 / 134217728.0) + f32(lo) * (1.0 / 9007199254740992.0);
}

fn sample_degree(u: f32) -> u32 {
    var d = 0u;
    for (var k = 1u; k <= MAX_DEGREE; k++) {
        if (u < survival(k)) {
            d = k;
        } else {
            break;
        }
    }
    return d;
}

fn biased_ray_marching(m: MediumGpu, r: Ray, t0: f32, t1: f32, doubled: bool,
                       rng: ptr<function, Pcg32>, lookups: ptr<function, u32>) -> f32 {
    let prep = od_prepare(m, r, t0, t1, true);
    if (prep.total <= 0.0) {
        return 1.0;
    }
    let n = n_cmf(prep.total) * select(1u, 2u, doubled);
    var x: array<f32, 9>;
    od_estimates(m, r, prep, prep.total / f32(n), true, false, 1u, rng, lookups, &x);
    return exp(-x[0]);
}

// kettunen::u_statistic: the mean over i of e^{−x_i} Σ_k m_k / (k! P(≥k)),
// m_k the elementary symmetric means of (x_i − x_j), j ≠ i.
fn u_statistic(x: ptr<function, array<f32, 9>>, len: u32) -> f32 {
    let n = len - 1u;
    var total = 0.0;
    for (var i = 0u; i < len; i++) {
        var em: array<f32, 9>;
        for (var k = 0u; k <= MAX_DEGREE; k++) {
            em[k] = 0.0;
        }
        em[0] = 1.0;
        var count = 0u;
        for (var j = 0u; j < len; j++) {
            if (j == i) {
                continue;
            }
            let y = (*x)[i] - (*x)[j];
            for (var k = count + 1u; k >= 1u; k--) {
                em[k] += f32(k) / f32(count + 1u) * (em[k - 1u] * y - em[k]);
            }
            count += 1u;
        }
        var series = 0.0;
        var factorial = 1.0;
        for (var k = 0u; k <= n; k++) {
            if (k > 0u) {
                factorial *= f32(k);
            }
            series += em[k] / (factorial * survival(k));
        }
        total += exp(-(*x)[i]) * series;
    }
    return total / f32(len);
}

fn unbiased_ray_marching(m: MediumGpu, r: Ray, t0: f32, t1: f32, mult: u32,
                         rng: ptr<function, Pcg32>, lookups: ptr<function, u32>) -> f32 {
    let prep = od_prepare(m, r, t0, t1, true);
    if (prep.total <= 0.0) {
        return 1.0;
    }
    let per = max(u32(round(f32(max(mult, 1u)) * f32(n_cmf(prep.total)) / EXPECTED_ESTIMATES)), 1u);
    let degree = sample_degree(pcg32_next_f64_as_f32(rng));
    var x: array<f32, 9>;
    od_estimates(m, r, prep, prep.total / f32(per), true, false, degree + 1u, rng, lookups, &x);
    return u_statistic(&x, degree + 1u);
}
