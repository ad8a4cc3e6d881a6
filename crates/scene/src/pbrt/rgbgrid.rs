//! `rgbgrid` media (pbrt's `RGBGridMedium`): per-voxel rgb `sigma_a`,
//! `sigma_s` and optional `Le` over the box `p0`–`p1`, cell-centred as
//! `SampledGrid::Lookup` reads them (as `uniformgrid`, through
//! [`super::grids`]); the medium exists in that box. As for
//! `uniformgrid`, near the box's faces pbrt interpolates towards zero
//! outside, fogbank towards the edge voxel (within half a voxel).
//!
//! - σ_t = `scale`·(σ_a + σ_s) per voxel (a missing grid is 1 in every
//!   channel, as pbrt's `SamplePoint`): one density array when every
//!   voxel's σ_t is grey, else a 3-channel array with `density_rgb`
//!   (chromatic extinction, exact per channel).
//! - albedo σ_s/σ_t: a constant when every voxel has the same, else an
//!   `albedo_grid` array. pbrt interpolates σ_s and σ_t and divides;
//!   fogbank interpolates the albedo, which differs only inside voxels
//!   whose neighbours' albedos differ (a notice says so). Voxels with
//!   σ_t = 0 take the mean albedo (their own is never used, only blended
//!   into neighbours').
//! - `Le` × `Lescale` as a 3-channel emission grid; fogbank emits σ_a·L_e
//!   as pbrt does. `Le` needs `sigma_a` (pbrt's rule).

use super::grids::{grid_box, register};
use super::interpret::Placed;
use super::tables::{array_field, set_array_density};
use super::warnings::Warnings;
use toml::{Table, Value};

/// The rgb array `name` as triples, checked non-negative.
fn triples(m: &Placed, name: &str) -> Result<Option<Vec<[f64; 3]>>, String> {
    let Some(v) = m.entity.params.nums("rgb", name) else {
        return Ok(None);
    };
    if v.len() % 3 != 0 {
        return Err(format!(
            "\"rgb {name}\" has {} values, not a multiple of 3",
            v.len()
        ));
    }
    if let Some(x) = v.iter().find(|x| !(**x >= 0.0 && x.is_finite())) {
        return Err(format!(
            "\"rgb {name}\": {x} is not a finite non-negative value"
        ));
    }
    Ok(Some(v.chunks(3).map(|c| [c[0], c[1], c[2]]).collect()))
}

fn rgb_value(c: [f64; 3]) -> Value {
    Value::Array(c.iter().map(|&x| Value::Float(x)).collect())
}

/// The `rgbgrid` medium `m` into the medium table `t`.
pub fn rgb_grid(m: &Placed, t: &mut Table, warnings: &mut Warnings) -> Result<(), String> {
    let ps = &m.entity.params;
    let sa = triples(m, "sigma_a")?;
    let ss = triples(m, "sigma_s")?;
    let le = triples(m, "Le")?;
    let count = match (&sa, &ss) {
        (None, None) => return Err("needs \"rgb sigma_a\" and/or \"rgb sigma_s\"".into()),
        (Some(a), Some(s)) if a.len() != s.len() => {
            return Err(format!(
                "{} sigma_a values but {} sigma_s values",
                a.len(),
                s.len()
            ))
        }
        (Some(a), _) => a.len(),
        (None, Some(s)) => s.len(),
    };
    if le.is_some() && sa.is_none() {
        return Err("\"Le\" needs \"sigma_a\"".into());
    }
    if let Some(l) = le.as_ref().filter(|l| l.len() != count) {
        return Err(format!("{} Le values for {count} voxels", l.len()));
    }
    let (n, p0, p1) = grid_box(ps)?;
    if n.iter().map(|&v| v as usize).product::<usize>() != count {
        return Err(format!("{count} values for {}×{}×{}", n[0], n[1], n[2]));
    }
    let at = |g: &Option<Vec<[f64; 3]>>, i: usize| g.as_ref().map_or([1.0; 3], |g| g[i]);
    let st: Vec<[f64; 3]> = (0..count)
        .map(|i| std::array::from_fn(|c| at(&sa, i)[c] + at(&ss, i)[c]))
        .collect();
    let source = format!("{} rgbgrid", m.entity.loc);
    let grey = st.iter().all(|s| s[0] == s[1] && s[1] == s[2]);
    let density = if grey {
        let v: Vec<f64> = st.iter().map(|s| s[0]).collect();
        register(n, 1, &v, p0, p1, &source)?
    } else {
        t.insert("density_rgb".into(), true.into());
        register(n, 3, &st.concat(), p0, p1, &format!("{source} σ_t"))?
    };
    let albedo: Vec<Option<[f64; 3]>> = (0..count)
        .map(|i| {
            (st[i].iter().all(|&x| x > 0.0))
                .then(|| std::array::from_fn(|c| at(&ss, i)[c] / st[i][c]))
        })
        .collect();
    albedo_table(
        &albedo,
        (n, p0, p1),
        &source,
        t,
        warnings,
        &m.entity.loc.to_string(),
    )?;
    let scale = ps.float("Lescale", 1.0).map_err(|e| e.0)?;
    if let Some(le) = le.filter(|l| l.iter().flatten().any(|&x| x > 0.0)) {
        let grid = register(n, 3, &le.concat(), p0, p1, &format!("{source} Le"))?;
        t.insert("emission".into(), emission(grid, scale));
    }
    t.insert(
        "sigma_t_scale".into(),
        ps.float("scale", 1.0).map_err(|e| e.0)?.into(),
    );
    set_array_density(t, density, m.ctm);
    Ok(())
}

/// The emission table of the `Le` grid `grid` times `scale`.
fn emission(grid: String, scale: f64) -> Value {
    let mut em = Table::new();
    em.insert("scale".into(), scale.into());
    em.insert("grid".into(), array_field(grid));
    Value::Table(em)
}

/// A constant `albedo`, or `albedo_grid` when the voxels' albedos differ.
fn albedo_table(
    albedo: &[Option<[f64; 3]>],
    (n, p0, p1): ([u32; 3], glam::DVec3, glam::DVec3),
    source: &str,
    t: &mut Table,
    warnings: &mut Warnings,
    loc: &str,
) -> Result<(), String> {
    let defined: Vec<[f64; 3]> = albedo.iter().flatten().copied().collect();
    let first = defined.first().copied().unwrap_or([0.0; 3]);
    if defined.iter().all(|a| *a == first) {
        t.insert("albedo".into(), rgb_value(first));
        return Ok(());
    }
    let k = defined.len() as f64;
    let mean: [f64; 3] = std::array::from_fn(|c| defined.iter().map(|a| a[c]).sum::<f64>() / k);
    let v: Vec<f64> = albedo.iter().flat_map(|a| a.unwrap_or(mean)).collect();
    t.insert("albedo".into(), rgb_value([1.0; 3]));
    t.insert(
        "albedo_grid".into(),
        array_field(register(n, 3, &v, p0, p1, &format!("{source} albedo"))?),
    );
    warnings.warn(format!(
        "{loc}: rgbgrid: the albedo σ_s/σ_t is interpolated between voxels (pbrt interpolates σ_s and σ_t, then divides): the same at voxel centres"
    ));
    Ok(())
}
