//! BC4-style round trip: every voxel lands on its block's 8-value palette,
//! within half a palette step (plus the endpoints' 8-bit rounding) of its
//! value; constant blocks and zeros survive exactly.

use fogbank_volume::bc4::bc4_roundtrip;

#[test]
fn bc4_error_is_within_half_a_palette_step() {
    let dims = [13u32, 9, 3];
    let f = |i: i32, j: i32, k: i32| -> f32 {
        if i < 4 && j < 4 {
            0.0
        } else if i >= 8 && (4..8).contains(&j) {
            2.5
        } else {
            ((i * 37 + j * 11 + k * 5) % 23) as f32 * 0.17
        }
    };
    let g = bc4_roundtrip(dims, f).unwrap();
    let peak = 22.0 * 0.17;
    for k in 0..3 {
        for j in 0..9 {
            for i in 0..13 {
                let (bi, bj) = (i / 4 * 4, j / 4 * 4);
                let (mut lo, mut hi) = (f32::INFINITY, f32::NEG_INFINITY);
                for y in bj..(bj + 4).min(9) {
                    for x in bi..(bi + 4).min(13) {
                        lo = lo.min(f(x, y, k));
                        hi = hi.max(f(x, y, k));
                    }
                }
                let bound = (hi - lo) / 14.0 + peak / 255.0 + 1e-5;
                let (v, d) = (f(i, j, k), g.fetch(i, j, k));
                assert!(
                    (v - d).abs() <= bound,
                    "({i},{j},{k}): {v} → {d}, bound {bound}"
                );
                if hi == lo {
                    assert!((d - v).abs() <= peak / 510.0 + 1e-5);
                }
                if v == 0.0 && hi == 0.0 {
                    assert_eq!(d, 0.0);
                }
            }
        }
    }
}
