//! Spatial reuse (Lin et al. 2021 §4.3, §5.3): one round over the pixel and 3
//! neighbours within 10 pixels from the R2 sequence ([`neighbour_offset`]),
//! all from the current frame's post-temporal reservoirs, combined with
//! Talbot MIS. Neighbours off the screen are skipped.

use super::combine::Input;
use super::integrator::{FrameData, Restir};
use super::neighbours::neighbour_offset;
use super::path::PathSample;
use super::reservoir::Reservoir;
use fogbank_math::Pcg32;

impl Restir {
    pub fn spatial(
        &self,
        data: &FrameData,
        pixels: &[Reservoir<PathSample>],
        pixel: (u32, u32),
        frame: u32,
        rng: &mut Pcg32,
        lookups: &mut u32,
    ) -> Reservoir<PathSample> {
        let cam = &data.world.camera;
        let (w, h) = (cam.width as i32, cam.height as i32);
        let centre = |x: u32, y: u32| cam.ray(x as f32 + 0.5, y as f32 + 0.5);
        let index = pixel.1 * cam.width + pixel.0;
        let mut inputs = vec![Input {
            res: pixels[index as usize],
            pixel: index as usize,
            ray: centre(pixel.0, pixel.1),
            data,
        }];
        for k in 0..self.params.neighbours {
            let o = neighbour_offset(index, frame, k, self.params.radius);
            let (x, y) = (pixel.0 as i32 + o[0], pixel.1 as i32 + o[1]);
            if x < 0 || y < 0 || x >= w || y >= h {
                continue;
            }
            let (x, y) = (x as u32, y as u32);
            inputs.push(Input {
                res: pixels[(y * cam.width + x) as usize],
                pixel: (y * cam.width + x) as usize,
                ray: centre(x, y),
                data,
            });
        }
        self.combine(&inputs, self.params.mis, rng, lookups)
    }
}
