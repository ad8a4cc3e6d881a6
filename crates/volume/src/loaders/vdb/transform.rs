//! Transform maps: the linear OpenVDB maps, as an index-to-world matrix.

use super::reader::Reader;
use crate::error::Result;

/// Reads a map and returns it as a row-major matrix for column vectors.
/// OpenVDB multiplies row vectors (`p' = p · M`), hence the transposes.
pub(super) fn read_transform(r: &mut Reader) -> Result<[[f64; 4]; 4]> {
    let at = r.offset();
    let ty = r.string("transform map type")?;
    let mut m = [[0.0f64; 4]; 4];
    m[3][3] = 1.0;
    let diag = |m: &mut [[f64; 4]; 4], s: [f64; 3]| {
        for c in 0..3 {
            m[c][c] = s[c];
        }
    };
    match ty.as_str() {
        "UniformScaleMap" | "ScaleMap" => {
            let scale = r.vec3d("scale map")?;
            // voxel size, inverse scale, inverse squared scale, inverse twice scale
            r.take(4 * 24, "scale map")?;
            diag(&mut m, scale);
        }
        "UniformScaleTranslateMap" | "ScaleTranslateMap" => {
            let t = r.vec3d("scale-translate map")?;
            let scale = r.vec3d("scale-translate map")?;
            r.take(4 * 24, "scale-translate map")?;
            diag(&mut m, scale);
            for c in 0..3 {
                m[c][3] = t[c];
            }
        }
        "TranslationMap" => {
            let t = r.vec3d("translation map")?;
            diag(&mut m, [1.0; 3]);
            for c in 0..3 {
                m[c][3] = t[c];
            }
        }
        "AffineMap" | "UnitaryMap" => {
            let mut a = [[0.0f64; 4]; 4];
            for row in a.iter_mut() {
                for v in row.iter_mut() {
                    *v = r.f64("affine map matrix")?;
                }
            }
            if a[0][3] != 0.0 || a[1][3] != 0.0 || a[2][3] != 0.0 || a[3][3] != 1.0 {
                return Err(r.fail_at(at, "affine map matrix is projective, not affine"));
            }
            for row in 0..3 {
                for col in 0..4 {
                    m[row][col] = a[col][row];
                }
            }
        }
        other => {
            return Err(r.fail_at(
                at,
                format!("unsupported transform map type `{other}` (only linear maps can be read)"),
            ))
        }
    }
    if m.iter().flatten().any(|v| !v.is_finite()) {
        return Err(r.fail_at(at, format!("{ty} has non-finite entries")));
    }
    Ok(m)
}
