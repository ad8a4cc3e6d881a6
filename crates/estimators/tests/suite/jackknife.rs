//! Peters 2025's jackknife estimator: exactness for normal inputs (Thm. 1,
//! App. A.2) and the fixed cost of Alg. 1/2.

use crate::support;
use fogbank_estimators::estimator::Jackknife;

use fogbank_estimators::jackknife::jackknife_transmittance;
use fogbank_estimators::jackknife_function::umvu_transmittance;
use fogbank_estimators::optical_depth::{prepare, Importance};
use fogbank_estimators::{transmittance, Estimator};
use fogbank_math::{Pcg32, RaySegment, SampleKey};
use fogbank_volume::{Filter, MediumView};
use support::*;

fn normal(rng: &mut Pcg32) -> f64 {
    let (u1, u2) = (1.0 - rng.next_f64(), rng.next_f64());
    (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
}

#[test]
fn unbiased_with_predicted_variance_for_normal_inputs() {
    let mut rng = Pcg32::new(12, 3);
    for (tau, sigma) in [(0.5, 0.2), (1.0, 0.5), (2.0, 1.0), (3.0, 1.5)] {
        let n = 2_000_000;
        let (mut s, mut s2) = (0.0f64, 0.0f64);
        for _ in 0..n {
            let x0 = tau + sigma * normal(&mut rng);
            let x1 = tau + sigma * normal(&mut rng);
            let k = jackknife_transmittance(x0, x1);
            s += k;
            s2 += k * k;
        }
        let mean = s / n as f64;
        let var = s2 / n as f64 - mean * mean;
        let se = (var / n as f64).sqrt();
        let exact: f64 = (-tau).exp();
        assert!(
            (mean - exact).abs() < 4.0 * se,
            "τ={tau} σ={sigma}: mean {mean} vs {exact} (se {se})"
        );
        // Peters 2025, App. A.2: V(K) = ½(e^{σ²} − 1)e^{−2τ}.
        let predicted = 0.5 * ((sigma * sigma).exp() - 1.0) * (-2.0 * tau).exp();
        assert!(
            (var / predicted - 1.0).abs() < 0.05,
            "τ={tau} σ={sigma}: variance {var} vs {predicted}"
        );
    }
}

#[test]
fn umvu_is_unbiased_for_normal_inputs_for_every_m() {
    let mut rng = Pcg32::new(5, 7);
    let (tau, sigma) = (1.2, 0.8);
    for m in [2usize, 3, 4, 6, 8] {
        let n = 400_000;
        let (mut s, mut s2) = (0.0f64, 0.0f64);
        let mut x = vec![0.0; m];
        for _ in 0..n {
            x.iter_mut()
                .for_each(|v| *v = tau + sigma * normal(&mut rng));
            let k = umvu_transmittance(&x);
            s += k;
            s2 += k * k;
        }
        let mean = s / n as f64;
        let se = ((s2 / n as f64 - mean * mean) / n as f64).sqrt();
        let exact: f64 = (-tau).exp();
        assert!(
            (mean - exact).abs() < 4.0 * se,
            "m={m}: mean {mean} vs {exact} (se {se})"
        );
    }
}

#[test]
fn fixed_cost_two_n_lookups_on_non_empty_rays_zero_otherwise() {
    let n = 48;
    let grid = cloud(n, 9);
    for filter in [Filter::Nearest, Filter::StochasticTrilinear] {
        let m = grid_medium(grid.clone(), filter, 20.0, 8);
        let (mut non_empty, mut empty) = (0, 0);
        for (i, ray) in test_rays([n; 3], 3000, 21).into_iter().enumerate() {
            // Independently: does the ray cross a super-voxel with σ_max > 0?
            let meets = match m.to_index(&ray, 0.0, f32::INFINITY) {
                None => false,
                Some((r, t0, t1)) => {
                    let sv = &m.supervoxels;
                    fogbank_volume::Dda::new(&r, sv.size as f32, sv.dims, t0, t1)
                        .any(|s| s.t1 > s.t0 && sv.get(s.cell).max > 0.0)
                }
            };
            for samples in [1, 5, 10] {
                let e = Estimator::Jackknife(Jackknife {
                    samples,
                    mode: fogbank_estimators::jackknife::StepMode::FixedCount,
                    jitter: fogbank_estimators::optical_depth::Jitter::Stratified,
                });
                let mut rng = SampleKey {
                    seed: 1,
                    pixel: i as u32,
                    sample: samples,
                    dimension: 0,
                }
                .rng();
                let est = transmittance(e, &m, &ray, f32::INFINITY, &mut rng);
                let expected = if meets { 2 * samples } else { 0 };
                if est.lookups != expected {
                    // Report the importance integral to tell a traversal slip
                    // from a counting one.
                    let total = match (m.to_index(&ray, 0.0, f32::INFINITY), m.view()) {
                        (Some((r, t0, t1)), MediumView::F32(v)) => {
                            prepare(&v, &RaySegment::new(r, t0, t1), Importance::VarianceAware)
                                .total
                        }
                        _ => 0.0,
                    };
                    panic!("ray {i} ({ray:?}), N={samples}: {} lookups, expected {expected} (F = {total})", est.lookups);
                }
                assert!(
                    est.transmittance.is_finite()
                        && est.transmittance <= 1.0
                        && est.transmittance >= -1.0
                );
            }
            if meets {
                non_empty += 1;
            } else {
                empty += 1;
            }
        }
        assert!(
            non_empty > 500 && empty > 100,
            "{non_empty} non-empty, {empty} empty rays"
        );
    }
}
