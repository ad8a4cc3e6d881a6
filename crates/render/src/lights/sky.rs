//! A procedural sky: a smooth gradient from a horizon colour up to a zenith
//! colour, and a ground colour below the horizon, built into a
//! latitude–longitude [`Envmap`] so that it is importance-sampled, rendered
//! on the GPU and animated exactly like an environment map file. It is what
//! a scene needs for outdoor light without shipping an HDR file (the
//! default scene's sky).

use super::envmap::Envmap;
use glam::Mat3;

/// Rows of the generated map: fine enough (0.09° each) that the nearest
/// lookup of [`Envmap`] shows no bands in a view of the sky. The gradient
/// depends on elevation only, so a few columns suffice.
const ROWS: usize = 2048;
const COLUMNS: usize = 4;

/// The sky's radiance for a direction of elevation sin(e) = `y` (unit
/// direction's +y component): zenith ↔ horizon by (1 − y)³, which keeps
/// the horizon band narrow as in a clear sky, and ground below the horizon
/// blended over the first few degrees so the horizon has no hard edge.
pub fn sky_radiance(y: f32, zenith: [f32; 3], horizon: [f32; 3], ground: [f32; 3]) -> [f32; 3] {
    let mix = |a: [f32; 3], b: [f32; 3], t: f32| std::array::from_fn(|c| a[c] + (b[c] - a[c]) * t);
    if y >= 0.0 {
        mix(zenith, horizon, (1.0 - y).powi(3))
    } else {
        mix(horizon, ground, (-y * 12.0).min(1.0))
    }
}

/// The sky's latitude–longitude pixels (width, height, rows from the
/// zenith down), each the gradient at its row's centre: what
/// [`sky_envmap`] builds, and what `fogbank convert` writes for Mitsuba.
pub fn sky_pixels(
    zenith: [f32; 3],
    horizon: [f32; 3],
    ground: [f32; 3],
) -> (usize, usize, Vec<[f32; 3]>) {
    let (w, h) = (COLUMNS, ROWS);
    let mut rgb = Vec::with_capacity(w * h);
    for i in 0..h {
        let theta = std::f32::consts::PI * (i as f32 + 0.5) / h as f32;
        let c = sky_radiance(theta.cos(), zenith, horizon, ground);
        rgb.extend(std::iter::repeat_n(c, w));
    }
    (w, h, rgb)
}

/// The sky as an environment map (radiance × `scale`), each pixel the
/// gradient at its row's centre.
pub fn sky_envmap(
    zenith: [f32; 3],
    horizon: [f32; 3],
    ground: [f32; 3],
    scale: f32,
) -> Result<Envmap, String> {
    let (w, h, rgb) = sky_pixels(zenith, horizon, ground);
    Envmap::from_pixels(w, h, rgb, scale, Mat3::IDENTITY)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    #[test]
    fn gradient_reaches_its_three_colours() {
        let (z, h, g) = ([0.2, 0.4, 1.0], [0.9, 0.9, 1.0], [0.3, 0.25, 0.2]);
        let close = |a: [f32; 3], b: [f32; 3]| (0..3).all(|c| (a[c] - b[c]).abs() < 1e-6);
        assert!(close(sky_radiance(1.0, z, h, g), z));
        assert!(close(sky_radiance(0.0, z, h, g), h));
        assert!(close(sky_radiance(-1.0, z, h, g), g));
        let env = sky_envmap(z, h, g, 2.0).unwrap();
        let up = env.eval(Vec3::Y);
        let down = env.eval(-Vec3::Y);
        for c in 0..3 {
            assert!((up[c] - 2.0 * z[c]).abs() < 0.02, "zenith {up:?}");
            assert!((down[c] - 2.0 * g[c]).abs() < 1e-6, "ground {down:?}");
        }
    }
}
