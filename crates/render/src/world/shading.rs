//! The gradient lobe of Lerzer and Dachsbacher 2025 §3: f = f_HG + ‖∇μ_t‖ (H·N)ⁿ (N·ω_L)₊, the
//! Blinn–Phong-like term that makes boundaries of scientific volumes read as
//! surfaces. N = ∇μ_t/‖∇μ_t‖ of the *classified* extinction (checklist §1),
//! flipped towards the viewer (the printed N points into denser matter);
//! H = normalize(ω_L − ω) for a ray travelling along ω. The lobe is
//! unnormalised and grows with ‖∇μ_t‖, so it is evaluated in the paper's
//! normalised units (the caller scales the gradient), and only at
//! next-event estimation: directions are sampled from HG alone.

use super::medium::SceneMedium;
use fogbank_math::Vec3;

/// The scatter function of Lerzer and Dachsbacher 2025 §3 at `p` for a ray along `d` toward
/// the light direction `wi`: HG, plus the gradient lobe of exponent `n`
/// when `lobe` is set, with ∇μ_t in the [−1, 1]³ units of `unit` (2 / the
/// medium's longest world extent; μ and the length each scale by 1/unit).
pub fn dvr_phase(m: &SceneMedium, p: Vec3, d: Vec3, wi: Vec3, lobe: Option<f32>, unit: f32) -> f32 {
    let hg = m.phase.eval(d.dot(wi));
    match lobe {
        None => hg,
        Some(n) => hg + gradient_lobe(m.gradient_sigma_t(p) / (unit * unit), d, wi, n),
    }
}

/// The lobe for a ray travelling along `omega` (unit), towards the light
/// `omega_l` (unit), with extinction gradient `grad` and exponent `n`.
#[inline]
pub fn gradient_lobe(grad: Vec3, omega: Vec3, omega_l: Vec3, n: f32) -> f32 {
    let g = grad.length();
    if !(g > 0.0 && g.is_finite()) {
        return 0.0;
    }
    let mut normal = grad / g;
    if normal.dot(-omega) < 0.0 {
        normal = -normal;
    }
    let h = (omega_l - omega).normalize_or_zero();
    let n_l = normal.dot(omega_l);
    if n_l <= 0.0 {
        return 0.0;
    }
    g * h.dot(normal).max(0.0).powf(n) * n_l
}

#[cfg(test)]
mod shading_test {
    use super::*;

    #[test]
    fn lobe_peaks_at_the_mirror_direction_and_vanishes_behind() {
        // Viewer looks down −z onto a surface whose gradient points into
        // the matter (−z): N is flipped to +z, towards the viewer.
        let omega = -Vec3::Z;
        let grad = Vec3::new(0.0, 0.0, -3.0);
        // Light straight above: H = +z = N, N·ω_L = 1: the full ‖∇μ‖.
        assert!((gradient_lobe(grad, omega, Vec3::Z, 40.0) - 3.0).abs() < 1e-5);
        // Light behind the surface: nothing.
        assert_eq!(gradient_lobe(grad, omega, -Vec3::Z, 40.0), 0.0);
        // Off the mirror direction the exponent narrows it.
        let l = Vec3::new(0.6, 0.0, 0.8);
        let wide = gradient_lobe(grad, omega, l, 1.0);
        let narrow = gradient_lobe(grad, omega, l, 40.0);
        assert!(narrow < wide && narrow > 0.0);
        assert_eq!(gradient_lobe(Vec3::ZERO, omega, Vec3::Z, 40.0), 0.0);
    }
}
