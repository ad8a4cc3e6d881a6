//! Temporal reuse (Lin et al. 2021 §4.4, §5.2): the pixel's candidate reservoir
//! combined with the previous frame's final reservoir at the pixel its
//! first vertex x_1 came from. x_1 (of the candidate-stage sample) is
//! moved back along the medium's velocity for one frame, projected with the
//! previous camera, and one of the four nearest pixels is picked with
//! bilinear probability (stochastic reprojection). A sample without x_1
//! reprojects a medium point resampled along its ray instead (§5.2,
//! [`super::velocity_resampling`]); without velocity resampling, or when
//! the ray sees no medium, it follows the background (its direction, a
//! point at infinity, under the previous camera). A point off the previous
//! screen reuses the same pixel (the authors' code). A medium moved by its placement keys maps the point back
//! with the previous frame's transform too (the checklist's choice for
//! rigidly animated volumes). The previous reservoir's M is capped at Q·M (§2.5), and
//! its target p̂_prev is evaluated with the previous frame's camera, volume
//! and lights (Talbot, as the authors' code).

use super::combine::Input;
use super::integrator::{pixel_ray, FrameData, Restir};
use super::path::PathSample;
use super::reservoir::Reservoir;
use super::velocity_resampling::resample_point;
use fogbank_math::{Pcg32, Vec3};

/// The previous frame: its final reservoirs and its data (camera, volume,
/// lights).
pub struct Previous<'a> {
    pub reservoirs: &'a [Reservoir<PathSample>],
    pub data: &'a FrameData<'a>,
}

/// Where the medium point `x` (current frame) was in the previous frame:
/// back along the velocity for one frame, then through the current
/// placement into index space and out through the old one.
fn map_back(cur: &FrameData, prev: &FrameData, x: Vec3) -> Vec3 {
    let m = &cur.world.media[0];
    let x = match &m.velocity {
        Some(v) => x - v.at(x) * cur.world.frame_dt,
        None => x,
    };
    let p = &prev.world.media[0].medium;
    let q = m.medium.world_to_index.transform_point3(x.as_dvec3());
    p.index_to_world.transform_point3(q).as_vec3()
}

/// What a pixel's temporal reprojection follows.
enum Seen {
    /// A medium point (x_1, or a resampled one).
    Point(Vec3),
    /// The background along this direction.
    Background(Vec3),
}

impl Restir {
    pub fn temporal(
        &self,
        cur: &FrameData,
        prev: &Previous,
        pixel: (u32, u32),
        cand: Reservoir<PathSample>,
        rng: &mut Pcg32,
        lookups: &mut u32,
    ) -> Reservoir<PathSample> {
        let ray = &pixel_ray(cur.world, pixel);
        let cam = &prev.data.world.camera;
        let (w, h) = (cam.width, cam.height);
        let u = [rng.next_f32(), rng.next_f32()];
        let p = &self.params;
        // Where the pixel's content was: a medium point moved back along
        // the velocity, else the background direction (a point at infinity).
        let seen = if !p.reprojection {
            None
        } else if let Some(y) = cand.y.filter(|y| y.k >= 1) {
            Some(Seen::Point(ray.at(y.z[0])))
        } else {
            let mip1 = cur.mips.level(&cur.world.media[0].medium, 1);
            let resampled = p
                .velocity_resampling
                .then(|| resample_point(mip1, ray, rng, lookups))
                .flatten();
            Some(resampled.map_or(Seen::Background(ray.d), Seen::Point))
        };
        let from = seen
            .and_then(|s| match s {
                Seen::Point(x) => cam.project(map_back(cur, prev.data, x)),
                Seen::Background(d) => cam.project_direction(d),
            })
            .and_then(|(px, py)| {
                let (x, y) = ((px - 0.5 + u[0]).floor(), (py - 0.5 + u[1]).floor());
                (x >= 0.0 && y >= 0.0 && x < w as f32 && y < h as f32)
                    .then_some((x as u32, y as u32))
            })
            .unwrap_or(pixel);
        let mut old = prev.reservoirs[(from.1 * w + from.0) as usize];
        old.cap(self.params.q() * cand.m);
        let inputs = [
            Input {
                res: cand,
                pixel: (pixel.1 * w + pixel.0) as usize,
                ray: *ray,
                data: cur,
            },
            Input {
                res: old,
                pixel: (from.1 * w + from.0) as usize,
                ray: pixel_ray(prev.data.world, from),
                data: prev.data,
            },
        ];
        self.combine(&inputs, self.params.mis, rng, lookups)
    }
}
