//! The scenes of Lin et al. 2021's dynamic studies (`restir-dynamic`,
//! `restir-bias`), as scene text: the procedural cloud or the animated
//! procedural plume under the sky probe, seen by a camera that may orbit,
//! with an optional sun that may sweep round. 128×96 (or smaller),
//! pixel-centre rays, the `restir` integrator with spatial radius 2 px
//! (see `equal_time::RADIUS`).

/// What moves in a dynamic scene.
#[derive(Clone, Copy, Debug)]
pub enum Motion {
    Still,
    /// The camera orbits the medium by this many degrees per frame, until
    /// frame `stop` (then holds).
    Orbit {
        degrees: f32,
        stop: u32,
    },
    /// The animated plume at this frame rate (its matter moves 0.15 box
    /// heights per second).
    Plume {
        fps: f32,
    },
    /// A sun whose direction turns this many degrees per frame.
    SunSweep {
        degrees: f32,
    },
    /// The cloud moves sideways (rigidly) this many world units per frame.
    Drift {
        step: f32,
    },
}

pub struct Shot {
    pub motion: Motion,
    pub frames: u32,
    pub k: u32,
    pub width: u32,
    pub height: u32,
}

const CLOUD: &str = "[[media]]\ndensity = { procedural = \"cloud\", resolution = 128, seed = 7 }\n\
    sigma_t_scale = 40.0\nalbedo = [0.95, 0.95, 0.95]\nphase = { type = \"hg\", g = 0.5 }\n";
const PLUME: &str = "[[media]]\ndensity = { procedural = \"plume\", resolution = 128, seed = 7 }\n\
    sigma_t_scale = 60.0\nalbedo = [0.9, 0.9, 0.9]\nphase = { type = \"hg\", g = 0.3 }\n";
const SKY: &str = "[[lights]]\ntype = \"envmap\"\nfile = \"probes/sky.hdr\"\n";

fn sun_direction(degrees: f32) -> [f32; 3] {
    let a = degrees.to_radians();
    [0.8 * a.sin(), -0.6, 0.8 * a.cos()]
}

impl Shot {
    pub fn text(&self) -> String {
        let (w, h, k, n) = (self.width, self.height, self.k, self.frames);
        let mut s = format!(
            "[camera]\nfrom = [0.0, 0.1, 2.0]\nto = [0.0, 0.0, 0.0]\nfov = 40.0\nwidth = {w}\nheight = {h}\n\
             [integrator]\ntype = \"restir\"\nmax_depth = {k}\nradius = 2.0\n[render]\npixel_jitter = false\n"
        );
        let mut anim = String::new();
        let fps = match self.motion {
            Motion::Plume { fps } => fps,
            _ => 24.0,
        };
        match self.motion {
            Motion::Plume { .. } => s += &format!("{PLUME}{SKY}"),
            Motion::SunSweep { degrees } => {
                s += CLOUD;
                s += "[[lights]]\ntype = \"constant\"\nradiance = [0.08, 0.1, 0.14]\n";
                let d = sun_direction(0.0);
                s += &format!(
                    "[[lights]]\ntype = \"directional\"\ndirection = {d:?}\nirradiance = [4.0, 3.8, 3.5]\n"
                );
                for f in 0..n {
                    let d = sun_direction(degrees * f as f32);
                    anim += &format!(
                        "[[animation.lights]]\nlight = 1\nframe = {f}\ndirection = {d:?}\n"
                    );
                }
            }
            Motion::Orbit { degrees, stop } => {
                s += &format!("{CLOUD}{SKY}");
                for f in 0..n {
                    let a = (degrees * f.min(stop) as f32).to_radians();
                    let from = [2.0 * a.sin(), 0.1, 2.0 * a.cos()];
                    anim += &format!("[[animation.camera]]\nframe = {f}\nfrom = {from:?}\n");
                }
            }
            Motion::Drift { step } => {
                s += &format!("{CLOUD}{SKY}");
                let x0 = -0.5 * step * (n - 1) as f32;
                let x1 = x0 + step * (n - 1) as f32;
                anim += &format!(
                    "[[animation.media]]\nmedium = 0\nframe = 0\ntranslate = [{x0:?}, 0.0, 0.0]\n\
                     [[animation.media]]\nmedium = 0\nframe = {}\ntranslate = [{x1:?}, 0.0, 0.0]\n",
                    n - 1
                );
            }
            Motion::Still => s += &format!("{CLOUD}{SKY}"),
        }
        format!("{s}[animation]\nframes = {n}\nfps = {fps}\n{anim}")
    }
}
