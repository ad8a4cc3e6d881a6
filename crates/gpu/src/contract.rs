//! The CPU↔GPU contract: every id and flag bit a WGSL kernel switches on,
//! taken from the Rust definitions (the registries of estimators, distance
//! samplers, `point_mis` strategies, light and emission kinds, random-stream
//! dimensions) and written into the WGSL prelude when shaders are assembled.
//! Naming a variant on the CPU is all it takes to name it on the GPU; a
//! kernel meeting an id it has no branch for marks the sample invalid.

use fogbank_estimators::estimator::{
    AnalyticTrilinear, BiasedRayMarching, Jackknife, JackknifeMeanImportance, JackknifeNaive,
    RatioTracking, RayMarching, RegularTracking, ResidualRatioTracking, TrackLength,
    UnbiasedRayMarching,
};
use fogbank_estimators::jackknife::StepMode;
use fogbank_estimators::optical_depth::Jitter;
use fogbank_estimators::Estimator;
use fogbank_render::integrators::point_mis::Strategy;
use fogbank_render::integrators::restir::params::ReuseMis;
use fogbank_render::integrators::shared::pin_params::PinMode;
use fogbank_render::integrators::shared::{dim, DistanceSampler};
use fogbank_render::integrators::visopt::params::Scattering;
use fogbank_render::lights::Light;
use fogbank_render::world::bitmap::{BitmapFilter, WrapMode};
use fogbank_render::world::bsdf::Bsdf;
use fogbank_render::world::emission::Emission;
use fogbank_render::world::texture::Texture;

/// Bits of `Frame::est_flags`.
pub const FLAGS: [(&str, u32); 3] = [("UNIFORM_JITTER", 1), ("CLIP", 2), ("DOUBLED", 4)];
const FLAG_UNIFORM_JITTER: u32 = FLAGS[0].1;
const FLAG_CLIP: u32 = FLAGS[1].1;
const FLAG_DOUBLED: u32 = FLAGS[2].1;
/// Bits of `Frame::integrator_flags` (WGSL `INTEGRATOR_*`).
pub const INTEGRATOR_FLAGS: [(&str, u32); 6] = [
    ("LIGHT_ONLY", 1),
    ("RAY_MARCHING", 2),
    ("UNQUANTISED", 4),
    ("SURFACES", 8),
    ("TRANSMITTANCE", 16),
    ("CHROMATIC", 32),
];
/// volpath's `restir_baseline` preset: light sampling only (no
/// phase-sampled escape MIS) and Russian roulette by albedo.
pub const INTEGRATOR_LIGHT_ONLY: u32 = INTEGRATOR_FLAGS[0].1;
/// Hansen 2025: rays without pins use fixed-step ray marching (§2.4).
pub const INTEGRATOR_RAY_MARCHING: u32 = INTEGRATOR_FLAGS[1].1;
/// Hansen 2025 Fig. 4.5: pins traced along each query ray, not looked up.
pub const INTEGRATOR_UNQUANTISED: u32 = INTEGRATOR_FLAGS[2].1;
/// The scene has shapes: rays meet surfaces; without, the
/// driver compiles the surface code out.
pub const INTEGRATOR_SURFACES: u32 = INTEGRATOR_FLAGS[3].1;
/// `transmittance` with surfaces or chromatic media: the scatter kernel's
/// shadow walk along the camera ray (transmittance.rs `sample`).
pub const INTEGRATOR_TRANSMITTANCE: u32 = INTEGRATOR_FLAGS[4].1;
/// The scene has chromatic media: NEE shares one walk between channels
/// where the estimator can (frame.wgsl `estimate_rgb`); without, the
/// driver compiles that code out.
pub const INTEGRATOR_CHROMATIC: u32 = INTEGRATOR_FLAGS[5].1;

/// `vec4`s per shape record: media and lights, flags, emission, two sides.
pub const SHAPE_STRIDE: u32 = 3 + 2 * SIDE_STRIDE;
/// `vec4`s per side: (kind, α, η, flags), three colour parameters, the
/// texture's two colours and its `to_uv`.
pub const SIDE_STRIDE: u32 = 7;

/// Shape flag bits (WGSL `SHAPE_*`).
pub const SHAPE_FLAGS: [(&str, u32); 6] = [
    ("NORMALS", 1),
    ("UVS", 2),
    ("EMITS", 4),
    ("NULL", 8),
    ("TWO_SIDED", 16),
    ("PASSES", 32),
];

/// Bits of a Lerzer and Dachsbacher 2025 importance rule's `flags` (WGSL `RULE_*`): which of
/// its predicates it has (world/importance.rs `ImportanceRule`).
pub const RULE_FLAGS: [(&str, u32); 6] = [
    ("EXTINCTION", 1),
    ("SCALAR", 2),
    ("GRADIENT", 4),
    ("BOX", 8),
    ("HALF_SPACE", 16),
    ("MASK", 32),
];
/// Bits of `VisOptUniform::flags` (WGSL `VISOPT_*`) for `visopt` and
/// `ament`: optimise (else plain DVR), the gradient lobe, Ament's printed
/// form, Ament's jittered start, nearest lookups of a pre-classified
/// importance.
pub const VISOPT_FLAGS: [(&str, u32); 5] = [
    ("OPTIMISE", 1),
    ("SHADING", 2),
    ("PRINTED", 4),
    ("JITTER", 8),
    ("PRE_NEAREST", 16),
];
pub const RULE_EXTINCTION: u32 = RULE_FLAGS[0].1;
pub const RULE_SCALAR: u32 = RULE_FLAGS[1].1;
pub const RULE_GRADIENT: u32 = RULE_FLAGS[2].1;
pub const RULE_BOX: u32 = RULE_FLAGS[3].1;
pub const RULE_HALF_SPACE: u32 = RULE_FLAGS[4].1;
pub const RULE_MASK: u32 = RULE_FLAGS[5].1;
pub const VISOPT_OPTIMISE: u32 = VISOPT_FLAGS[0].1;
pub const VISOPT_SHADING: u32 = VISOPT_FLAGS[1].1;
pub const VISOPT_PRINTED: u32 = VISOPT_FLAGS[2].1;
pub const VISOPT_JITTER: u32 = VISOPT_FLAGS[3].1;
pub const VISOPT_PRE_NEAREST: u32 = VISOPT_FLAGS[4].1;

/// The `SCATTERING_*` id of visopt's `scattering` key.
pub fn scattering_id(s: Scattering) -> u32 {
    position(&Scattering::ALL.map(Scattering::name), s.name())
}

/// The `PIN_MODE_*` id of volpath's `pins` key.
pub fn pin_mode_id(m: PinMode) -> u32 {
    position(&PinMode::NAMES.map(|(n, _)| n), m.name())
}

/// Emission kinds of a medium (0: none).
pub const EMISSION_KINDS: [&str; 3] = ["none", "color", "blackbody"];

fn position(names: &[&str], name: &str) -> u32 {
    names
        .iter()
        .position(|n| *n == name)
        .expect("every variant is registered") as u32
}

/// The `EST_*` id of an estimator: its place in the estimator registry.
pub fn estimator_id(e: Estimator) -> u32 {
    position(&Estimator::names(), e.name())
}

pub fn sampler_id(s: DistanceSampler) -> u32 {
    position(&DistanceSampler::ALL.map(DistanceSampler::name), s.name())
}

pub fn strategy_id(s: Strategy) -> u32 {
    position(&Strategy::ALL.map(Strategy::name), s.name())
}

/// Light kinds on the device: the scene's, then the emitting shapes'
/// (`area` triangles, `sphere`, `disk`: scenes do not list them).
pub fn light_kinds() -> Vec<&'static str> {
    let mut k = Light::KINDS.to_vec();
    k.extend(["area", "sphere", "disk"]);
    k
}

pub fn light_id(l: &Light) -> u32 {
    position(&light_kinds(), l.kind())
}

pub fn bsdf_id(b: &Bsdf) -> u32 {
    position(&Bsdf::NAMES, b.name())
}

pub fn texture_id(t: &Texture) -> u32 {
    position(&Texture::NAMES, t.name())
}

pub fn emission_id(e: Option<&Emission>) -> u32 {
    position(
        &EMISSION_KINDS,
        match e {
            None => "none",
            Some(Emission::Color { .. }) => "color",
            Some(Emission::Blackbody { .. }) => "blackbody",
        },
    )
}

/// How the GPU evaluates a medium's velocity (`VELOCITY_*`): a grid of
/// three property records, or an affine map M·p + c inside a box (a
/// constant, and the plume's rise and swirl, which is affine in position).
pub const VELOCITY_KINDS: [&str; 3] = ["none", "grid", "affine"];

pub fn velocity_id(v: Option<&fogbank_render::world::velocity::Velocity>) -> u32 {
    use fogbank_render::world::velocity::Velocity;
    position(
        &VELOCITY_KINDS,
        match v {
            None => "none",
            Some(Velocity::Grid { .. }) => "grid",
            Some(Velocity::Constant(_) | Velocity::Plume { .. }) => "affine",
        },
    )
}

/// A WGSL-ported estimator: its `ESTIMATOR` constant and the options the
/// kernel reads from the frame (samples, fixed step or 0, flags).
pub struct GpuEstimator {
    pub id: u32,
    pub samples: u32,
    pub step: f32,
    pub flags: u32,
    /// Ratio and residual ratio tracking: the roulette threshold (0: off).
    pub roulette: f32,
}

/// The kernel's constants of estimator `e`; `None` for one without a WGSL port.
pub fn gpu_estimator(e: Estimator) -> Option<GpuEstimator> {
    let jitter = |j: Jitter| {
        if j == Jitter::Uniform {
            FLAG_UNIFORM_JITTER
        } else {
            0
        }
    };
    let id = estimator_id(e);
    Some(match e {
        Estimator::RegularTracking(RegularTracking)
        | Estimator::TrackLength(TrackLength)
        | Estimator::AnalyticTrilinear(AnalyticTrilinear) => GpuEstimator {
            id,
            samples: 0,
            step: 0.0,
            flags: 0,
            roulette: 0.0,
        },
        Estimator::RatioTracking(RatioTracking { roulette })
        | Estimator::ResidualRatioTracking(ResidualRatioTracking { roulette }) => GpuEstimator {
            id,
            samples: 0,
            step: 0.0,
            flags: 0,
            roulette,
        },
        Estimator::RayMarching(RayMarching { samples, clip }) => GpuEstimator {
            id,
            samples,
            step: 0.0,
            flags: if clip { FLAG_CLIP } else { 0 },
            roulette: 0.0,
        },
        Estimator::Jackknife(Jackknife {
            samples,
            mode,
            jitter: j,
        }) => GpuEstimator {
            id,
            samples,
            step: match mode {
                StepMode::FixedCount => 0.0,
                StepMode::FixedStep(s) => s.max(1e-6),
            },
            flags: jitter(j),
            roulette: 0.0,
        },
        Estimator::JackknifeNaive(JackknifeNaive { samples, jitter: j }) => GpuEstimator {
            id,
            samples,
            step: 0.0,
            flags: jitter(j),
            roulette: 0.0,
        },
        Estimator::JackknifeMeanImportance(JackknifeMeanImportance { samples, jitter: j }) => {
            GpuEstimator {
                id,
                samples,
                step: 0.0,
                flags: jitter(j),
                roulette: 0.0,
            }
        }
        Estimator::BiasedRayMarching(BiasedRayMarching { doubled }) => GpuEstimator {
            id,
            samples: 0,
            step: 0.0,
            flags: if doubled { FLAG_DOUBLED } else { 0 },
            roulette: 0.0,
        },
        Estimator::UnbiasedRayMarching(UnbiasedRayMarching { mult }) => GpuEstimator {
            id,
            samples: mult,
            step: 0.0,
            flags: 0,
            roulette: 0.0,
        },
        // An estimator registered without a WGSL port (a test's) renders
        // on the CPU only; today every registered one has a port.
        #[allow(unreachable_patterns)]
        _ => return None,
    })
}

/// One group of WGSL constants, `PREFIX_NAME = index` (and `PREFIX_COUNT`).
fn enumeration(out: &mut String, prefix: &str, names: &[&str]) {
    for (i, n) in names.iter().enumerate() {
        out.push_str(&format!(
            "const {prefix}_{}: u32 = {i}u;\n",
            n.to_uppercase()
        ));
    }
    out.push_str(&format!("const {prefix}_COUNT: u32 = {}u;\n", names.len()));
}

/// Set in an analytic shape's primitive index in the surface records
/// (surfaces.rs): the slot holds a sphere or disk, not a triangle.
pub const PRIMITIVE_ANALYTIC: u32 = 1 << 31;

/// Node groups the WGSL wide-BVH walk (bvh.wgsl) keeps waiting: one per
/// level at most (through an instance: the top level's, one for the
/// instance's leaf, then the group's), so surfaces.rs refuses deeper trees.
pub const BVH_STACK: u32 = 32;

/// `vec4`s per instance record in the surface data (surfaces.rs): the
/// world → group rows, the group → world rows, then the group's node and
/// slot bases, whether it mirrors, and the instance's index.
pub const INSTANCE_STRIDE: u32 = 7;

/// Samples one invocation takes in a row and merges into the pixel's
/// moments at once: the unit of the device's accumulation order, so images
/// are the same however many chunks a dispatch runs side by side.
pub const SAMPLES_PER_CHUNK: u32 = 4;

/// The WGSL prelude of every kernel: the contract's ids and flag bits.
pub fn wgsl_prelude() -> String {
    let mut s = String::from(
        "// Generated from the Rust definitions (fogbank-gpu contract.rs) when the\n\
         // shaders are assembled: ids and flag bits shared with the CPU.\n",
    );
    enumeration(&mut s, "EST", &Estimator::names());
    enumeration(
        &mut s,
        "SAMPLER",
        &DistanceSampler::ALL.map(DistanceSampler::name),
    );
    enumeration(&mut s, "STRATEGY", &Strategy::ALL.map(Strategy::name));
    enumeration(&mut s, "LIGHT", &light_kinds());
    enumeration(&mut s, "QUADRIC", &fogbank_geometry::Quadric::NAMES);
    s.push_str(&format!(
        "const PRIMITIVE_ANALYTIC: u32 = {PRIMITIVE_ANALYTIC}u;\nconst BVH_STACK: u32 = {BVH_STACK}u;\n\
         const INSTANCE_STRIDE: u32 = {INSTANCE_STRIDE}u;\n"
    ));
    enumeration(&mut s, "BSDF", &Bsdf::NAMES);
    enumeration(&mut s, "TEXTURE", &Texture::NAMES);
    enumeration(&mut s, "FILTER", &BitmapFilter::NAMES);
    enumeration(&mut s, "WRAP", &WrapMode::NAMES);
    enumeration(&mut s, "EMISSION", &EMISSION_KINDS);
    enumeration(&mut s, "VELOCITY", &VELOCITY_KINDS);
    enumeration(&mut s, "PIN_MODE", &PinMode::NAMES.map(|(n, _)| n));
    enumeration(&mut s, "MIS", &ReuseMis::ALL.map(ReuseMis::name));
    for (name, bit) in FLAGS {
        s.push_str(&format!("const FLAG_{name}: u32 = {bit}u;\n"));
    }
    enumeration(&mut s, "SCATTERING", &Scattering::ALL.map(Scattering::name));
    for (prefix, bits) in [
        ("INTEGRATOR", &INTEGRATOR_FLAGS[..]),
        ("RULE", &RULE_FLAGS[..]),
        ("VISOPT", &VISOPT_FLAGS[..]),
        ("SHAPE", &SHAPE_FLAGS[..]),
    ] {
        for (name, bit) in bits {
            s.push_str(&format!("const {prefix}_{name}: u32 = {bit}u;\n"));
        }
    }
    s.push_str(&format!(
        "const DIM_CAMERA: u32 = {}u;\nconst DIM_ESTIMATOR: u32 = {}u;\n",
        dim::CAMERA,
        dim::ESTIMATOR
    ));
    s.push_str(&format!(
        "const SHAPE_STRIDE: u32 = {}u;\nconst SIDE_STRIDE: u32 = {}u;\n",
        SHAPE_STRIDE, SIDE_STRIDE
    ));
    s.push_str(&format!(
        "const SAMPLES_PER_CHUNK: u32 = {}u;\n",
        SAMPLES_PER_CHUNK
    ));
    s
}

/// A vector and a fourth component as one WGSL `vec4<f32>`.
pub(crate) fn v4(v: glam::Vec3, w: f32) -> [f32; 4] {
    [v.x, v.y, v.z, w]
}
