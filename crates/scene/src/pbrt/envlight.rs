//! Image `infinite` lights (pbrt's `ImageInfiniteLight`): a square image in
//! pbrt's equal-area octahedral layout (Clarberg's mapping,
//! `EqualAreaSquareToSphere`, +z of the light's frame at the square's
//! centre) becomes a latitude–longitude map fogbank's `envmap` light reads.
//!
//! The map is resampled at load time: each lat-long pixel averages, by
//! solid angle, 3×3 directions of its area, each taking the octahedral
//! pixel it falls in (pbrt's `LookupNearestChannel`; negative values
//! clamped to zero as `ImageLe` does). The light's transform (any linear
//! map; pbrt's `renderFromLight`, whose inverse takes a world direction to
//! the image) is baked into the resampling, so the `envmap` needs no
//! rotation. The result is an OpenEXR file in a cache folder (the system's
//! temporary folder, `fogbank-pbrt-envmaps`), named by a hash of the source
//! file's path, size, modification time, the transform and the resolution,
//! so a scene read again reuses it. A notice says it is resampled.
//!
//! `scale` multiplies; `illuminance` E scales the map so that pbrt's
//! estimate of its upper-hemisphere illuminance (2π/N² Σ Y cos θ over the
//! square's pixels with z > 0, as pbrt's `Light::Create` computes it) is E.
//! Images are read by [`fogbank_image::image_io::read_image`] (OpenEXR,
//! PNG); a non-square image is an error, as in pbrt.

use super::cursor::resolve;
use super::interpret::Placed;
use super::warnings::Warnings;
use fogbank_render::error::SceneError;
use glam::{DMat3, DVec2, DVec3};
use rayon::prelude::*;
use std::f64::consts::PI;
use std::hash::{Hash, Hasher};
use std::path::{Path, PathBuf};
use toml::{Table, Value};

/// pbrt's `EqualAreaSquareToSphere`: a point of [0, 1]² to a unit vector.
pub fn square_to_sphere(p: DVec2) -> DVec3 {
    let (u, v) = (2.0 * p.x - 1.0, 2.0 * p.y - 1.0);
    let (up, vp) = (u.abs(), v.abs());
    let signed = 1.0 - (up + vp);
    let r = 1.0 - signed.abs();
    let phi = if r == 0.0 { 1.0 } else { (vp - up) / r + 1.0 } * PI / 4.0;
    let z = (1.0 - r * r).copysign(signed);
    let s = r * (2.0 - r * r).max(0.0).sqrt();
    DVec3::new(phi.cos().copysign(u) * s, phi.sin().copysign(v) * s, z)
}

/// The inverse of [`square_to_sphere`] (pbrt's `EqualAreaSphereToSquare`,
/// here with an exact arctangent where pbrt uses a polynomial).
pub fn sphere_to_square(d: DVec3) -> DVec2 {
    let (x, y, z) = (d.x.abs(), d.y.abs(), d.z.abs());
    let r = (1.0 - z).max(0.0).sqrt();
    // φ ∈ [0, π/2] within the quadrant; t = (vp − up)/r.
    let t = if x == 0.0 && y == 0.0 {
        0.0
    } else {
        y.atan2(x) * 4.0 / PI - 1.0
    };
    let sum = if d.z >= 0.0 { r } else { 2.0 - r };
    let (up, vp) = ((sum - r * t) / 2.0, (sum + r * t) / 2.0);
    let u = up.copysign(if d.x >= 0.0 { 1.0 } else { -1.0 });
    let v = vp.copysign(if d.y >= 0.0 { 1.0 } else { -1.0 });
    DVec2::new((u + 1.0) / 2.0, (v + 1.0) / 2.0)
}

/// A square image of `n`×`n` pixels, row-major from the top.
pub struct Square<'a> {
    pub n: usize,
    pub rgb: &'a [[f32; 3]],
}

impl Square<'_> {
    /// The pixel `uv` falls in (pbrt's `LookupNearestChannel`), clamped ≥ 0.
    fn nearest(&self, uv: DVec2) -> [f64; 3] {
        let n = self.n as f64;
        let x = ((uv.x * n) as usize).min(self.n - 1);
        let y = ((uv.y * n) as usize).min(self.n - 1);
        self.rgb[y * self.n + x].map(|c| {
            if c.is_finite() {
                c.max(0.0) as f64
            } else {
                0.0
            }
        })
    }

    /// pbrt's upper-hemisphere illuminance estimate of the map.
    pub fn illuminance(&self) -> f64 {
        let n = self.n as f64;
        let mut e = 0.0;
        for y in 0..self.n {
            for x in 0..self.n {
                let w = square_to_sphere(DVec2::new((x as f64 + 0.5) / n, (y as f64 + 0.5) / n));
                if w.z > 0.0 {
                    let c = self.nearest(DVec2::new((x as f64 + 0.5) / n, (y as f64 + 0.5) / n));
                    e += super::spectra::luminance(c) * w.z;
                }
            }
        }
        e * 2.0 * PI / (n * n)
    }

    /// The lat-long map (`2h`×`h`, fogbank's `envmap` layout) of the world
    /// seen through `light_from_world`.
    pub fn latlong(&self, h: usize, light_from_world: DMat3) -> Vec<[f32; 3]> {
        let w = 2 * h;
        const SS: usize = 3;
        (0..w * h)
            .into_par_iter()
            .map(|k| {
                let (i, j) = (k / w, k % w);
                let (mut sum, mut wsum) = ([0.0; 3], 0.0);
                for a in 0..SS {
                    for b in 0..SS {
                        let theta = (i as f64 + (a as f64 + 0.5) / SS as f64) * PI / h as f64;
                        let phi = (j as f64 + (b as f64 + 0.5) / SS as f64) * 2.0 * PI / w as f64;
                        let (st, ct) = theta.sin_cos();
                        let d = DVec3::new(st * phi.sin(), ct, -st * phi.cos());
                        let dl = (light_from_world * d).normalize_or_zero();
                        let c = self.nearest(sphere_to_square(dl));
                        for (s, c) in sum.iter_mut().zip(c) {
                            *s += c * st;
                        }
                        wsum += st;
                    }
                }
                sum.map(|s| (s / wsum) as f32)
            })
            .collect()
    }
}

/// The `envmap` table of an image `infinite` light.
pub fn image_light(
    l: &Placed,
    top_dir: &Path,
    warnings: &mut Warnings,
) -> Result<Table, SceneError> {
    let e = &l.entity;
    let ps = &e.params;
    let err = |m: String| e.loc.error(format!("{}: {m}", e.what("LightSource")));
    let file = ps.string("filename")?.unwrap_or_default();
    if ps.has("L") {
        return Err(err("give either \"L\" or \"filename\", not both".into()));
    }
    let path = resolve(file, &e.loc, top_dir);
    let img = fogbank_image::image_io::read_image(&path).map_err(err)?;
    if img.width != img.height || img.width == 0 {
        return Err(err(format!(
            "{}: {}×{} is not a square (equal-area octahedral) image",
            path.display(),
            img.width,
            img.height
        )));
    }
    let sq = Square {
        n: img.width,
        rgb: &img.rgb,
    };
    let mut scale = ps.float("scale", 1.0)?;
    if let Some(ev) = ps.one("float", "illuminance")?.filter(|&x| x > 0.0) {
        let k = sq.illuminance();
        if k.is_nan() || k <= 0.0 {
            return Err(err(
                "\"illuminance\" asks to scale a map that is black above the horizon".into(),
            ));
        }
        scale *= ev / k;
    }
    let m = DMat3::from_mat4(l.ctm);
    if m.determinant().abs() < 1e-12 {
        return Err(err("the light's transform is singular".into()));
    }
    let h = img.width.clamp(8, 2048);
    let out = cached(&path, m, h, || sq.latlong(h, m.inverse())).map_err(err)?;
    warnings.warn(format!(
        "{}: infinite light: {} (equal-area octahedral {}²) is resampled to a {}×{} lat-long map, {}",
        e.loc,
        path.display(),
        img.width,
        2 * h,
        h,
        out.display()
    ));
    let mut t = Table::new();
    t.insert("type".into(), "envmap".into());
    t.insert("file".into(), out.display().to_string().into());
    t.insert("scale".into(), Value::Float(scale));
    Ok(t)
}

/// The cached lat-long file for `source` seen through `m` at height `h`,
/// made by `make` when missing.
fn cached(
    source: &Path,
    m: DMat3,
    h: usize,
    make: impl FnOnce() -> Vec<[f32; 3]>,
) -> Result<PathBuf, String> {
    let meta = std::fs::metadata(source).map_err(|e| format!("{}: {e}", source.display()))?;
    let mut hasher = std::collections::hash_map::DefaultHasher::new();
    source.hash(&mut hasher);
    meta.len().hash(&mut hasher);
    meta.modified().ok().hash(&mut hasher);
    h.hash(&mut hasher);
    for x in m.to_cols_array() {
        x.to_bits().hash(&mut hasher);
    }
    let dir = std::env::temp_dir().join("fogbank-pbrt-envmaps");
    std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let out = dir.join(format!("{:016x}.exr", hasher.finish()));
    if !out.exists() {
        // Written beside and renamed, so a concurrent reader never sees half a file.
        let tmp = dir.join(format!(
            "{:016x}.{}.tmp.exr",
            hasher.finish(),
            std::process::id()
        ));
        let px = make();
        fogbank_image::image_io::write_exr(&tmp, 2 * h as u32, h as u32, &px, None)?;
        std::fs::rename(&tmp, &out).map_err(|e| format!("{}: {e}", out.display()))?;
    }
    Ok(out)
}
