//! Hansen 2025 (pins): discrete exactness of MSB sampling and popcount
//! transmittance with exact masks, the thesis's bit conventions, pin
//! tracing on a medium with a known answer, and the 5D grid's indexing.

use crate::support;

use fogbank_estimators::pins::mask::bernoulli_mask;
use fogbank_estimators::pins::reference::{collision_probabilities, ratio_rows};
use fogbank_estimators::pins::{Chord, Pin, PinGrid, PinGridSpec, UnitCube, INTERVALS};
use fogbank_math::chi2::{sidak, IntervalTest};
use fogbank_math::{Pcg32, Ray, Vec3};
use fogbank_volume::{BrickGrid, Filter, MediumView};
use glam::Mat3;
use support::*;

/// Interval transmittances: uniform τ_i in [0, 0.3] (Fig. 3.4), nearly
/// opaque ones (t_min near 0), nearly clear ones (t_min near 1), and a
/// profile with clear intervals between dense ones.
fn profiles() -> Vec<[f64; INTERVALS]> {
    let mut rng = Pcg32::new(17, 4);
    let mut v = vec![std::array::from_fn(|_| (-0.3 * rng.next_f64()).exp())];
    v.push(std::array::from_fn(|i| {
        if i % 5 == 2 {
            1e-4
        } else {
            0.6 + 0.4 * rng.next_f64()
        }
    }));
    v.push(std::array::from_fn(|_| 1.0 - 0.004 * rng.next_f64()));
    v.push(std::array::from_fn(|i| {
        if (8..12).contains(&i) || i == 27 {
            0.3
        } else {
            1.0
        }
    }));
    v
}

/// A ray along +z (or −z) through the unit cube's column at (0.3, 0.6):
/// chord [0, 1] in its parameter when it starts at the entry face.
fn axis_ray(up: bool) -> Ray {
    if up {
        Ray::new(Vec3::new(0.3, 0.6, 0.0), Vec3::Z)
    } else {
        Ray::new(Vec3::new(0.3, 0.6, 1.0), -Vec3::Z)
    }
}

/// With a fresh Ĩ for every draw and an exact Bernoulli(1 − t_min) H, MSB
/// sampling from bit `o` is discrete free flight from interval `o` (Eq.
/// 3.3, corrected), uniform inside the bit, the start's interval whole:
/// chi-square over 4 bins per interval plus "no collision".
#[test]
fn msb_sampling_is_discrete_free_flight() {
    let cases: Vec<_> = profiles()
        .into_iter()
        .flat_map(|t| [(t, 0u32), (t, 13)])
        .collect();
    let alpha = sidak(0.01, cases.len() as u32);
    for (n, (t, o)) in cases.iter().enumerate() {
        let o = *o as usize;
        let ray = axis_ray(true);
        // The start in the middle of bit o: its interval still counts whole.
        let t_start = (o as f32 + 0.5) / 32.0;
        let chord = Chord::new(&ray, t_start).unwrap();
        assert_eq!(chord.offset as usize, o);
        let mut tail = [1.0; INTERVALS];
        tail[..INTERVALS - o].copy_from_slice(&t[o..]);
        let c = collision_probabilities(&tail);
        let bit = 1.0 / 32.0;
        let test = IntervalTest {
            a: 0.0,
            b: 1.0 - o as f64 * bit,
            bins: 4 * (INTERVALS - o),
            samples: 200_000,
            seed: 40 + n as u64,
        };
        let r = test.run(
            |rng| {
                let pin = Pin::from_transmittances(t, rng);
                let h = bernoulli_mask(1.0 - pin.t_min as f64, rng);
                chord
                    .sample_distance(pin.mask & h, f32::INFINITY, rng.next_f32())
                    .map(|d| d as f64)
            },
            |x| c[((x / bit) as usize).min(INTERVALS - 1)] / bit,
            c[INTERVALS - o..].iter().sum(),
        );
        assert!(r.passes(alpha), "profile {n}, offset {o}:\n{r}");
    }
}

/// Eq. 3.8: over fresh Ĩ, E[t_min^popcount(bits o..=e)] = Π_{i=o}^{e} t_i,
/// for segments inside the chord, ending past it, and reversed.
#[test]
fn popcount_transmittance_has_the_product_as_expectation() {
    let mut rng = Pcg32::new(5, 5);
    let mut tested = 0;
    for (n, t) in profiles().iter().enumerate() {
        for (start, len, up) in [
            (0.0f32, 2.0f32, true),
            (0.21, 0.33, true),
            (0.52, 0.1, false),
            (0.9, 5.0, false),
        ] {
            let ray = axis_ray(up);
            let chord = Chord::new(&ray, start).unwrap();
            let o = chord.offset as usize;
            // The end's bit, inclusive, clamped to the last.
            let e = (((start + len) * 32.0) as usize).min(31);
            // Along −z the query's bit j is the pin's interval 31 − j.
            let exact: f64 = (o..=e).map(|j| if up { t[j] } else { t[31 - j] }).product();
            let samples = 100_000;
            let (mut sum, mut sq) = (0.0f64, 0.0f64);
            for _ in 0..samples {
                let pin = Pin::from_transmittances(t, &mut rng);
                let x = chord.transmittance(&pin, len) as f64;
                sum += x;
                sq += x * x;
            }
            let mean = sum / samples as f64;
            let se = ((sq / samples as f64 - mean * mean).max(0.0) / samples as f64).sqrt();
            assert!(
                (mean - exact).abs() <= 4.5 * se + 1e-6 * exact,
                "profile {n}, start {start}, len {len}, up {up}: {mean} ± {se} vs {exact}"
            );
            tested += 1;
        }
    }
    assert_eq!(tested, 16);
}

#[test]
fn bit_conventions_follow_the_thesis() {
    // MSB is the chord's start; a −z query reads the pin reversed.
    let up = Chord::new(&axis_ray(true), 0.0).unwrap();
    let down = Chord::new(&axis_ray(false), 0.0).unwrap();
    assert!(!up.reversed && down.reversed);
    let mask = 0b1u32 << 31 | 0b1 << 2; // intervals 0 and 29 (from −z)
    assert_eq!(up.sample_distance(mask, 9.0, 0.0), Some(0.0));
    assert_eq!(down.sample_distance(mask, 9.0, 0.0), Some(2.0 / 32.0));
    // An origin on the exit face sits in bit 31; an empty mask, or none
    // ahead, means no collision and T = 1.
    let exit = Chord::new(&axis_ray(true), 1.0).unwrap();
    assert_eq!(exit.offset, 31);
    assert_eq!(exit.sample_distance(1 << 31, 9.0, 0.5), None);
    assert_eq!(exit.sample_distance(1, 9.0, 0.5), Some(0.5 / 32.0));
    assert_eq!(up.sample_distance(0, 9.0, 0.5), None);
    assert_eq!(
        up.transmittance(
            &Pin {
                mask: 0,
                t_min: 0.1
            },
            1.0
        ),
        1.0
    );
    // Beyond max_len: no collision.
    assert_eq!(up.sample_distance(1 << 20, 0.3, 0.5), None);
    // The end bit is included: a segment ending inside bit 3 counts bits 0..=3.
    assert_eq!(up.count(u32::MAX, 3.5 / 32.0), 4);
    assert_eq!(up.count(u32::MAX, 100.0), 32);
    // t_min = 1: no attenuation, an empty mask.
    let mut rng = Pcg32::new(1, 1);
    assert_eq!(
        Pin::from_transmittances(&[1.0; INTERVALS], &mut rng),
        Pin::CLEAR
    );
    // Homogeneous intervals: every ratio is 1, all bits set (§3.5).
    assert_eq!(
        Pin::from_transmittances(&[0.8; INTERVALS], &mut rng).mask,
        u32::MAX
    );
    // A ray from outside: the parameter keeps counting from its origin.
    let outside = Ray::new(Vec3::new(0.3, 0.6, -2.0), Vec3::Z);
    assert_eq!(Chord::new(&outside, 2.0).unwrap().offset, 0);
}

/// Reversal symmetry: a stretch of the line read upwards from its lower
/// end and downwards from its upper end covers the same intervals.
#[test]
fn reading_a_pin_backwards_mirrors_it() {
    let mut rng = Pcg32::new(8, 8);
    let t = profiles()[0];
    let mut differ = 0;
    for pin in ratio_rows(&t, 200, &mut rng) {
        for o in [0u32, 5, 17, 31] {
            let s = (o as f32 + 0.5) / 32.0;
            let up = Chord::new(&axis_ray(true), s).unwrap().count(pin.mask, 9.0);
            let down = Chord::new(&axis_ray(false), 0.0)
                .unwrap()
                .count(pin.mask, 1.0 - s);
            assert_eq!(up, down, "mask {:032b}, from bit {o}", pin.mask);
            // Downwards from the top over the same length reads other bits.
            differ += (Chord::new(&axis_ray(true), 0.0)
                .unwrap()
                .count(pin.mask, 1.0 - s)
                != up) as u32;
        }
    }
    assert!(differ > 100, "{differ}");
}

/// Pins traced through a homogeneous medium see t_i = exp(−σ·|interval|)
/// in world units (a non-cubic box with a scaled transform), so every bit
/// is set and t_min matches.
#[test]
fn traced_pins_measure_the_medium() {
    let mut m = grid_medium(
        BrickGrid::from_fn([8, 4, 16], |_, _, _| 1.0).unwrap(),
        Filter::Trilinear,
        3.0,
        4,
    );
    m.index_to_world = glam::DAffine3::from_scale(glam::DVec3::new(0.05, 0.1, 0.025));
    let MediumView::F32(v) = m.view() else {
        unreachable!()
    };
    let linear = m.index_to_world.matrix3.as_mat3();
    let cube = UnitCube::new(m.dims(), linear);
    let mut rng = Pcg32::new(3, 3);
    // Along z: the world chord is 16 · 0.025 = 0.4 long.
    let pin = Pin::trace(&v, &cube, Vec3::new(0.5, 0.5, 0.3), Vec3::Z, 0.01, &mut rng);
    assert_eq!(pin.mask, u32::MAX);
    let expected = (-3.0f32 * 0.4 / 32.0).exp();
    assert!(
        (pin.t_min - expected).abs() < 1e-5,
        "{} vs {expected}",
        pin.t_min
    );
    // Outside the cube's lines: a clear pin.
    assert_eq!(
        Pin::trace(&v, &cube, Vec3::splat(0.5), Vec3::ZERO, 0.01, &mut rng),
        Pin::CLEAR
    );
    let _ = Mat3::IDENTITY;
}

/// Gather: the point and direction drawn for a cell look that cell up;
/// directions of either sign share a bin; bins cover the hemisphere.
#[test]
fn grid_cells_round_trip() {
    let spec = PinGridSpec {
        positions: 5,
        phi: 16,
        theta: 4,
        ..Default::default()
    };
    let mut rng = Pcg32::new(9, 1);
    let n = spec.pin_count().unwrap() as usize;
    assert_eq!(n, 125 * 64);
    for i in (0..n).step_by(7) {
        let (p, d) = spec.sample_in_cell(i, &mut rng);
        assert_eq!(spec.cell(p, d), i, "cell {i}: {p:?} {d:?}");
        assert_eq!(spec.cell(p, -d), i);
    }
    let mut seen = [false; 64];
    for _ in 0..20_000 {
        seen[spec.direction_bin(random_unit(&mut rng)) as usize] = true;
    }
    assert!(seen.iter().all(|&s| s));
    // Bad sizes are refused with the key named.
    let zero = PinGridSpec {
        positions: 0,
        ..spec
    };
    assert!(zero.pin_count().unwrap_err().contains("positions"));
    let huge = PinGridSpec {
        positions: 4096,
        ..spec
    };
    assert!(huge.pin_count().unwrap_err().contains("limit"));
    // Gather fills every cell, independent of threads (seeded per cell).
    let m = grid_medium(cloud(16, 3), Filter::Trilinear, 8.0, 4);
    let MediumView::F32(v) = m.view() else {
        unreachable!()
    };
    let cube = UnitCube::new(m.dims(), Mat3::from_diagonal(Vec3::splat(1.0 / 16.0)));
    let small = PinGridSpec {
        positions: 3,
        ..spec
    };
    let a = PinGrid::gather(&v, &cube, small, 7).unwrap();
    let b = PinGrid::gather(&v, &cube, small, 7).unwrap();
    assert_eq!(a.pins, b.pins);
    assert_eq!(a.memory_bytes(), 27 * 64 * 8);
    assert!(a.pins.iter().filter(|p| p.mask != 0).count() > a.pins.len() / 4);
}
