//! Equiangular sampling (Kulla & Fajardo 2012) towards a point light: t on
//! `[a, b]` with density ∝ 1/(D² + (t − Δ)²), which cancels the inverse
//! squared distance to the light. Independent of the medium, so its pdf is
//! exact and cheap (needed for MIS, Peters 2025 §5).

use fogbank_math::{Ray, Vec3};

/// The light's projection onto the (unit-direction) ray: Δ = (c − o)·d and
/// the distance D of the light from the ray's line.
fn frame(ray: &Ray, light: Vec3) -> (f32, f32) {
    let delta = (light - ray.o).dot(ray.d);
    let d = (ray.o + delta * ray.d - light).length().max(1e-6);
    (delta, d)
}

/// Samples t ∈ [a, b]; returns (t, pdf).
pub fn sample(ray: &Ray, light: Vec3, a: f32, b: f32, u: f32) -> (f32, f32) {
    let (delta, d) = frame(ray, light);
    let theta_a = ((a - delta) / d).atan();
    let theta_b = ((b - delta) / d).atan();
    let t = (delta + d * (theta_a + u * (theta_b - theta_a)).tan()).clamp(a, b);
    (t, pdf_with(delta, d, theta_a, theta_b, t))
}

fn pdf_with(delta: f32, d: f32, theta_a: f32, theta_b: f32, t: f32) -> f32 {
    let span = theta_b - theta_a;
    if span <= 0.0 {
        return 0.0;
    }
    d / (span * (d * d + (t - delta) * (t - delta)))
}

/// Density of `t` under [`sample`] on `[a, b]` (0 outside).
pub fn pdf(ray: &Ray, light: Vec3, a: f32, b: f32, t: f32) -> f32 {
    if t < a || t > b {
        return 0.0;
    }
    let (delta, d) = frame(ray, light);
    pdf_with(
        delta,
        d,
        ((a - delta) / d).atan(),
        ((b - delta) / d).atan(),
        t,
    )
}
