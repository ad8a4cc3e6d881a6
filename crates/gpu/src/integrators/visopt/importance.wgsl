// world/importance.rs, SceneMedium::sigma_t_smooth / gradient_sigma_t and
// world/shading.rs on the device: Lerzer and Dachsbacher 2025's importance rules (§4.2) and
// the smooth classified extinction that they and the gradient lobe (§3)
// read. One medium (record 0), as the CPU integrators require.

// Medium::sigma_t_smooth at world point p: the trilinear interpolant,
// classified after interpolation; 0 outside the box (a zero super-voxel
// reads 0 here too: its apron is zero, so the lookup is skipped only on
// the CPU).
fn sigma_smooth(m: MediumGpu, p: vec3<f32>) -> f32 {
    let o = vec4<f32>(p, 1.0);
    let q = vec3<f32>(dot(m.w2i0, o), dot(m.w2i1, o), dot(m.w2i2, o));
    return sigma_smooth_index(m, q);
}

fn sigma_smooth_index(m: MediumGpu, q: vec3<f32>) -> f32 {
    if (any(q < vec3<f32>(0.0)) || any(q > vec3<f32>(m.dims))) {
        return 0.0;
    }
    return m.scale * classify(m, trilinear(m, q));
}

// SceneMedium::gradient_sigma_t: central differences of one voxel in index
// space, into world units by the transposed linear part of world → index.
fn gradient_sigma_t(m: MediumGpu, p: vec3<f32>) -> vec3<f32> {
    let o = vec4<f32>(p, 1.0);
    let q = vec3<f32>(dot(m.w2i0, o), dot(m.w2i1, o), dot(m.w2i2, o));
    // One lookup in a loop rather than six inlined copies (compile time).
    var g = vec3<f32>(0.0);
    for (var i = 0u; i < 6u; i++) {
        var e = vec3<f32>(0.0);
        e[i / 2u] = 1.0;
        let sign = 1.0 - 2.0 * f32(i % 2u);
        g[i / 2u] += 0.5 * sign * sigma_smooth_index(m, q + sign * e);
    }
    return m.w2i0.xyz * g.x + m.w2i1.xyz * g.y + m.w2i2.xyz * g.z;
}

// Field::eval_nearest (one channel): the voxel holding p, 0 outside.
fn field_nearest(first: u32, p: vec3<f32>) -> f32 {
    let m = media[first];
    let o = vec4<f32>(p, 1.0);
    let q = vec3<f32>(dot(m.w2i0, o), dot(m.w2i1, o), dot(m.w2i2, o));
    if (any(q < vec3<f32>(0.0)) || any(q > vec3<f32>(m.dims))) {
        return 0.0;
    }
    return nearest(m, q);
}

fn in_range(range: vec2<f32>, v: f32) -> bool {
    return v >= range.x && v < range.y;
}

// ImportanceRule::spatial: the predicates on the position alone.
fn rule_spatial(r: ImportanceRuleGpu, p: vec3<f32>) -> bool {
    if ((r.flags & RULE_BOX) != 0u && !(all(p >= r.box_lo.xyz) && all(p <= r.box_hi.xyz))) {
        return false;
    }
    if ((r.flags & RULE_HALF_SPACE) != 0u && dot(r.half_space.xyz, p) < r.half_space.w) {
        return false;
    }
    if ((r.flags & RULE_MASK) != 0u && field_eval(r.mask, 1u, p).x < r.mask_threshold) {
        return false;
    }
    return true;
}

// The scalar and ‖∇σ_t‖ at a point, read when a rule first needs them.
struct ImportanceInputs {
    scalar: f32,
    gradient: f32,
    // Bit 0: scalar read; bit 1: gradient read.
    have: u32,
}

// ImportanceRule: whether every predicate of rule r holds at p.
fn rule_holds(r: ImportanceRuleGpu, p: vec3<f32>, sigma_t: f32, x: ptr<function, ImportanceInputs>) -> bool {
    if (!rule_spatial(r, p)) {
        return false;
    }
    if ((r.flags & RULE_EXTINCTION) != 0u && !in_range(r.ranges.xy, sigma_t)) {
        return false;
    }
    if ((r.flags & RULE_SCALAR) != 0u) {
        if (((*x).have & 1u) == 0u) {
            (*x).scalar = scalar_at(media[0], p);
            (*x).have |= 1u;
        }
        if (!in_range(r.ranges.zw, (*x).scalar)) {
            return false;
        }
    }
    if ((r.flags & RULE_GRADIENT) != 0u) {
        if (((*x).have & 2u) == 0u) {
            (*x).gradient = length(gradient_sigma_t(media[0], p));
            (*x).have |= 2u;
        }
        if (!in_range(r.gradient.xy, (*x).gradient)) {
            return false;
        }
    }
    return true;
}

// visopt::optimised::importance_at / Importance::eval: the value of the
// first rule that holds at p (σ_t there known), else 0; a pre-classified
// importance is looked up instead.
fn importance_at(p: vec3<f32>, sigma_t: f32) -> f32 {
    if (vo.pre_field != 0u) {
        var v: f32;
        if (vo_flag(VISOPT_PRE_NEAREST)) {
            v = field_nearest(vo.pre_field - 1u, p);
        } else {
            v = field_eval(vo.pre_field - 1u, 1u, p).x;
        }
        return clamp(v, 0.0, 1.0);
    }
    var inputs = ImportanceInputs(0.0, 0.0, 0u);
    var value = 0.0;
    for (var i = 0u; i < vo.rule_count; i++) {
        let r = rule_at(i);
        if (rule_holds(r, p, sigma_t, &inputs)) {
            value = r.value;
            break;
        }
    }
    return value;
}

// shading::gradient_lobe for a ray along omega toward the light omega_l.
fn gradient_lobe(grad: vec3<f32>, omega: vec3<f32>, omega_l: vec3<f32>, n: f32) -> f32 {
    let g = length(grad);
    if (!(g > 0.0 && g < F32_INF)) {
        return 0.0;
    }
    var normal = grad / g;
    if (dot(normal, -omega) < 0.0) {
        normal = -normal;
    }
    var h = omega_l - omega;
    let hl = length(h);
    if (hl > 0.0) {
        h /= hl;
    }
    let n_l = dot(normal, omega_l);
    if (n_l <= 0.0) {
        return 0.0;
    }
    return g * pow(max(dot(h, normal), 0.0), n) * n_l;
}

// shading::dvr_phase: HG, plus with VISOPT_SHADING the lobe of ∇μ_t in
// [−1, 1]³ units.
fn dvr_phase(p: vec3<f32>, d: vec3<f32>, wi: vec3<f32>) -> f32 {
    let hg = hg_eval(shading[0].w, dot(d, wi));
    if (!vo_flag(VISOPT_SHADING)) {
        return hg;
    }
    let grad = gradient_sigma_t(media[0], p) / (vo.unit * vo.unit);
    return hg + gradient_lobe(grad, d, wi, vo.n);
}

// segments::mu_factor, Lerzer and Dachsbacher 2025 Eq. 8: μ'/μ = p / (p + (1 − g)^{2λ} h).
fn mu_factor(g: f32, h: f32) -> f32 {
    var w = 1.0;
    if (vo.lambda != 0.0) {
        let base = max(1.0 - g, 0.0);
        w = select(0.0, pow(base, 2.0 * vo.lambda), base > 0.0);
    }
    return vo.p / (vo.p + w * h);
}
