//! A medium's extinction: density data, scale, filter, placement in the world
//! and the super-voxel statistics estimators need. Albedo, phase function and
//! emission belong to the scene layer above.

use crate::access::{Filter, GridView};
use crate::analytic::{AnalyticField, AnalyticView};
use crate::grid::{BrickGrid, Precision, Voxel};
use crate::supervoxel::SuperVoxelGrid;
use fogbank_math::{Aabb, DAffine3, DVec3, PiecewiseLinear, Ray, Vec3};
use half::f16;

/// Density storage; the variant is matched once per ray, never per lookup.
#[derive(Clone, Debug)]
pub enum DensityData {
    F16(BrickGrid<f16>),
    F32(BrickGrid<f32>),
    Analytic(AnalyticField),
}

impl DensityData {
    pub fn dims(&self) -> [u32; 3] {
        match self {
            DensityData::F16(g) => g.dims(),
            DensityData::F32(g) => g.dims(),
            DensityData::Analytic(a) => [a.n; 3],
        }
    }

    pub fn memory_bytes(&self) -> usize {
        match self {
            DensityData::F16(g) => g.memory_bytes(),
            DensityData::F32(g) => g.memory_bytes(),
            DensityData::Analytic(_) => 0,
        }
    }

    pub fn precision_name(&self) -> &'static str {
        match self {
            DensityData::F16(_) => "f16",
            DensityData::F32(_) => "f32",
            DensityData::Analytic(_) => "analytic",
        }
    }

    /// Whether every stored voxel is finite: a value beyond f16's range
    /// (±65504) becomes infinite when stored as f16, so an `F16` grid that
    /// is not finite stands for a file it could not hold.
    pub fn stored_values_are_finite(&self) -> bool {
        match self {
            DensityData::F16(g) => g.buffers().2.iter().all(|v| v.is_finite()),
            DensityData::F32(g) => g.buffers().2.iter().all(|v| v.is_finite()),
            DensityData::Analytic(_) => true,
        }
    }

    /// (min, max) of the stored values (of an analytic field: its
    /// super-voxel bounds at 16³).
    pub fn value_range(&self) -> (f32, f32) {
        let fold = |it: &mut dyn Iterator<Item = f32>| {
            it.fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), v| {
                (lo.min(v), hi.max(v))
            })
        };
        let all = |d: [u32; 3]| {
            (0..d[2])
                .flat_map(move |k| (0..d[1]).flat_map(move |j| (0..d[0]).map(move |i| (i, j, k))))
        };
        let (lo, hi) = match self {
            DensityData::F16(g) => {
                fold(&mut all(g.dims()).map(|(i, j, k)| g.fetch(i as i32, j as i32, k as i32)))
            }
            DensityData::F32(g) => {
                fold(&mut all(g.dims()).map(|(i, j, k)| g.fetch(i as i32, j as i32, k as i32)))
            }
            DensityData::Analytic(a) => {
                let sv = a.supervoxels(16);
                fold(&mut sv.cells.iter().flat_map(|c| [c.min, c.max]))
            }
        };
        if lo <= hi {
            (lo, hi)
        } else {
            (0.0, 0.0)
        }
    }

    /// Builds from an f32 grid in the requested precision.
    pub fn from_f32(grid: BrickGrid<f32>, precision: Precision) -> Self {
        match precision {
            Precision::F32 => DensityData::F32(grid),
            Precision::F16 => DensityData::F16(convert(&grid)),
        }
    }
}

/// Super-voxel statistics of a voxel grid (empty space skipped).
fn grid_supervoxels<T: Voxel>(
    g: &BrickGrid<T>,
    supervoxel: u32,
    apron: u32,
    tf: Option<&PiecewiseLinear<1>>,
) -> SuperVoxelGrid {
    SuperVoxelGrid::build_sparse(
        g.dims(),
        supervoxel,
        apron,
        |i, j, k| g.fetch(i, j, k),
        |lo, hi| g.uniform_in(lo, hi),
        tf,
    )
}

fn convert(g: &BrickGrid<f32>) -> BrickGrid<f16> {
    g.to_voxel()
}

#[derive(Clone, Debug)]
pub struct Medium {
    pub data: DensityData,
    pub sigma_t_scale: f32,
    pub filter: Filter,
    pub index_to_world: DAffine3,
    pub world_to_index: DAffine3,
    /// Statistics of σ_t (already multiplied by `sigma_t_scale`).
    pub supervoxels: SuperVoxelGrid,
    /// Post-interpolative classification: σ_t = scale · α(s), with s the
    /// filtered voxel value (a transfer function's opacity). `None`:
    /// σ_t = scale · s.
    pub opacity: Option<PiecewiseLinear<1>>,
}

/// A view of the medium for the estimators, one per storage type.
pub enum MediumView<'a> {
    F16(GridView<'a, f16>),
    F32(GridView<'a, f32>),
    Analytic(AnalyticView<'a>),
}

impl Medium {
    pub fn new(
        data: DensityData,
        sigma_t_scale: f32,
        filter: Filter,
        index_to_world: DAffine3,
        supervoxel: u32,
    ) -> Self {
        Self::classified(
            data,
            None,
            sigma_t_scale,
            filter,
            index_to_world,
            supervoxel,
        )
    }

    /// A medium whose extinction is `sigma_t_scale · opacity(s)` of the
    /// filtered voxel value s (see [`Medium::opacity`]); analytic fields are
    /// never classified (`opacity` is ignored for them).
    pub fn classified(
        data: DensityData,
        opacity: Option<PiecewiseLinear<1>>,
        sigma_t_scale: f32,
        filter: Filter,
        index_to_world: DAffine3,
        supervoxel: u32,
    ) -> Self {
        let apron = filter.apron();
        let tf = opacity.as_ref();
        let supervoxels = match &data {
            DensityData::F16(g) => grid_supervoxels(g, supervoxel, apron, tf),
            DensityData::F32(g) => grid_supervoxels(g, supervoxel, apron, tf),
            DensityData::Analytic(a) => a.supervoxels(supervoxel),
        }
        .scaled(sigma_t_scale);
        let opacity = match data {
            DensityData::Analytic(_) => None,
            _ => opacity,
        };
        Medium {
            data,
            sigma_t_scale,
            filter,
            index_to_world,
            world_to_index: index_to_world.inverse(),
            supervoxels,
            opacity,
        }
    }

    pub fn dims(&self) -> [u32; 3] {
        self.data.dims()
    }

    /// Whether index point `q` lies in `[0, dims]`.
    #[inline]
    fn contains_index(&self, q: Vec3) -> bool {
        let d = self.dims();
        q.cmpge(Vec3::ZERO).all()
            && q.cmple(Vec3::new(d[0] as f32, d[1] as f32, d[2] as f32))
                .all()
    }

    /// The stored value (before scale and classification), trilinearly
    /// interpolated at index point `q`; 0 outside `[0, dims]`.
    #[inline]
    pub fn scalar_trilinear(&self, q: Vec3) -> f32 {
        if !self.contains_index(q) {
            return 0.0;
        }
        match &self.data {
            DensityData::F16(g) => g.trilinear(q),
            DensityData::F32(g) => g.trilinear(q),
            DensityData::Analytic(a) => a.density(q / a.n as f32),
        }
    }

    /// σ_t of the trilinear interpolant at index point `q`, classified
    /// after interpolation (the smooth field gradients and importance
    /// criteria read); 0 outside `[0, dims]`, and without a lookup in
    /// super-voxels where the field is zero.
    #[inline]
    pub fn sigma_t_smooth(&self, q: Vec3) -> f32 {
        if !self.contains_index(q) {
            return 0.0;
        }
        let sv = &self.supervoxels;
        let c = (q / sv.size as f32)
            .floor()
            .as_ivec3()
            .min(glam::IVec3::from(sv.dims.map(|v| v as i32 - 1)));
        if sv.is_zero(c.into(), crate::supervoxel::ZERO_TRILINEAR) {
            return 0.0;
        }
        let s = self.scalar_trilinear(q);
        self.sigma_t_scale * self.opacity.as_ref().map_or(s, |o| o.eval(s)[0])
    }

    pub fn index_bounds(&self) -> Aabb {
        let d = self.dims();
        Aabb::new(Vec3::ZERO, Vec3::new(d[0] as f32, d[1] as f32, d[2] as f32))
    }

    /// World-space bounding box of the index box's eight corners.
    pub fn world_bounds(&self) -> Aabb {
        let d = self.dims();
        let mut lo = DVec3::splat(f64::INFINITY);
        let mut hi = DVec3::splat(f64::NEG_INFINITY);
        for c in 0..8 {
            let p = DVec3::new(
                if c & 1 != 0 { d[0] as f64 } else { 0.0 },
                if c & 2 != 0 { d[1] as f64 } else { 0.0 },
                if c & 4 != 0 { d[2] as f64 } else { 0.0 },
            );
            let w = self.index_to_world.transform_point3(p);
            lo = lo.min(w);
            hi = hi.max(w);
        }
        Aabb::new(lo.as_vec3(), hi.as_vec3())
    }

    /// The world ray in index space, and its parameter range inside the
    /// medium's box (`None` if it misses).
    pub fn to_index(&self, world: &Ray, t_min: f32, t_max: f32) -> Option<(Ray, f32, f32)> {
        let r = world.transformed(&self.world_to_index);
        let (t0, t1) = self.index_bounds().intersect(&r, t_min, t_max)?;
        (t1 > t0).then_some((r, t0, t1))
    }

    pub fn view(&self) -> MediumView<'_> {
        let (filter, scale, sv) = (self.filter, self.sigma_t_scale, &self.supervoxels);
        let opacity = self.opacity.as_ref();
        match &self.data {
            DensityData::F16(grid) => MediumView::F16(GridView {
                grid,
                filter,
                scale,
                supervoxels: sv,
                opacity,
            }),
            DensityData::F32(grid) => MediumView::F32(GridView {
                grid,
                filter,
                scale,
                supervoxels: sv,
                opacity,
            }),
            DensityData::Analytic(field) => MediumView::Analytic(AnalyticView {
                field,
                scale,
                supervoxels: sv,
            }),
        }
    }

    pub fn memory_bytes(&self) -> usize {
        self.data.memory_bytes() + self.supervoxels.memory_bytes()
    }
}

/// Index `[0, dims]` ↦ the box `[lo, hi]` (a `.vol` file's placement).
pub fn box_transform(dims: [u32; 3], lo: [f64; 3], hi: [f64; 3]) -> DAffine3 {
    let (lo, hi) = (DVec3::from(lo), DVec3::from(hi));
    let res = DVec3::from(dims.map(f64::from));
    DAffine3::from_scale_rotation_translation((hi - lo) / res, glam::DQuat::IDENTITY, lo)
}

/// Placement that maps the index box `[0, dims]` into the world box
/// `[-½, ½]` along the longest axis, centred at the origin, keeping aspect.
pub fn unit_box_transform(dims: [u32; 3]) -> DAffine3 {
    let m = dims.iter().copied().max().unwrap_or(1).max(1) as f64;
    let d = DVec3::new(dims[0] as f64, dims[1] as f64, dims[2] as f64);
    DAffine3::from_scale_rotation_translation(
        DVec3::splat(1.0 / m),
        glam::DQuat::IDENTITY,
        -0.5 * d / m,
    )
}
