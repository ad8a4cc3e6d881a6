//! Exact Euclidean distance transforms of voxel masks (Felzenszwalb &
//! Huttenlocher 2012: the lower envelope of parabolas, one pass per axis),
//! and the signed-distance encoding of a segmentation that Lerzer and Dachsbacher 2025 §6.6
//! uses for its importance masks: 0.5 on the boundary, interpolated
//! trilinearly, so a threshold of ½ follows the shape smoothly between
//! voxels instead of along their faces (Green 2007).

use crate::grid::BrickGrid;
use crate::Result;

/// Squared distance (in voxels, centre to centre) from every voxel to the
/// nearest voxel where `feature` is set; `f32::INFINITY` without features.
/// `dims[0]` fastest.
pub fn squared_distance(dims: [u32; 3], feature: &[bool]) -> Vec<f32> {
    let [nx, ny, nz] = dims.map(|d| d as usize);
    let mut d: Vec<f32> = feature
        .iter()
        .map(|&f| if f { 0.0 } else { f32::INFINITY })
        .collect();
    let mut line = Vec::new();
    let mut out = Vec::new();
    // One 1D transform along each axis in turn: (stride, length, lines).
    for (axis, stride, len, others) in [
        (0, 1, nx, ny * nz),
        (1, nx, ny, nx * nz),
        (2, nx * ny, nz, nx * ny),
    ] {
        for o in 0..others {
            let base = match axis {
                0 => o * nx,
                1 => (o / nx) * nx * ny + o % nx,
                _ => o,
            };
            line.clear();
            line.extend((0..len).map(|i| d[base + i * stride]));
            transform_1d(&line, &mut out);
            for (i, v) in out.iter().enumerate() {
                d[base + i * stride] = *v;
            }
        }
    }
    d
}

/// 1D squared distance transform of sampled function `f` into `out`.
fn transform_1d(f: &[f32], out: &mut Vec<f32>) {
    let n = f.len();
    out.clear();
    out.resize(n, f32::INFINITY);
    // Parabola apexes v and the boundaries z between them.
    let mut v = vec![0usize; n];
    let mut z = vec![0f64; n + 1];
    let mut k: isize = -1;
    for q in 0..n {
        if !f[q].is_finite() {
            continue;
        }
        loop {
            if k < 0 {
                k = 0;
                v[0] = q;
                z[0] = f64::NEG_INFINITY;
                z[1] = f64::INFINITY;
                break;
            }
            let p = v[k as usize];
            let s = ((f[q] as f64 + (q * q) as f64) - (f[p] as f64 + (p * p) as f64))
                / (2.0 * (q as f64 - p as f64));
            if s <= z[k as usize] {
                k -= 1;
                continue;
            }
            k += 1;
            v[k as usize] = q;
            z[k as usize] = s;
            z[k as usize + 1] = f64::INFINITY;
            break;
        }
    }
    if k < 0 {
        return;
    }
    let mut j = 0usize;
    for (q, o) in out.iter_mut().enumerate() {
        while z[j + 1] < q as f64 {
            j += 1;
        }
        let p = v[j];
        *o = ((q as f64 - p as f64).powi(2) + f[p] as f64) as f32;
    }
}

/// The segmentation `inside` (x fastest) as an encoded signed distance:
/// 0.5 + sd / (2·`spread`) clamped to [0, 1], sd the signed distance in
/// voxels to the boundary halfway between an inside and an outside voxel
/// (positive inside). Threshold ½ of the trilinear interpolant is the
/// shape's surface.
pub fn encoded_signed_distance(
    dims: [u32; 3],
    inside: &[bool],
    spread: f32,
) -> Result<BrickGrid<f32>> {
    let outside: Vec<bool> = inside.iter().map(|&b| !b).collect();
    let to_inside = squared_distance(dims, inside);
    let to_outside = squared_distance(dims, &outside);
    let [nx, ny, _] = dims.map(|d| d as usize);
    BrickGrid::from_fn(dims, |i, j, k| {
        let n = (k as usize * ny + j as usize) * nx + i as usize;
        let sd = if inside[n] {
            to_outside[n].sqrt() - 0.5
        } else {
            0.5 - to_inside[n].sqrt()
        };
        (0.5 + sd / (2.0 * spread)).clamp(0.0, 1.0)
    })
}

#[cfg(test)]
mod distance_test {
    use super::*;
    use fogbank_math::Pcg32;

    #[test]
    fn matches_brute_force_on_random_masks() {
        let mut rng = Pcg32::new(5, 5);
        for dims in [[7u32, 5, 4], [1, 9, 3], [12, 1, 1]] {
            let n = dims.iter().product::<u32>() as usize;
            let feature: Vec<bool> = (0..n).map(|_| rng.next_u32().is_multiple_of(7)).collect();
            let d = squared_distance(dims, &feature);
            let [nx, ny, _] = dims.map(|v| v as usize);
            let at = |i: usize| {
                [
                    (i % nx) as f32,
                    ((i / nx) % ny) as f32,
                    (i / (nx * ny)) as f32,
                ]
            };
            for (a, &got) in d.iter().enumerate() {
                let best = (0..n)
                    .filter(|&b| feature[b])
                    .map(|b| {
                        let (p, q) = (at(a), at(b));
                        (p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2)
                    })
                    .fold(f32::INFINITY, f32::min);
                assert_eq!(got, best, "{dims:?} voxel {a}");
            }
        }
    }

    #[test]
    fn a_ball_is_thresholded_at_its_radius() {
        let (n, r) = (24u32, 7.3f32);
        let c = n as f32 / 2.0;
        let inside: Vec<bool> = (0..n * n * n)
            .map(|i| {
                let p = [i % n, (i / n) % n, i / (n * n)].map(|v| v as f32 + 0.5 - c);
                (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt() < r
            })
            .collect();
        let g = encoded_signed_distance([n; 3], &inside, 4.0).unwrap();
        // Along +x through the centre the ½ crossing lies within half a
        // voxel of the radius.
        let mut crossing = None;
        for s in 0..2000 {
            let x = c + s as f32 * 0.005;
            if g.trilinear(fogbank_math::Vec3::new(x, c, c)) < 0.5 {
                crossing = Some(x - c);
                break;
            }
        }
        let x = crossing.expect("no crossing");
        assert!((x - r).abs() < 0.5, "crossing at {x}, radius {r}");
    }
}
