//! Measurements of fogbank's own machinery that reproduce no paper's
//! figure: kept apart from the paper folders so that those hold only
//! reproductions.
//!
//! - `bvh_perf`: build time and closest-hit / any-hit rays per second of
//!   the surfaces' BVH on a generated mesh of over 10⁶ triangles
//!   (`bvh-perf`);
//! - `light_bvh`: the light BVH against picking lights by power, at equal
//!   spp and equal time, in scenes of many small emitters (`light-bvh`).

pub mod bvh_instances;
pub mod bvh_perf;
pub mod light_bvh;
