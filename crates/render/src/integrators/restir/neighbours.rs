//! Where spatial reuse looks (Lin et al. 2021 §5.3): 3 neighbours within a radius
//! of 10 pixels, drawn from a low-discrepancy sequence (the authors' code:
//! the R2 sequence, Roberts 2018), rotated per pixel and frame by a hash so
//! that neighbouring pixels do not reuse in lockstep.

use fogbank_math::rng::{pcg3d, unit_f32};

/// The plastic number g (x³ = x + 1), whose powers give R2's step.
const PLASTIC: f64 = 1.324_717_957_244_746;

/// Point `k` of the R2 sequence in [0, 1)².
pub fn r2(k: u32) -> [f32; 2] {
    let a1 = 1.0 / PLASTIC;
    let a2 = 1.0 / (PLASTIC * PLASTIC);
    let k = k as f64;
    [(0.5 + a1 * k).fract() as f32, (0.5 + a2 * k).fract() as f32]
}

/// Offset of spatial neighbour `k` of pixel `pixel` in frame `frame`:
/// uniform in the disk of `radius` pixels (area-preserving map of R2 point
/// `k` shifted by a per-pixel-and-frame random offset), never (0, 0).
pub fn neighbour_offset(pixel: u32, frame: u32, k: u32, radius: f32) -> [i32; 2] {
    let h = pcg3d([pixel, frame, 0x5E57_1A7F]);
    let shift = [unit_f32(h[0]), unit_f32(h[1])];
    let p = r2(k);
    for attempt in 0..8u32 {
        let u = (p[0] + shift[0] + attempt as f32 * 0.618_034).fract();
        let v = (p[1] + shift[1]).fract();
        let r = radius * u.sqrt();
        let phi = std::f32::consts::TAU * v;
        let o = [
            (r * phi.cos()).round() as i32,
            (r * phi.sin()).round() as i32,
        ];
        if o != [0, 0] {
            return o;
        }
    }
    [1, 0]
}
