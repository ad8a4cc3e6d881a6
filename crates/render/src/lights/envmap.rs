//! Environment map light: radiance arriving from infinitely far away, stored
//! as a latitude–longitude (equirectangular) image, importance-sampled in
//! proportion to luminance × solid angle.
//!
//! # Layout (Mitsuba 3's `envmap` convention)
//!
//! +y is up. A local direction d = (x, y, z) has polar angle
//! θ = atan2(√(x² + z²), y) ∈ [0, π] from +y and azimuth
//! φ = atan2(x, −z) ∈ [0, 2π), so φ = 0 is −z, φ = π/2 is +x, φ = π is +z and
//! φ = 3π/2 is −x; conversely d = (sin θ sin φ, cos θ, −sin θ cos φ). Image
//! coordinates are u = φ / 2π (column, left to right) and v = θ / π (row, top
//! to bottom): the top row is the zenith, the middle row the horizon. Pixel
//! (row i, column j) covers θ ∈ [iπ/H, (i+1)π/H] and φ ∈ [2πj/W, 2π(j+1)/W].
//! Maps authored for Mitsuba 3 therefore appear the same way round here.
//! A world direction is taken to the map by the inverse of `to_world`, which
//! must be a rotation (orthogonal), so that solid angles are preserved.
//!
//! # Lookup and sampling
//!
//! Radiance is piecewise constant: `eval` returns the pixel the direction
//! falls in (nearest lookup, no filtering). This is what the sampler can
//! match exactly: pixels are picked with probability ∝ Y · Ω (luminance Y,
//! pixel solid angle Ω = Δφ (cos θ₀ − cos θ₁), which is ∝ sin θ at the row
//! centre), then a direction is drawn uniformly in solid angle inside the
//! pixel (uniform in cos θ and φ). The pdf in solid angle is then
//! Y(pixel) / ∫ Y dω, constant over each pixel, so `pdf` and the sample's
//! pdf agree to the last bit, and radiance / pdf is the same for every
//! direction in a pixel. Pixel selection uses a 2D CDF (marginal over rows,
//! conditional within the row) with binary search: O(log W + log H) per
//! sample (pbrt-v4 §A.5.6, "piecewise-constant 2D distributions").
//!
//! Bilinear lookup would need a piecewise-bilinear sampling density to stay
//! exact; nearest lookup keeps the two consistent by construction.

use glam::{DVec3, Mat3, Vec3};
use std::f64::consts::PI;
use std::path::Path;

/// Rec. 709 luminance, used to distribute samples and for [`Envmap::power_proxy`].
fn luminance(c: Vec3) -> f64 {
    0.2126 * c.x as f64 + 0.7152 * c.y as f64 + 0.0722 * c.z as f64
}

/// Fraction of a pixel kept away from its edges when placing a sample: the
/// f32 direction carries ≈10⁻⁷ rad of rounding, which must not move a
/// sample into the neighbouring pixel (whose radiance and pdf differ).
const EDGE_MARGIN: f64 = 1e-4;

/// Latitude–longitude environment light (see the module docs).
#[derive(Clone, Debug)]
pub struct Envmap {
    width: usize,
    height: usize,
    /// Scaled radiance per pixel, row-major from the top row; pixels with a
    /// non-finite channel are 0, negative channels are clamped to 0.
    radiance: Vec<Vec3>,
    to_world: Mat3,
    to_local: Mat3,
    /// Marginal CDF over rows (height + 1 entries, 0 to 1) of Σ_j Y_ij Ω_i.
    row_cdf: Vec<f64>,
    /// Per row, the conditional CDF over its columns ((width + 1) entries
    /// per row, 0 to 1; all zero for a black row).
    col_cdf: Vec<f64>,
    /// ∫ Y dω over the sphere, the normalisation of the pdf.
    luminance_integral: f64,
    non_finite_pixels: usize,
    negative_pixels: usize,
    /// Mitsuba 3's bilinear lookup instead of nearest (see
    /// [`Envmap::bilinear`]).
    bilinear: bool,
}

impl Envmap {
    /// Reads an OpenEXR (RGB or RGBA, half or float; the first layer with
    /// R, G and B channels at full resolution) or Radiance `.hdr` image,
    /// recognised by its magic number. Errors name the file.
    pub fn load(path: &Path, scale: f32, to_world: Mat3) -> Result<Envmap, String> {
        let name = path.display();
        let mut magic = [0u8; 4];
        {
            use std::io::Read;
            let mut file =
                std::fs::File::open(path).map_err(|e| format!("{name}: cannot open: {e}"))?;
            let mut read = 0;
            while read < magic.len() {
                match file.read(&mut magic[read..]) {
                    Ok(0) => break,
                    Ok(n) => read += n,
                    Err(e) => return Err(format!("{name}: cannot read: {e}")),
                }
            }
        }
        let (width, height, rgb) = if magic == [0x76, 0x2f, 0x31, 0x01] {
            read_exr(path).map_err(|e| format!("{name}: cannot read OpenEXR: {e}"))?
        } else if magic.starts_with(b"#?") {
            read_hdr(path).map_err(|e| format!("{name}: cannot read Radiance HDR: {e}"))?
        } else {
            return Err(format!(
                "{name}: not an OpenEXR or Radiance HDR image (unknown magic number)"
            ));
        };
        Envmap::from_pixels(width, height, rgb, scale, to_world).map_err(|e| format!("{name}: {e}"))
    }

    /// Builds the map from linear RGB radiance, row-major from the top row
    /// (see the module docs for the layout), multiplied by `scale`.
    pub fn from_pixels(
        width: usize,
        height: usize,
        rgb: Vec<[f32; 3]>,
        scale: f32,
        to_world: Mat3,
    ) -> Result<Envmap, String> {
        if width == 0 || height == 0 {
            return Err(format!("environment map is empty ({width}×{height})"));
        }
        if width.checked_mul(height) != Some(rgb.len()) {
            return Err(format!(
                "environment map is {width}×{height} but has {} pixels",
                rgb.len()
            ));
        }
        if !(scale.is_finite() && scale >= 0.0) {
            return Err(format!(
                "environment map scale {scale} is not finite and ≥ 0"
            ));
        }
        let gram = to_world.transpose() * to_world;
        let off = (gram - Mat3::IDENTITY).to_cols_array();
        if !to_world.is_finite() || off.iter().any(|v| v.abs() > 1e-3) {
            return Err(format!(
                "environment map to_world {to_world:?} is not a rotation (orthogonal matrix)"
            ));
        }

        let (mut non_finite_pixels, mut negative_pixels) = (0, 0);
        let radiance: Vec<Vec3> = rgb
            .into_iter()
            .map(|p| {
                let c = Vec3::from(p);
                if !c.is_finite() {
                    // One NaN or Inf channel makes the whole pixel unknown.
                    non_finite_pixels += 1;
                    return Vec3::ZERO;
                }
                if c.cmplt(Vec3::ZERO).any() {
                    negative_pixels += 1;
                }
                let c = c.max(Vec3::ZERO) * scale;
                // A huge finite value times scale may overflow.
                if c.is_finite() {
                    c
                } else {
                    Vec3::ZERO
                }
            })
            .collect();

        let dphi = 2.0 * PI / width as f64;
        let mut row_cdf = Vec::with_capacity(height + 1);
        let mut col_cdf = vec![0.0; height * (width + 1)];
        row_cdf.push(0.0);
        let mut total = 0.0;
        for i in 0..height {
            let omega = dphi * band_height(i, height);
            let cdf = &mut col_cdf[i * (width + 1)..(i + 1) * (width + 1)];
            let mut row = 0.0;
            for j in 0..width {
                row += luminance(radiance[i * width + j]);
                cdf[j + 1] = row;
            }
            if row > 0.0 {
                cdf.iter_mut().for_each(|c| *c /= row);
                cdf[width] = 1.0;
            }
            total += row * omega;
            row_cdf.push(total);
        }
        if total > 0.0 && total.is_finite() {
            row_cdf.iter_mut().for_each(|c| *c /= total);
            row_cdf[height] = 1.0;
        } else {
            total = 0.0;
        }
        Ok(Envmap {
            width,
            height,
            radiance,
            to_world,
            to_local: to_world.inverse(),
            row_cdf,
            col_cdf,
            luminance_integral: total,
            non_finite_pixels,
            negative_pixels,
            bilinear: false,
        })
    }

    /// The flat arrays a GPU port needs: radiance per pixel, the row CDF
    /// (height + 1) followed by the per-row column CDFs (height · (width + 1)),
    /// the world → map rotation and ∫ Y dω.
    pub fn gpu_layout(&self) -> (Vec<[f32; 4]>, Vec<f32>, Mat3, f32) {
        let rgb = self.radiance.iter().map(|c| [c.x, c.y, c.z, 0.0]).collect();
        let cdf = self
            .row_cdf
            .iter()
            .chain(&self.col_cdf)
            .map(|&c| c as f32)
            .collect();
        (rgb, cdf, self.to_local, self.luminance_integral as f32)
    }

    pub fn width(&self) -> usize {
        self.width
    }

    pub fn height(&self) -> usize {
        self.height
    }

    pub fn to_world(&self) -> Mat3 {
        self.to_world
    }

    /// Pixels with a NaN or infinite channel (the whole pixel reads as 0).
    pub fn non_finite_pixels(&self) -> usize {
        self.non_finite_pixels
    }

    /// Pixels with a negative channel (clamped to 0).
    pub fn negative_pixels(&self) -> usize {
        self.negative_pixels
    }

    /// ∫ Y(L(ω)) dω over the sphere (scaled luminance times steradians), the
    /// power-like scalar for picking among lights: a constant environment of
    /// radiance L gives 4π Y(L). A distant light's flux through a scene of
    /// bounding radius r is about π r² times this, which the caller supplies.
    pub fn power_proxy(&self) -> f32 {
        self.luminance_integral as f32
    }

    /// Radiance arriving from direction `dir_world` (unit, pointing from the
    /// scene towards the environment).
    pub fn eval(&self, dir_world: Vec3) -> Vec3 {
        if self.bilinear {
            return self.eval_bilinear(dir_world);
        }
        self.radiance[self.pixel_of(dir_world)]
    }

    /// The map read as Mitsuba 3's `envmap` reads it: bilinear between
    /// texels at u = (j + ½)/W (columns wrap) and v = i/(H − 1) (row 0 at
    /// the zenith, the last at the nadir, clamped). Sampling stays
    /// piecewise constant over pixels: its pdf is still a density over the
    /// sphere, so the estimate stays unbiased wherever the map's pixels
    /// have luminance (elsewhere the phase or BSDF strategy covers the
    /// light, as MIS lets it).
    pub fn bilinear(mut self) -> Envmap {
        self.bilinear = true;
        self
    }

    pub fn is_bilinear(&self) -> bool {
        self.bilinear
    }

    fn eval_bilinear(&self, dir_world: Vec3) -> Vec3 {
        let d = (self.to_local * dir_world).as_dvec3();
        let mut u = d.x.atan2(-d.z) / (2.0 * PI);
        u -= u.floor();
        let v = (d.y.clamp(-1.0, 1.0).acos() / PI).clamp(0.0, 1.0);
        let (w, h) = (self.width as f64, self.height as f64);
        let x = u * w - 0.5;
        let y = v * (h - 1.0);
        if !(x.is_finite() && y.is_finite()) {
            return Vec3::ZERO;
        }
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = ((x - x0) as f32, (y - y0) as f32);
        let col = |k: f64| (k.rem_euclid(w) as usize).min(self.width - 1);
        let row = |k: f64| (k.clamp(0.0, h - 1.0) as usize).min(self.height - 1);
        let at = |r: usize, c: usize| self.radiance[r * self.width + c];
        let (c0, c1) = (col(x0), col(x0 + 1.0));
        let (r0, r1) = (row(y0), row(y0 + 1.0));
        let top = at(r0, c0) * (1.0 - fx) + at(r0, c1) * fx;
        let bottom = at(r1, c0) * (1.0 - fx) + at(r1, c1) * fx;
        top * (1.0 - fy) + bottom * fy
    }

    /// Solid-angle pdf with which [`Envmap::sample`] returns `dir_world`:
    /// Y(pixel) / ∫ Y dω; 0 everywhere for a black map.
    pub fn pdf(&self, dir_world: Vec3) -> f32 {
        self.pdf_of_pixel(self.pixel_of(dir_world))
    }

    /// Draws a direction ∝ luminance: `u[0]` picks the row, `u[1]` the
    /// column, and what is left of each places the direction inside the
    /// pixel. Returns (direction in world space, its radiance, its pdf in
    /// solid angle). A black map returns pdf 0 and zero radiance (with a
    /// valid direction), which callers must skip.
    pub fn sample(&self, u: [f32; 2]) -> (Vec3, Vec3, f32) {
        let (u0, u1) = (u[0] as f64, u[1] as f64);
        if self.luminance_integral <= 0.0 {
            let dir = self.to_world * direction(1.0 - 2.0 * u0, 2.0 * PI * u1).as_vec3();
            return (dir.normalize_or(Vec3::Y), Vec3::ZERO, 0.0);
        }
        let (i, fv) = sample_cdf(&self.row_cdf, u0);
        let w1 = self.width + 1;
        let (j, fu) = sample_cdf(&self.col_cdf[i * w1..(i + 1) * w1], u1);
        // Uniform in solid angle within the pixel: uniform in cos θ and φ.
        let (c0, c1) = band_cos(i, self.height);
        let fv = fv.clamp(EDGE_MARGIN, 1.0 - EDGE_MARGIN);
        let fu = fu.clamp(EDGE_MARGIN, 1.0 - EDGE_MARGIN);
        let cos_theta = c0 + (c1 - c0) * fv;
        let phi = 2.0 * PI * (j as f64 + fu) / self.width as f64;
        let local = direction(cos_theta, phi);
        let dir = (self.to_world.as_dmat3() * local).normalize().as_vec3();
        // Read back what `eval` and `pdf` see for this very direction, so
        // that the three always agree exactly even if rounding moved the
        // direction across a pixel edge.
        let p = self.pixel_of(dir);
        (dir, self.eval(dir), self.pdf_of_pixel(p))
    }

    fn pdf_of_pixel(&self, p: usize) -> f32 {
        if self.luminance_integral > 0.0 {
            (luminance(self.radiance[p]) / self.luminance_integral) as f32
        } else {
            0.0
        }
    }

    /// Index of the pixel that the world direction falls in.
    fn pixel_of(&self, dir_world: Vec3) -> usize {
        let d = self.to_local * dir_world;
        // atan2 of (√(x²+z²), y) keeps θ accurate at the poles, where
        // acos(y) of an f32 y loses half its digits.
        let theta = ((d.x * d.x + d.z * d.z).sqrt() as f64).atan2(d.y as f64);
        let mut phi = (d.x as f64).atan2(-d.z as f64);
        if phi < 0.0 {
            phi += 2.0 * PI;
        }
        let row = ((theta / PI * self.height as f64) as usize).min(self.height - 1);
        let col = ((phi / (2.0 * PI) * self.width as f64) as usize).min(self.width - 1);
        // NaN directions land on pixel 0 (`as usize` maps NaN to 0).
        row * self.width + col
    }
}

/// Local direction from cos θ (about +y) and φ (from −z towards +x).
fn direction(cos_theta: f64, phi: f64) -> DVec3 {
    let sin_theta = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
    DVec3::new(sin_theta * phi.sin(), cos_theta, -sin_theta * phi.cos())
}

/// cos θ at the top and bottom edges of row `i`.
fn band_cos(i: usize, height: usize) -> (f64, f64) {
    let t0 = PI * i as f64 / height as f64;
    let t1 = PI * (i + 1) as f64 / height as f64;
    (t0.cos(), t1.cos())
}

/// cos θ₀ − cos θ₁ of row `i`, in the cancellation-free form
/// 2 sin((θ₀ + θ₁)/2) sin((θ₁ − θ₀)/2), so that pixel solid angles stay
/// accurate at the poles of large maps.
fn band_height(i: usize, height: usize) -> f64 {
    let dtheta = PI / height as f64;
    let mid = dtheta * (i as f64 + 0.5);
    2.0 * mid.sin() * (0.5 * dtheta).sin()
}

/// Finds k with cdf[k] ≤ u < cdf[k + 1] (never a zero-probability entry,
/// since cdf[k + 1] > u ≥ cdf[k]) and the position of u inside it, in [0, 1).
fn sample_cdf(cdf: &[f64], u: f64) -> (usize, f64) {
    let n = cdf.len() - 1;
    let k = cdf[1..].partition_point(|&c| c <= u).min(n - 1);
    let width = cdf[k + 1] - cdf[k];
    let f = if width > 0.0 {
        ((u - cdf[k]) / width).clamp(0.0, 1.0)
    } else {
        0.5
    };
    (k, f)
}

type Pixels = (usize, usize, Vec<[f32; 3]>);

fn read_exr(path: &Path) -> Result<Pixels, String> {
    use exr::prelude::*;
    let image = read()
        .no_deep_data()
        .largest_resolution_level()
        .rgb_channels(
            |resolution, _| {
                (
                    resolution.width(),
                    vec![[0.0f32; 3]; resolution.width() * resolution.height()],
                )
            },
            |(width, pixels): &mut (usize, Vec<[f32; 3]>), position, (r, g, b): (f32, f32, f32)| {
                pixels[position.y() * *width + position.x()] = [r, g, b];
            },
        )
        .first_valid_layer()
        .all_attributes()
        .from_file(path)
        .map_err(|e| e.to_string())?;
    let size = image.layer_data.size;
    let (_, pixels) = image.layer_data.channel_data.pixels;
    Ok((size.width(), size.height(), pixels))
}

fn read_hdr(path: &Path) -> Result<Pixels, String> {
    let file = std::fs::File::open(path).map_err(|e| e.to_string())?;
    let reader =
        image::ImageReader::with_format(std::io::BufReader::new(file), image::ImageFormat::Hdr);
    let image = reader.decode().map_err(|e| e.to_string())?.into_rgb32f();
    let (width, height) = (image.width() as usize, image.height() as usize);
    let pixels = image.pixels().map(|p| p.0).collect();
    Ok((width, height, pixels))
}
