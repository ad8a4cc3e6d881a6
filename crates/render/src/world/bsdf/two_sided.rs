//! Mitsuba 3's `twosided` adapter: one-sided reflection models (diffuse,
//! conductors, plastic) scatter on the back face too — with the same BSDF
//! or a second one — by evaluating them in the frame mirrored through the
//! surface when `wo` is below it.

use super::model::Bsdf;
use super::sample::BsdfSample;
use glam::Vec3;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TwoSided {
    pub front: Bsdf,
    pub back: Bsdf,
}

fn flip(w: Vec3) -> Vec3 {
    Vec3::new(w.x, w.y, -w.z)
}

impl TwoSided {
    /// The same BSDF on both faces.
    pub fn new(bsdf: Bsdf) -> TwoSided {
        TwoSided {
            front: bsdf,
            back: bsdf,
        }
    }

    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        if wo.z >= 0.0 {
            self.front.eval(wo, wi)
        } else {
            self.back.eval(flip(wo), flip(wi))
        }
    }

    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if wo.z >= 0.0 {
            self.front.pdf(wo, wi)
        } else {
            self.back.pdf(flip(wo), flip(wi))
        }
    }

    pub fn sample(&self, wo: Vec3, uc: f32, u: [f32; 2]) -> Option<BsdfSample> {
        if wo.z >= 0.0 {
            self.front.sample(wo, uc, u)
        } else {
            self.back.sample(flip(wo), uc, u).map(|mut s| {
                s.wi = flip(s.wi);
                s
            })
        }
    }
}

#[cfg(test)]
mod two_sided_test {
    use super::*;

    #[test]
    fn back_face_mirrors_the_front() {
        let d = Bsdf::Diffuse {
            reflectance: Vec3::splat(0.5),
        };
        let one = TwoSided::new(d);
        let (wo, wi) = (
            Vec3::new(0.3, 0.1, 0.9).normalize(),
            Vec3::new(-0.2, 0.4, 0.8).normalize(),
        );
        // One-sided: black from below; two-sided: the mirrored value.
        assert_eq!(d.eval(flip(wo), flip(wi)), Vec3::ZERO);
        assert_eq!(one.eval(flip(wo), flip(wi)), d.eval(wo, wi));
        assert_eq!(one.pdf(flip(wo), flip(wi)), d.pdf(wo, wi));
        let s = one.sample(flip(wo), 0.3, [0.2, 0.7]).unwrap();
        assert!(s.wi.z < 0.0);
        assert_eq!(flip(s.wi), d.sample(wo, 0.3, [0.2, 0.7]).unwrap().wi);
        // Reflection only: light from the other side of the surface does
        // not pass.
        assert_eq!(one.eval(wo, flip(wi)), Vec3::ZERO);
    }
}
