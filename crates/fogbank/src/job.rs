//! The work of a render: how many samples per pixel (or how long), which
//! part of them (a shard), with the checks every front end shares.

use crate::error::Error;
use crate::renderer::{Device, Observer, Rendered, Renderer};
use fogbank_render::integrators::IntegratorKind;
use fogbank_render::shard::{Piece, Shard};
use fogbank_render::{Progress, RenderOptions, Scene};
use std::time::Duration;

#[derive(Clone, Debug, Default)]
pub struct RenderJob {
    /// Samples per pixel; `None`: the scene's `render.spp`, or as many as
    /// `time_budget` allows when one is given.
    pub spp: Option<u32>,
    /// Stop starting passes after this many seconds (with `spp`: whichever
    /// comes first).
    pub time_budget: Option<f64>,
    /// Render only this part of the work, for `fogbank merge`.
    pub shard: Option<Shard>,
}

impl RenderJob {
    /// Samples per pixel asked for: `u32::MAX` for "until the budget".
    pub fn spp(&self, scene: &Scene) -> u32 {
        match (self.spp, self.time_budget) {
            (Some(s), _) => s,
            (None, Some(_)) => u32::MAX,
            (None, None) => scene.desc.render.spp,
        }
    }

    /// The render loop's options, after checking what a front end can get
    /// wrong.
    pub fn options(&self, scene: &Scene) -> Result<RenderOptions, Error> {
        if let Some(b) = self.time_budget {
            if !(b > 0.0 && b.is_finite()) {
                return Err(Error::invalid(
                    "--time-budget must be a positive number of seconds",
                ));
            }
        }
        let spp = self.spp(scene);
        if spp == 0 {
            return Err(Error::invalid("render.spp must be at least 1"));
        }
        Ok(RenderOptions {
            spp,
            seed: scene.desc.render.seed,
            time_budget: self.time_budget.map(Duration::from_secs_f64),
        })
    }

    /// The sample indices and pixels this job renders.
    pub fn piece(&self, spp: u32) -> Piece {
        self.shard.map_or(Piece::whole(spp), |s| s.piece(spp))
    }

    /// What a shard cannot be combined with, known before the scene is
    /// loaded: a time budget, the GPU.
    pub fn check_shard(&self, device: Device) -> Result<(), Error> {
        let Some(s) = self.shard else {
            return Ok(());
        };
        let why = if self.time_budget.is_some() {
            "--time-budget: a shard's part of the work is fixed by spp; give --spp"
        } else if device == Device::Gpu {
            "--device gpu: GPU films keep running means in f32, whose parts do not add up bit for bit; shard CPU renders"
        } else {
            return Ok(());
        };
        Err(Error::invalid(format!(
            "--shard {}: not with {why}",
            s.label()
        )))
    }

    /// Whether `scene`'s integrator can render this job's part.
    pub fn check_integrator(&self, scene: &Scene) -> Result<(), Error> {
        if self.shard.is_some() && matches!(scene.integrator, IntegratorKind::Restir(_)) {
            return Err(Error::invalid("--shard: `restir` carries reservoirs from pass to pass and pixel to pixel, so its parts cannot be rendered apart; render it whole"));
        }
        Ok(())
    }

    /// Renders `scene` on `renderer`, calling `after(film, seconds)` after
    /// every pass when given.
    pub fn run(
        &self,
        renderer: &Renderer,
        scene: &Scene,
        progress: &Progress,
        after: Option<Observer>,
    ) -> Result<Rendered, Error> {
        self.check_shard(renderer.device())?;
        self.check_integrator(scene)?;
        let opts = self.options(scene)?;
        renderer.render(scene, &opts, &self.piece(opts.spp), progress, after)
    }
}
