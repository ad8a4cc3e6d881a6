//! fogbank brick grid → OpenVDB-style sparse grid, the inverse of
//! [`vdb_grid`](crate::loaders::vdb_grid).
//!
//! fogbank puts voxel `(i, j, k)`'s value at the cell centre `(i + ½, j +
//! ½, k + ½)`, OpenVDB at the integer index. Voxel `(i, j, k)` becomes
//! OpenVDB voxel `(i, j, k)`, each brick one leaf, and the index→world map
//! gains a translation by `+½` voxel, so that the values keep their world
//! positions; reading the file back undoes it exactly (the reader shifts
//! by the origin it picks, less ½). Bricks whose voxels all equal the
//! background are dropped; in the others a voxel is active when it differs
//! from the background (a fog volume's convention). Voxels of a brick past
//! the grid's edge are background and inactive.

use fogbank_math::{DAffine3, DVec3};

use crate::grid::{BrickGrid, Voxel, BRICK};
use crate::loaders::vdb::{GridClass, VdbGrid, VdbLeaf};

/// The OpenVDB file format version written, the one OpenVDB 6 – 11 write.
pub const VDB_FILE_VERSION: u32 = 224;

/// `grid` with fogbank's voxel-centre transform `index_to_world` (voxel
/// `(i, j, k)` centred at `(i + ½, j + ½, k + ½)` mapped to world) as a fog
/// volume named `name` over `background`.
pub fn from_brick_grid<T: Voxel>(
    grid: &BrickGrid<T>,
    index_to_world: DAffine3,
    name: &str,
    background: f32,
) -> VdbGrid {
    let dims = grid.dims();
    let bdims = dims.map(|d| d.div_ceil(BRICK));
    let mut leaves = Vec::new();
    for bz in 0..bdims[2] {
        for by in 0..bdims[1] {
            for bx in 0..bdims[0] {
                if let Some(leaf) = leaf_of(grid, [bx, by, bz], background) {
                    leaves.push(leaf);
                }
            }
        }
    }
    let shifted = exact_shift(index_to_world, &leaves);
    VdbGrid {
        name: name.to_string(),
        grid_class: GridClass::FogVolume,
        file_version: VDB_FILE_VERSION,
        stored_as_half: false,
        compression: "none".to_string(),
        background,
        index_to_world: rows(&shifted),
        leaves,
        tiles: Vec::new(),
    }
}

/// `index_to_world` shifted by `+½` voxel, with its translation chosen so
/// that the reader's own shift (to the origin it will pick, less ½: a
/// leaf below the lowest one, see [`vdb_grid`](crate::loaders::vdb_grid))
/// lands on the map of its voxel frame bit for bit, not just to within
/// rounding: a grid read from a file, exported and loaded again has the
/// same transform.
fn exact_shift(index_to_world: DAffine3, leaves: &[VdbLeaf]) -> DAffine3 {
    let half = index_to_world * DAffine3::from_translation(DVec3::splat(0.5));
    let Some(lo) = leaves
        .iter()
        .map(|l| l.origin)
        .reduce(|a, b| std::array::from_fn(|k| a[k].min(b[k])))
    else {
        return half;
    };
    // The reader's origin, and the map it should arrive at for its voxel
    // frame (exactly `index_to_world` when the origin is 0, as for a grid
    // that was itself read from a file).
    let origin = DVec3::from_array(lo.map(|v| (v - BRICK as i32) as f64));
    let want = (index_to_world * DAffine3::from_translation(origin)).translation;
    // What the reader computes: `matrix · (origin − ½) + translation`.
    let ls = index_to_world.matrix3 * (origin - 0.5);
    let mut t = half.translation;
    for k in 0..3 {
        let mut candidate = want[k] - ls[k];
        // The difference is exact in most cases; otherwise a neighbour
        // within a few ulps is.
        for step in [0, 1, -1, 2, -2, 3, -3] {
            let c = nudge(want[k] - ls[k], step);
            if ls[k] + c == want[k] {
                candidate = c;
                break;
            }
        }
        t[k] = candidate;
    }
    DAffine3::from_mat3_translation(index_to_world.matrix3, t)
}

/// `x` moved by `steps` ulps.
fn nudge(x: f64, steps: i32) -> f64 {
    let mut y = x;
    for _ in 0..steps.unsigned_abs() {
        y = if steps > 0 {
            y.next_up()
        } else {
            y.next_down()
        };
    }
    y
}

/// The leaf of brick `b`, or `None` when it holds only background.
fn leaf_of<T: Voxel>(grid: &BrickGrid<T>, b: [u32; 3], background: f32) -> Option<VdbLeaf> {
    let dims = grid.dims();
    let lo = b.map(|v| (v * BRICK) as i32);
    let hi: [i32; 3] = std::array::from_fn(|k| (lo[k] + BRICK as i32).min(dims[k] as i32) - 1);
    // One table lookup settles empty space.
    if grid.uniform_in(lo, hi) == Some(background) {
        return None;
    }
    let mut values = Box::new([background; 512]);
    let mut active = [0u64; 8];
    for x in lo[0]..=hi[0] {
        for y in lo[1]..=hi[1] {
            for z in lo[2]..=hi[2] {
                let v = grid.fetch(x, y, z);
                let idx = (((x - lo[0]) << 6) | ((y - lo[1]) << 3) | (z - lo[2])) as usize;
                values[idx] = v;
                if v != background {
                    active[idx / 64] |= 1 << (idx % 64);
                }
            }
        }
    }
    active.iter().any(|&w| w != 0).then_some(VdbLeaf {
        origin: lo,
        values,
        active,
    })
}

/// Row-major 4×4 of an affine map, world = M · (i, j, k, 1).
pub fn rows(a: &DAffine3) -> [[f64; 4]; 4] {
    let m = a.matrix3;
    let t = a.translation;
    [
        [m.x_axis.x, m.y_axis.x, m.z_axis.x, t.x],
        [m.x_axis.y, m.y_axis.y, m.z_axis.y, t.y],
        [m.x_axis.z, m.y_axis.z, m.z_axis.z, t.z],
        [0.0, 0.0, 0.0, 1.0],
    ]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::loaders::vdb_grid::to_brick_grid;

    #[test]
    fn brick_grid_round_trips_through_vdb_grid() {
        let g = BrickGrid::<f32>::from_fn([20, 9, 17], |i, j, k| {
            if (i + j + k) % 3 == 0 && i > 2 && i < 18 {
                (i * 100 + j * 10 + k) as f32
            } else {
                0.0
            }
        })
        .unwrap();
        let xf = DAffine3::from_scale(DVec3::new(0.5, 0.25, 2.0))
            * DAffine3::from_translation(DVec3::new(4.0, -2.0, 1.0));
        let v = from_brick_grid(&g, xf, "density", 0.0);
        let occupied = (0..3 * 2 * 3)
            .filter(|b| {
                let (bx, by, bz) = (b % 3 * 8, b / 3 % 2 * 8, b / 6 * 8);
                (0..512).any(|n| g.fetch(bx + n % 8, by + n / 8 % 8, bz + n / 64) != 0.0)
            })
            .count();
        assert_eq!(v.leaves.len(), occupied);
        let (back, bxf) = to_brick_grid(v.clone()).unwrap();
        // Same world placement of every voxel centre, same values.
        for (i, j, k) in [(3, 0, 0), (5, 8, 16), (17, 4, 2), (10, 3, 11)] {
            let p = xf.transform_point3(DVec3::new(i as f64, j as f64, k as f64) + 0.5);
            let q = bxf.inverse().transform_point3(p) - 0.5;
            let (a, b, c) = (q.x.round() as i32, q.y.round() as i32, q.z.round() as i32);
            assert!((q - DVec3::new(a as f64, b as f64, c as f64)).length() < 1e-9);
            assert_eq!(back.fetch(a, b, c), g.fetch(i, j, k));
            assert_eq!(v.value_at([i, j, k]), g.fetch(i, j, k));
        }
        let nonzero = (0..20 * 9 * 17)
            .filter(|n| g.fetch(n % 20, n / 20 % 9, n / 180) != 0.0)
            .count();
        assert_eq!(v.active_voxel_count(), nonzero as u64);
    }

    /// A grid read from a file, converted back and read again: the same
    /// brick grid and the same transform, bit for bit.
    #[test]
    fn file_grid_round_trips_exactly() {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/vdb");
        for file in ["fog_f32_zip.vdb", "affine_half_blosc.vdb"] {
            let g = crate::loaders::vdb::read_grid(&dir.join(file), None).unwrap();
            let (a, axf) = to_brick_grid(g).unwrap();
            let v = from_brick_grid(&a, axf, "density", 0.0);
            let (b, bxf) = to_brick_grid(v).unwrap();
            assert_eq!(bxf, axf, "{file}");
            assert_eq!(b.dims(), a.dims(), "{file}");
            let d = a.dims();
            for n in 0..d[0] as usize * d[1] as usize * d[2] as usize {
                let (i, j, k) = (
                    n % d[0] as usize,
                    n / d[0] as usize % d[1] as usize,
                    n / (d[0] * d[1]) as usize,
                );
                let (i, j, k) = (i as i32, j as i32, k as i32);
                assert_eq!(
                    b.fetch(i, j, k).to_bits(),
                    a.fetch(i, j, k).to_bits(),
                    "{file}"
                );
            }
        }
    }
}
