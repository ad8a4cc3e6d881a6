//! Hansen 2025 Fig. 4.9: memory of the half-float density texture and of the
//! pin grid for the thesis's four evaluation volumes, with P chosen by
//! fogbank's default rule (the largest P whose P³ × 64 pins of 8 bytes
//! stay within 0.1× the texture), beside the thesis's P and megabytes.
//! (`fogbank info FILE` prints the same for any volume file.)

use crate::harness::Writer;
use fogbank_render::integrators::shared::pin_params::PinGridParams;

/// (name, dims, the thesis's P, texture MB, grid MB).
pub const THESIS: [(&str, [u64; 3], u32, f64, f64); 4] = [
    ("Teapot (Boston Teapot)", [256, 256, 178], 16, 23.3, 2.1),
    ("Snow (Tooth)", [103, 94, 161], 8, 3.1, 0.26),
    ("Cloud (CSAFE Heptane)", [302, 302, 302], 22, 55.0, 5.4),
    ("Cube (Perlin noise)", [512, 512, 512], 37, 268.4, 25.9),
];

pub struct Row {
    pub name: String,
    pub dims: [u64; 3],
    pub positions: u32,
    pub texture_mb: f64,
    pub grid_mb: f64,
}

/// fogbank's default grid for a dense volume of `dims` voxels.
pub fn row(name: &str, dims: [u64; 3]) -> Row {
    let g = PinGridParams::default();
    let voxels: u64 = dims.iter().product();
    let p = g.positions_for(voxels);
    let pins = (p as u64).pow(3) * (g.phi * g.theta) as u64;
    Row {
        name: name.into(),
        dims,
        positions: p,
        texture_mb: (2 * voxels) as f64 / 1e6,
        grid_mb: (8 * pins) as f64 / 1e6,
    }
}

pub fn run(w: &mut Writer, _trials: Option<u64>) -> Result<String, String> {
    let mut csv = Vec::new();
    let mut lines = Vec::new();
    for (name, dims, p, tex, grid) in THESIS {
        let r = row(name, dims);
        lines.push(format!(
            "| {name} | {}×{}×{} | {} ({p}) | {:.1} ({tex}) | {:.2} ({grid}) |",
            dims[0], dims[1], dims[2], r.positions, r.texture_mb, r.grid_mb
        ));
        csv.push(vec![
            name.to_string(),
            format!("{}x{}x{}", dims[0], dims[1], dims[2]),
            r.positions.to_string(),
            p.to_string(),
            format!("{:.3}", r.texture_mb),
            format!("{tex}"),
            format!("{:.3}", r.grid_mb),
            format!("{grid}"),
        ]);
    }
    w.csv(
        "memory.csv",
        &[
            "volume",
            "dims",
            "positions",
            "thesis_positions",
            "texture_mb",
            "thesis_texture_mb",
            "grid_mb",
            "thesis_grid_mb",
        ],
        &csv,
    )?;
    Ok(format!(
        "Hansen 2025 Fig. 4.9: half-float texture (2 bytes a voxel) and pin grid (P³ positions × 16 φ × 4 θ directions × \
         8 bytes) with fogbank's default P (the largest within 0.1× the texture); the thesis's values in brackets.\n\n\
         | volume | voxels | P | texture MB | grid MB |\n|---|---|---|---|---|\n{}\n",
        lines.join("\n")
    ))
}
