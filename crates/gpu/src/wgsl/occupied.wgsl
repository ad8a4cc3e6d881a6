// fogbank_volume::occupied: the spans of a ray between super-voxels where
// the field is exactly zero, so walks skip empty space. The flags are the
// CPU's (SuperVoxelGrid::is_zero): a super-voxel is zero for nearest
// lookups when its statistics (apron included) are all zero; for trilinear
// lookups too when the statistics cover a one-voxel apron (trilinear and
// stochastic filters), else when its 26 neighbours are zero as well.

fn sv_own_zero(m: MediumGpu, c: vec3<i32>) -> bool {
    let s = supervoxel(m, c);
    return s.x == 0.0 && s.y == 0.0;
}

fn sv_zero(m: MediumGpu, c: vec3<i32>, trilinear: bool) -> bool {
    if (!sv_own_zero(m, c)) {
        return false;
    }
    if (!trilinear || m.filter_mode != 0u) {
        return true;
    }
    let hi = vec3<i32>(m.sv_dims) - vec3<i32>(1);
    for (var n = 0; n < 27; n++) {
        let o = vec3<i32>(n % 3 - 1, (n / 3) % 3 - 1, n / 9 - 1);
        if (!sv_own_zero(m, clamp(c + o, vec3<i32>(0), hi))) {
            return false;
        }
    }
    return true;
}

// The super-voxel walk of a ray (Occupied::new); a plain Dda, since naga's
// SPIR-V writer cannot pass a pointer to a struct member.
fn spans_new(m: MediumGpu, r: Ray, t0: f32, t1: f32) -> Dda {
    return dda_new(r, m.sv_size, m.sv_dims, t0, t1);
}

// Occupied::next: the next maximal span of non-zero super-voxels.
fn spans_next(s: ptr<function, Dda>, m: MediumGpu, trilinear: bool, out: ptr<function, vec2<f32>>) -> bool {
    var have = false;
    var span = vec2<f32>(0.0);
    var st: DdaStep;
    while (dda_next(s, &st)) {
        if (sv_zero(m, st.cell, trilinear)) {
            if (have) {
                *out = span;
                return true;
            }
        } else {
            if (!have) {
                span.x = st.t0;
                have = true;
            }
            span.y = st.t1;
        }
    }
    *out = span;
    return have;
}
