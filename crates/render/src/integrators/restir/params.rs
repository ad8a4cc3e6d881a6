//! The parameters of `restir` (the table is in the module docs of
//! [`super`]) and their validation.

use super::path::MAX_K;
use super::volume::MAX_MIP;
use crate::error::SceneError;
use crate::integrators::plugin::{Capabilities, IntegratorParams};
use crate::params::{take_estimator, Param, ParamReader};
use fogbank_estimators::estimator::{AnalyticTrilinear, RegularTracking};
use fogbank_estimators::Estimator;

pub const PARAMS: [Param; 21] = [
    Param {
        key: "max_depth",
        default: "3",
        meaning: "K, the longest path in vertices, medium or surface (1..=8)",
    },
    Param {
        key: "candidates",
        default: "4",
        meaning: "M, random walks per pixel and frame",
    },
    Param {
        key: "reuse",
        default: "spatiotemporal",
        meaning: "`none` (plain RIS), `spatial`, `temporal`, `spatiotemporal`",
    },
    Param {
        key: "mis",
        default: "talbot",
        meaning: "combination MIS: `talbot` (Eq. 11), `stochastic` (Eq. 10), `uniform` (1/M, Eq. 9, biased), `pairwise` (beyond the paper: 2N target evaluations for N neighbours instead of N(N + 1))",
    },
    Param {
        key: "temporal_cap",
        default: "4 (10 with shapes)",
        meaning: "Q: the previous reservoir's M is capped at Q·M",
    },
    Param {
        key: "neighbours",
        default: "3",
        meaning: "spatial neighbours besides the pixel itself (0..=32)",
    },
    Param {
        key: "radius",
        default: "10",
        meaning: "spatial reuse radius in pixels",
    },
    Param {
        key: "frames",
        default: "8",
        meaning: "frames per sequence of a static render (the last one is kept)",
    },
    Param {
        key: "primary_mip",
        default: "1",
        meaning: "mip of candidate regular tracking on the primary segment (0: exact trilinear free flight at full resolution)",
    },
    Param {
        key: "indirect_mip",
        default: "2",
        meaning: "mip of candidate regular tracking after the first vertex",
    },
    Param {
        key: "nee_mip",
        default: "2",
        meaning: "mip of the ray-marched T̃ on candidate NEE segments",
    },
    Param {
        key: "nee_transmittance",
        default: "true",
        meaning: "false: candidates ignore NEE transmittance (Fig. 11)",
    },
    Param {
        key: "reuse_mip",
        default: "1",
        meaning: "mip of the ray-marched T̃ in the reuse target p̂ (0: full resolution)",
    },
    Param {
        key: "reuse_step",
        default: "1",
        meaning: "marching step of T̃ in p̂, in voxel diagonals of `reuse_mip`",
    },
    Param {
        key: "estimator",
        default: "analytic_trilinear",
        meaning: "transmittance of final shading: exact, or any unbiased estimator",
    },
    Param {
        key: "reuse_bc4",
        default: "false",
        meaning: "march the reuse T̃ through a BC4-compressed copy of its mip (4 bits a voxel, §5.1; p̂ only, so no bias)",
    },
    Param {
        key: "primary_table",
        default: "true",
        meaning: "tabulate the reuse T̃ of every pixel's primary ray once per frame (`restir::primary`): the same p̂ bit for bit with one lookup per first segment instead of a march (CPU; the GPU marches)",
    },
    Param {
        key: "shift",
        default: "direction",
        meaning: "path shift of reuse: `direction` (ω_i and z_i copied, §4.2's default) or `vertex` (x_2 … x_k kept, 1/z² terms; not with shapes)",
    },
    Param {
        key: "reprojection",
        default: "true",
        meaning: "temporal reuse follows x_1 to the previous frame (false: the same pixel, Fig. 8)",
    },
    Param {
        key: "velocity_resampling",
        default: "true",
        meaning: "a sample without x_1 reprojects through a medium point resampled ∝ σ_t·T along its ray (§5.2, Fig. 13)",
    },
    Param {
        key: "rr_depth",
        default: "3",
        meaning: "Russian roulette by albedo after vertex x_rr_depth (only when K > rr_depth, §6.1)",
    },
];

/// Which reuse passes run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Reuse {
    pub temporal: bool,
    pub spatial: bool,
}

impl Reuse {
    pub fn parse(s: &str) -> Option<Reuse> {
        let (temporal, spatial) = match s {
            "none" => (false, false),
            "spatial" => (false, true),
            "temporal" => (true, false),
            "spatiotemporal" => (true, true),
            _ => return None,
        };
        Some(Reuse { temporal, spatial })
    }
    pub fn name(self) -> &'static str {
        match (self.temporal, self.spatial) {
            (false, false) => "none",
            (false, true) => "spatial",
            (true, false) => "temporal",
            (true, true) => "spatiotemporal",
        }
    }
}

#[derive(Clone, Debug, PartialEq)]
pub struct RestirParams {
    pub max_depth: u32,
    pub candidates: u32,
    pub reuse: Reuse,
    pub mis: ReuseMis,
    /// Q (§2.5); `None`: 4, or 10 in a scene with shapes (§5.3), which
    /// the built integrator resolves.
    pub temporal_cap: Option<f32>,
    pub neighbours: u32,
    pub radius: f32,
    pub frames: u32,
    pub primary_mip: u32,
    pub indirect_mip: u32,
    pub nee_mip: u32,
    pub nee_transmittance: bool,
    pub reuse_mip: u32,
    pub reuse_step: f32,
    pub estimator: Estimator,
    pub rr_depth: u32,
    /// Vertex reuse (§4.2's option) instead of direction reuse.
    pub vertex_reuse: bool,
    /// March the reuse target through a BC4-compressed mip (§5.1).
    pub reuse_bc4: bool,
    /// Tabulate the reuse T̃ of primary rays once per frame (CPU speed-up).
    pub primary_table: bool,
    /// Temporal reuse follows x_1 to the previous frame (§4.4).
    pub reprojection: bool,
    /// A sample without x_1 reprojects a resampled medium point (§5.2).
    pub velocity_resampling: bool,
}

impl RestirParams {
    /// Q as given, else the paper's 4 for volumes alone.
    pub fn q(&self) -> f32 {
        self.temporal_cap.unwrap_or(4.0)
    }
}

impl Default for RestirParams {
    fn default() -> Self {
        RestirParams {
            max_depth: 3,
            candidates: 4,
            reuse: Reuse {
                temporal: true,
                spatial: true,
            },
            mis: ReuseMis::Talbot,
            temporal_cap: None,
            neighbours: 3,
            radius: 10.0,
            frames: 8,
            primary_mip: 1,
            indirect_mip: 2,
            nee_mip: 2,
            nee_transmittance: true,
            reuse_mip: 1,
            reuse_step: 1.0,
            estimator: Estimator::AnalyticTrilinear(AnalyticTrilinear),
            rr_depth: 3,
            vertex_reuse: false,
            reuse_bc4: false,
            primary_table: true,
            reprojection: true,
            velocity_resampling: true,
        }
    }
}

fn in_range<T: PartialOrd + std::fmt::Display + Copy>(
    r: &ParamReader,
    key: &str,
    v: T,
    lo: T,
    hi: T,
) -> Result<T, SceneError> {
    if v >= lo && v <= hi {
        Ok(v)
    } else {
        Err(SceneError(format!(
            "{}: {v} is outside {lo}..={hi}",
            r.key_path(key)
        )))
    }
}

impl IntegratorParams for RestirParams {
    const NAME: &'static str = "restir";
    const PARAMS: &'static [Param] = &PARAMS;
    const CAPABILITIES: Capabilities = Capabilities {
        chromatic: false,
        far_clip: false,
    };

    fn read(r: &mut ParamReader) -> Result<Self, SceneError> {
        let d = RestirParams::default();
        let max_depth = r.take("max_depth")?.unwrap_or(d.max_depth);
        let candidates = r.take("candidates")?.unwrap_or(d.candidates);
        let (reuse, mis) = read_reuse(r, &d)?;
        let temporal_cap: Option<f32> = r.take("temporal_cap")?;
        let neighbours = r.take("neighbours")?.unwrap_or(d.neighbours);
        let radius: f32 = r.take("radius")?.unwrap_or(d.radius);
        let frames = r.take("frames")?.unwrap_or(d.frames);
        let mips = ["primary_mip", "indirect_mip", "nee_mip", "reuse_mip"];
        let mut levels = [d.primary_mip, d.indirect_mip, d.nee_mip, d.reuse_mip];
        for (key, level) in mips.iter().zip(levels.iter_mut()) {
            let v = r.take(key)?.unwrap_or(*level);
            *level = in_range(r, key, v, 0, MAX_MIP)?;
        }
        let nee_transmittance = r.take("nee_transmittance")?.unwrap_or(d.nee_transmittance);
        let reuse_step: f32 = r.take("reuse_step")?.unwrap_or(d.reuse_step);
        let estimator = read_estimator(r, &d)?;
        let rr_depth = r.take("rr_depth")?.unwrap_or(d.rr_depth);
        let reuse_bc4 = r.take("reuse_bc4")?.unwrap_or(d.reuse_bc4);
        let primary_table = r.take("primary_table")?.unwrap_or(d.primary_table);
        let reprojection = r.take("reprojection")?.unwrap_or(d.reprojection);
        let velocity_resampling = r
            .take("velocity_resampling")?
            .unwrap_or(d.velocity_resampling);
        let vertex_reuse = read_shift(r, &d)?;
        Ok(RestirParams {
            max_depth: in_range(r, "max_depth", max_depth, 1, MAX_K as u32)?,
            candidates: in_range(r, "candidates", candidates, 1, 1024)?,
            reuse,
            mis,
            temporal_cap: match temporal_cap {
                Some(q) => Some(in_range(r, "temporal_cap", q, 0.01, 1e6)?),
                None => None,
            },
            neighbours: in_range(r, "neighbours", neighbours, 0, 32)?,
            radius: in_range(r, "radius", radius, 1.0, 1e4)?,
            frames: in_range(r, "frames", frames, 1, 1_000_000)?,
            primary_mip: levels[0],
            indirect_mip: levels[1],
            nee_mip: levels[2],
            nee_transmittance,
            reuse_mip: levels[3],
            reuse_step: in_range(r, "reuse_step", reuse_step, 0.01, 100.0)?,
            estimator,
            rr_depth: in_range(r, "rr_depth", rr_depth, 1, 1000)?,
            vertex_reuse,
            reuse_bc4,
            primary_table,
            reprojection,
            velocity_resampling,
        })
    }

    fn write(&self, t: &mut toml::Table) {
        t.insert("max_depth".into(), i64::from(self.max_depth).into());
        t.insert("candidates".into(), i64::from(self.candidates).into());
        t.insert("reuse".into(), self.reuse.name().into());
        t.insert("mis".into(), self.mis.name().into());
        if let Some(q) = self.temporal_cap {
            t.insert("temporal_cap".into(), f64::from(q).into());
        }
        t.insert("neighbours".into(), i64::from(self.neighbours).into());
        t.insert("radius".into(), f64::from(self.radius).into());
        t.insert("frames".into(), i64::from(self.frames).into());
        t.insert("primary_mip".into(), i64::from(self.primary_mip).into());
        t.insert("indirect_mip".into(), i64::from(self.indirect_mip).into());
        t.insert("nee_mip".into(), i64::from(self.nee_mip).into());
        t.insert("nee_transmittance".into(), self.nee_transmittance.into());
        t.insert("reuse_mip".into(), i64::from(self.reuse_mip).into());
        t.insert("reuse_step".into(), f64::from(self.reuse_step).into());
        t.insert(
            "estimator".into(),
            crate::params::estimator_value(self.estimator),
        );
        t.insert("rr_depth".into(), i64::from(self.rr_depth).into());
        t.insert("reuse_bc4".into(), self.reuse_bc4.into());
        t.insert("primary_table".into(), self.primary_table.into());
        t.insert("reprojection".into(), self.reprojection.into());
        t.insert(
            "velocity_resampling".into(),
            self.velocity_resampling.into(),
        );
        t.insert(
            "shift".into(),
            if self.vertex_reuse {
                "vertex"
            } else {
                "direction"
            }
            .into(),
        );
    }

    fn estimator(&self) -> Estimator {
        self.estimator
    }
}

/// MIS of a combination (`mis = "talbot" | "stochastic" | "uniform" |
/// "pairwise"`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ReuseMis {
    Talbot,
    Stochastic,
    Uniform,
    /// Beyond Lin et al. 2021: pairwise MIS against the receiving pixel
    /// ([`super::reservoir::pairwise_canonical`]).
    Pairwise,
}

impl ReuseMis {
    /// Every variant, in the order of the GPU's `MIS_*` ids.
    pub const ALL: [ReuseMis; 4] = [
        ReuseMis::Talbot,
        ReuseMis::Stochastic,
        ReuseMis::Uniform,
        ReuseMis::Pairwise,
    ];
    pub const NAMES: &'static str = "talbot, stochastic, uniform or pairwise";
    pub fn parse(s: &str) -> Option<ReuseMis> {
        ReuseMis::ALL.into_iter().find(|m| m.name() == s)
    }
    pub fn name(self) -> &'static str {
        match self {
            ReuseMis::Talbot => "talbot",
            ReuseMis::Stochastic => "stochastic",
            ReuseMis::Uniform => "uniform",
            ReuseMis::Pairwise => "pairwise",
        }
    }
}

/// `reuse` (which passes) and `mis` (how reuse weights its inputs).
fn read_reuse(r: &mut ParamReader, d: &RestirParams) -> Result<(Reuse, ReuseMis), SceneError> {
    let reuse = match r.take::<String>("reuse")? {
        None => d.reuse,
        Some(s) => Reuse::parse(&s).ok_or_else(|| {
            SceneError(format!(
                "{}: `{s}` is not none, spatial, temporal or spatiotemporal",
                r.key_path("reuse")
            ))
        })?,
    };
    let mis = match r.take::<String>("mis")? {
        None => d.mis,
        Some(s) => ReuseMis::parse(&s).ok_or_else(|| {
            SceneError(format!(
                "{}: `{s}` is not {}",
                r.key_path("mis"),
                ReuseMis::NAMES
            ))
        })?,
    };
    Ok((reuse, mis))
}

/// Final shading's transmittance estimator, which must be an unbiased
/// estimate of the trilinear field's.
fn read_estimator(r: &mut ParamReader, d: &RestirParams) -> Result<Estimator, SceneError> {
    let estimator = if r.has("estimator") {
        take_estimator(r)?
    } else {
        d.estimator
    };
    if estimator.biased() || estimator == Estimator::RegularTracking(RegularTracking) {
        return Err(SceneError(format!(
            "{}: `{}` is not an unbiased transmittance of the trilinear field, which final shading needs",
            r.key_path("estimator"),
            estimator.name()
        )));
    }
    Ok(estimator)
}

/// `shift`: direction reuse (false) or vertex reuse (true), Lin et al. 2021 §4.2.
fn read_shift(r: &mut ParamReader, d: &RestirParams) -> Result<bool, SceneError> {
    Ok(match r.take::<String>("shift")?.as_deref() {
        None => d.vertex_reuse,
        Some("direction") => false,
        Some("vertex") => true,
        Some(other) => {
            return Err(SceneError(format!(
                "{}: `{other}` is not direction or vertex",
                r.key_path("shift")
            )))
        }
    })
}
