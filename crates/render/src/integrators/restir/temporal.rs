//! Temporal reuse (seed 002 §4.4, §5.2): the pixel's candidate reservoir
//! combined with the previous frame's final reservoir at the pixel its
//! first vertex x_1 came from. x_1 (of the candidate-stage sample) is
//! projected with the previous camera and one of the four nearest pixels
//! is picked with bilinear probability (stochastic reprojection); a sample
//! without x_1, or one off the previous screen, reuses the same pixel (the
//! authors' code). A medium moved by its placement keys maps x_1 back with
//! the previous frame's transform first (the checklist's choice for rigidly
//! animated volumes). The previous reservoir's M is capped at Q·M (§2.5), and
//! its target p̂_prev is evaluated with the previous frame's camera, volume
//! and lights (Talbot, as the authors' code).

use super::combine::Input;
use super::integrator::{FrameData, Restir};
use super::path::PathSample;
use super::reservoir::Reservoir;
use fogbank_math::{Pcg32, Ray, Vec3};

/// The previous frame: its final reservoirs and its data (camera, volume,
/// lights).
pub struct Previous<'a> {
    pub reservoirs: &'a [Reservoir<PathSample>],
    pub data: &'a FrameData<'a>,
}

/// Where the medium point `x` (current frame) was in the previous frame:
/// through the current placement into index space, out through the old one.
fn map_back(cur: &FrameData, prev: &FrameData, x: Vec3) -> Vec3 {
    let (c, p) = (&cur.world.media[0].medium, &prev.world.media[0].medium);
    let q = c.world_to_index.transform_point3(x.as_dvec3());
    p.index_to_world.transform_point3(q).as_vec3()
}

impl Restir {
    #[allow(clippy::too_many_arguments)]
    pub fn temporal(
        &self,
        cur: &FrameData,
        prev: &Previous,
        pixel: (u32, u32),
        ray: &Ray,
        cand: Reservoir<PathSample>,
        rng: &mut Pcg32,
        lookups: &mut u32,
    ) -> Reservoir<PathSample> {
        let cam = &prev.data.world.camera;
        let (w, h) = (cam.width, cam.height);
        let u = [rng.next_f32(), rng.next_f32()];
        let from = cand
            .y
            .filter(|y| y.k >= 1)
            .and_then(|y| cam.project(map_back(cur, prev.data, ray.at(y.z[0]))))
            .and_then(|(px, py)| {
                let (x, y) = ((px - 0.5 + u[0]).floor(), (py - 0.5 + u[1]).floor());
                (x >= 0.0 && y >= 0.0 && x < w as f32 && y < h as f32)
                    .then_some((x as u32, y as u32))
            })
            .unwrap_or(pixel);
        let mut old = prev.reservoirs[(from.1 * w + from.0) as usize];
        old.cap(self.params.temporal_cap * cand.m);
        let inputs = [
            Input {
                res: cand,
                ray: *ray,
                data: cur,
            },
            Input {
                res: old,
                ray: cam.ray(from.0 as f32 + 0.5, from.1 as f32 + 0.5),
                data: prev.data,
            },
        ];
        self.combine(&inputs, self.params.mis, rng, lookups)
    }
}
