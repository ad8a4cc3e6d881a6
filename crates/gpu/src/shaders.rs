//! WGSL sources, one concept per file, concatenated per kernel (WGSL has no
//! includes). Order matters only for readability: WGSL resolves names
//! module-wide.

pub const FLOAT: &str = include_str!("wgsl/float.wgsl");
pub const RNG: &str = include_str!("wgsl/rng.wgsl");
pub const MEDIUM: &str = include_str!("wgsl/medium.wgsl");
pub const DDA: &str = include_str!("wgsl/dda.wgsl");
pub const OCCUPIED: &str = include_str!("wgsl/occupied.wgsl");
pub const REGULAR_TRACKING: &str = include_str!("wgsl/regular_tracking.wgsl");
pub const NULL_COLLISIONS: &str = include_str!("wgsl/null_collisions.wgsl");
pub const TRACK_LENGTH: &str = include_str!("wgsl/track_length.wgsl");
pub const RATIO_TRACKING: &str = include_str!("wgsl/ratio_tracking.wgsl");
pub const RESIDUAL_RATIO_TRACKING: &str = include_str!("wgsl/residual_ratio_tracking.wgsl");
pub const ANALYTIC_TRILINEAR: &str = include_str!("wgsl/analytic_trilinear.wgsl");
pub const DISTANCE_TRILINEAR: &str = include_str!("wgsl/distance_trilinear.wgsl");
pub const OPTICAL_DEPTH: &str = include_str!("wgsl/optical_depth.wgsl");
pub const JACKKNIFE: &str = include_str!("wgsl/jackknife.wgsl");
pub const RAY_MARCHING: &str = include_str!("wgsl/ray_marching.wgsl");
pub const KETTUNEN: &str = include_str!("wgsl/kettunen.wgsl");
pub const RNG_STREAMS_KERNEL: &str = include_str!("wgsl/rng_streams_kernel.wgsl");
pub const FRAME: &str = include_str!("wgsl/frame.wgsl");
pub const DISTANCE: &str = include_str!("wgsl/distance.wgsl");
pub const MIS: &str = include_str!("wgsl/mis.wgsl");
pub const PHASE: &str = include_str!("wgsl/phase.wgsl");
pub const LIGHTS: &str = include_str!("wgsl/lights.wgsl");
pub const SHAPE_LIGHTS: &str = include_str!("wgsl/shape_lights.wgsl");
pub const PROPERTIES: &str = include_str!("wgsl/properties.wgsl");
pub const LIGHT_BVH: &str = include_str!("wgsl/light_bvh.wgsl");
pub const SCATTER_KERNEL: &str = include_str!("wgsl/scatter_kernel.wgsl");
pub const RAY_MARCHING_STEP: &str = include_str!("wgsl/ray_marching_step.wgsl");
pub const PINS: &str = include_str!("wgsl/pins.wgsl");
pub const PIN_GRID: &str = include_str!("wgsl/pin_grid.wgsl");
pub const TRACKING: &str = include_str!("wgsl/tracking.wgsl");
pub const PIN_GATHER_KERNEL: &str = include_str!("wgsl/pin_gather_kernel.wgsl");
pub const PIN_STREAM_KERNEL: &str = include_str!("wgsl/pin_stream_kernel.wgsl");
pub const CHORD_QUERIES_KERNEL: &str = include_str!("wgsl/chord_queries_kernel.wgsl");
/// Surfaces: watertight triangles and BVH traversal.
pub const BVH: &str = include_str!("wgsl/bvh.wgsl");
/// Surfaces: analytic spheres and disks.
pub const ANALYTIC_SHAPES: &str = include_str!("wgsl/analytic_shapes.wgsl");
pub const BVH_QUERIES_KERNEL: &str = include_str!("wgsl/bvh_queries_kernel.wgsl");
pub const LIGHT_PICKS_KERNEL: &str = include_str!("wgsl/light_picks_kernel.wgsl");
pub const MICROFACET: &str = include_str!("wgsl/surfaces/microfacet.wgsl");
pub const BSDF: &str = include_str!("wgsl/surfaces/bsdf.wgsl");
pub const BITMAP: &str = include_str!("wgsl/surfaces/bitmap.wgsl");
pub const SURFACES: &str = include_str!("wgsl/surfaces/surfaces.wgsl");
pub const SURFACE_DATA: &str = include_str!("wgsl/surfaces/surface_data.wgsl");
pub const OCCLUDERS: &str = include_str!("wgsl/occluders.wgsl");
pub const NEXT_EVENT: &str = include_str!("wgsl/surfaces/next_event.wgsl");
pub const ACCUMULATE: &str = include_str!("wgsl/accumulate.wgsl");

/// Every estimator's source, after the generated contract constants
/// ([`crate::contract::wgsl_prelude`]) and the shared media code.
pub fn estimators() -> String {
    [
        &crate::contract::wgsl_prelude(),
        FLOAT,
        RNG,
        MEDIUM,
        DDA,
        OCCUPIED,
        REGULAR_TRACKING,
        NULL_COLLISIONS,
        DISTANCE,
        TRACK_LENGTH,
        RATIO_TRACKING,
        RESIDUAL_RATIO_TRACKING,
        ANALYTIC_TRILINEAR,
        OPTICAL_DEPTH,
        JACKKNIFE,
        RAY_MARCHING,
        KETTUNEN,
    ]
    .join("\n")
}

/// A kernel over the frame alone (no scattering, no lights): the
/// estimators, the frame, `kernel`'s own source, the accumulation.
pub(crate) fn per_sample_kernel(kernel: &str) -> String {
    [&estimators(), FRAME, kernel, ACCUMULATE].join("\n")
}

/// A scattering integrator's kernel: the estimators, the frame, MIS, phase,
/// lights and medium properties, then `kernel`'s own source.
pub(crate) fn scattering_kernel(kernel: &str) -> String {
    [
        &estimators(),
        FRAME,
        MIS,
        PHASE,
        LIGHTS,
        SHAPE_LIGHTS,
        PROPERTIES,
        LIGHT_BVH,
        kernel,
        ACCUMULATE,
    ]
    .join("\n")
}

/// Shapes with their BSDFs: the BVH, the analytic shapes, the microfacet
/// and layered BSDFs, the per-shape data and the textures (bitmaps).
pub(crate) fn surfaces() -> String {
    [
        BVH,
        ANALYTIC_SHAPES,
        MICROFACET,
        BSDF,
        SURFACE_DATA,
        SURFACES,
        BITMAP,
    ]
    .join("\n")
}

/// `direct` and `volpath`: with Hansen 2025's ray marching and pins, chosen
/// per ray (tracking.wgsl), and surfaces (compiled out without shapes).
pub fn scatter_kernel() -> String {
    scattering_kernel(
        &[
            RAY_MARCHING_STEP,
            PINS,
            PIN_GRID,
            TRACKING,
            &surfaces(),
            NEXT_EVENT,
            SCATTER_KERNEL,
        ]
        .join("\n"),
    )
}

/// Gather population of a pin grid (Hansen 2025 §3.7).
pub fn pin_gather_kernel() -> String {
    [&estimators(), PINS, PIN_GRID, PIN_GATHER_KERNEL].join("\n")
}

/// The pin stream of a pin grid before a pass (Hansen 2025 §3.7).
pub fn pin_stream_kernel() -> String {
    [&estimators(), PINS, PIN_GRID, PIN_STREAM_KERNEL].join("\n")
}

/// A kernel of an integrator that sees shapes as opaque occluders only
/// (occluders.wgsl, compiled out without shapes).
pub(crate) fn occluding_kernel(kernel: &str) -> String {
    scattering_kernel(&[BVH, ANALYTIC_SHAPES, SURFACE_DATA, OCCLUDERS, kernel].join("\n"))
}

/// (span, [(member, offset)]) of WGSL struct `name` in `source`.
#[cfg(test)]
pub(crate) fn wgsl_struct(source: &str, name: &str) -> (u32, Vec<(String, u32)>) {
    let module = naga::front::wgsl::parse_str(source).expect("kernel parses");
    for (_, ty) in module.types.iter() {
        if ty.name.as_deref() == Some(name) {
            if let naga::TypeInner::Struct { members, span } = &ty.inner {
                let m = members
                    .iter()
                    .map(|m| (m.name.clone().unwrap_or_default(), m.offset))
                    .collect();
                return (*span, m);
            }
        }
    }
    panic!("no struct {name} in the kernel");
}

#[cfg(test)]
pub(crate) fn check_layout(source: &str, name: &str, size: usize, expected: &[(&str, usize)]) {
    let (span, members) = wgsl_struct(source, name);
    assert_eq!(span as usize, size, "{name}: WGSL size vs Rust size_of");
    let got: Vec<(&str, usize)> = members
        .iter()
        .map(|(n, o)| (n.as_str(), *o as usize))
        .collect();
    assert_eq!(got, expected, "{name}: WGSL members and offsets vs Rust");
}
