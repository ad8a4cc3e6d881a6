// Fresnel terms, Snell refraction and the microfacet distributions,
// mirroring render/src/world/bsdf/fresnel.rs and microfacet.rs: `eta` is
// the IOR of the side the normal points away from over the side it points
// into; directions are in the local frame, z along the normal.

// fresnel::dielectric: unpolarised reflectance at incident cosine cos_i
// (negative: from inside); total internal reflection gives 1.
fn fresnel_dielectric(cos_in: f32, eta_in: f32) -> f32 {
    var cos_i = clamp(cos_in, -1.0, 1.0);
    var eta = eta_in;
    if (cos_i < 0.0) {
        eta = 1.0 / eta;
        cos_i = -cos_i;
    }
    let sin2_t = (1.0 - cos_i * cos_i) / (eta * eta);
    if (sin2_t >= 1.0) {
        return 1.0;
    }
    let cos_t = sqrt(max(1.0 - sin2_t, 0.0));
    let r_parl = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    let r_perp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    return 0.5 * (r_parl * r_parl + r_perp * r_perp);
}

// Complex numbers as vec2 (re, im).
fn c_mul(a: vec2<f32>, b: vec2<f32>) -> vec2<f32> {
    return vec2<f32>(a.x * b.x - a.y * b.y, a.x * b.y + a.y * b.x);
}

fn c_div(a: vec2<f32>, b: vec2<f32>) -> vec2<f32> {
    let d = dot(b, b);
    return vec2<f32>((a.x * b.x + a.y * b.y) / d, (a.y * b.x - a.x * b.y) / d);
}

// Principal square root.
fn c_sqrt(z: vec2<f32>) -> vec2<f32> {
    let n = length(z);
    if (n == 0.0) {
        return vec2<f32>(0.0);
    }
    let t1 = sqrt(0.5 * (n + abs(z.x)));
    let t2 = 0.5 * z.y / t1;
    if (z.x >= 0.0) {
        return vec2<f32>(t1, t2);
    }
    return vec2<f32>(abs(t2), select(t1, -t1, z.y < 0.0));
}

// fresnel::conductor1: reflectance of complex IOR eta + i k (pbrt-v4's FrComplex).
fn fresnel_conductor1(cos_in: f32, eta: f32, k: f32) -> f32 {
    let cos_i = clamp(cos_in, 0.0, 1.0);
    let e = vec2<f32>(eta, k);
    let ci = vec2<f32>(cos_i, 0.0);
    let sin2_t = c_div(vec2<f32>(1.0 - cos_i * cos_i, 0.0), c_mul(e, e));
    let cos_t = c_sqrt(vec2<f32>(1.0, 0.0) - sin2_t);
    let ec = c_mul(e, ci);
    let r_parl = c_div(ec - cos_t, ec + cos_t);
    let et = c_mul(e, cos_t);
    let r_perp = c_div(ci - et, ci + et);
    return 0.5 * (dot(r_parl, r_parl) + dot(r_perp, r_perp));
}

fn fresnel_conductor(cos_i: f32, eta: vec3<f32>, k: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(fresnel_conductor1(cos_i, eta.x, k.x), fresnel_conductor1(cos_i, eta.y, k.y),
                     fresnel_conductor1(cos_i, eta.z, k.z));
}

struct Refraction {
    wt: vec3<f32>,
    // The relative IOR crossed (η, or 1/η from the inside).
    etap: f32,
    valid: bool,
}

// fresnel::refract: invalid under total internal reflection.
fn refract_dir(wi: vec3<f32>, n_in: vec3<f32>, eta_in: f32) -> Refraction {
    var n = n_in;
    var eta = eta_in;
    var cos_i = dot(n, wi);
    if (cos_i < 0.0) {
        eta = 1.0 / eta;
        cos_i = -cos_i;
        n = -n;
    }
    let sin2_i = max(1.0 - cos_i * cos_i, 0.0);
    let sin2_t = sin2_i / (eta * eta);
    if (sin2_t >= 1.0) {
        return Refraction(vec3<f32>(0.0), eta, false);
    }
    let cos_t = sqrt(1.0 - sin2_t);
    return Refraction(-wi / eta + (cos_i / eta - cos_t) * n, eta, true);
}

fn reflect_dir(w: vec3<f32>, n: vec3<f32>) -> vec3<f32> {
    return -w + 2.0 * dot(w, n) * n;
}

// Microfacet::SMOOTH: rougher than this is a microfacet lobe, else a delta.
const MF_SMOOTH: f32 = 1e-3;

// bsdf::Microfacet: GGX or Beckmann normals of roughness alpha, sampled
// visible from the incident direction or from D cos θm.
struct Microfacet {
    alpha: f32,
    beckmann: bool,
    sample_visible: bool,
}

// erf::erfc (Numerical Recipes' erfcc), erf and erfinv (Giles 2010).
fn erfc_nr(x: f32) -> f32 {
    let z = abs(x);
    let t = 1.0 / (1.0 + 0.5 * z);
    let poly = -1.2655122 + t * (1.0000237 + t * (0.37409196 + t * (0.09678418 + t * (-0.18628806
        + t * (0.27886807 + t * (-1.135204 + t * (1.4885159 + t * (-0.8221522 + t * 0.17087277))))))));
    let r = t * exp(-z * z + poly);
    return select(2.0 - r, r, x >= 0.0);
}

fn erf_nr(x: f32) -> f32 {
    return 1.0 - erfc_nr(x);
}

fn erfinv_giles(x: f32) -> f32 {
    var w = -log((1.0 - x) * (1.0 + x));
    var p: f32;
    if (w < 5.0) {
        w = w - 2.5;
        p = 2.8102264e-8;
        p = 3.4327394e-7 + p * w;
        p = -3.5233877e-6 + p * w;
        p = -4.3915065e-6 + p * w;
        p = 2.1858087e-4 + p * w;
        p = -1.253725e-3 + p * w;
        p = -4.1776816e-3 + p * w;
        p = 0.24664073 + p * w;
        p = 1.5014094 + p * w;
    } else {
        w = sqrt(w) - 3.0;
        p = -2.0021426e-4;
        p = 1.0095056e-4 + p * w;
        p = 1.3493432e-3 + p * w;
        p = -3.6734284e-3 + p * w;
        p = 5.7395077e-3 + p * w;
        p = -7.6224613e-3 + p * w;
        p = 9.4388705e-3 + p * w;
        p = 1.0016741 + p * w;
        p = 2.8329768 + p * w;
    }
    return p * x;
}

// Microfacet::d
fn mf_d(m: Microfacet, wm: vec3<f32>) -> f32 {
    let cos2 = wm.z * wm.z;
    if (wm.z <= 0.0) {
        return 0.0;
    }
    let a2 = m.alpha * m.alpha;
    let tan2 = max(1.0 - cos2, 0.0) / cos2;
    var d: f32;
    if (m.beckmann) {
        d = exp(-tan2 / a2) / (PI * a2 * cos2 * cos2);
    } else {
        let e = 1.0 + tan2 / a2;
        d = 1.0 / (PI * a2 * cos2 * cos2 * e * e);
    }
    return select(0.0, d, is_finite1(d));
}

// Microfacet::a: 1 / (α tan θ), infinite at normal incidence.
fn mf_a(m: Microfacet, w: vec3<f32>) -> f32 {
    let sin2 = max(1.0 - w.z * w.z, 0.0);
    if (sin2 == 0.0) {
        return F32_INF;
    }
    return abs(w.z) / (m.alpha * sqrt(sin2));
}

// Microfacet::g1: exact for GGX, Walter et al.'s fit for Beckmann.
fn mf_g1(m: Microfacet, w: vec3<f32>) -> f32 {
    if (!m.beckmann) {
        let cos2 = w.z * w.z;
        if (cos2 <= 0.0) {
            return 0.0;
        }
        let tan2 = max(1.0 - cos2, 0.0) / cos2;
        return 1.0 / (1.0 + 0.5 * (sqrt(1.0 + m.alpha * m.alpha * tan2) - 1.0));
    }
    if (w.z == 0.0) {
        return 0.0;
    }
    let a = mf_a(m, w);
    if (a >= 1.6) {
        return 1.0;
    }
    return (3.535 * a + 2.181 * a * a) / (1.0 + 2.276 * a + 2.577 * a * a);
}

// Microfacet::g1_exact: Smith's exact G1 (Beckmann's Λ through erfc).
fn mf_g1_exact(m: Microfacet, w: vec3<f32>) -> f32 {
    if (!m.beckmann) {
        return mf_g1(m, w);
    }
    if (w.z == 0.0) {
        return 0.0;
    }
    let a = mf_a(m, w);
    if (a > 9.0) {
        return 1.0;
    }
    let lambda = 0.5 * max(exp(-a * a) / (a * sqrt(PI)) - erfc_nr(a), 0.0);
    return 1.0 / (1.0 + lambda);
}

// Mitsuba's separable G1(wo) G1(wi).
fn mf_g(m: Microfacet, wo: vec3<f32>, wi: vec3<f32>) -> f32 {
    return mf_g1(m, wo) * mf_g1(m, wi);
}

// Microfacet::pdf: the density of mf_sample in solid angle of wm.
fn mf_pdf(m: Microfacet, w: vec3<f32>, wm: vec3<f32>) -> f32 {
    if (!m.sample_visible) {
        return mf_d(m, wm) * max(wm.z, 0.0);
    }
    let c = abs(w.z);
    if (c == 0.0) {
        return 0.0;
    }
    let facing = max(dot(w, wm) * select(-1.0, 1.0, w.z >= 0.0), 0.0);
    return mf_g1_exact(m, w) / c * mf_d(m, wm) * facing;
}

// Microfacet::sample_all: wm from D cos θm.
fn mf_sample_all(m: Microfacet, u0: f32, u1: f32) -> vec3<f32> {
    let a2 = m.alpha * m.alpha;
    var tan2 = a2 * u0 / max(1.0 - u0, 1e-12);
    if (m.beckmann) {
        tan2 = -a2 * log(max(1.0 - u0, 1e-12));
    }
    let c = 1.0 / sqrt(1.0 + tan2);
    let s = sqrt(max(1.0 - c * c, 0.0));
    let phi = 2.0 * PI * u1;
    return vec3<f32>(s * cos(phi), s * sin(phi), c);
}

// Microfacet::sample_visible_ggx (Heitz 2018; w below the surface mirrored up).
fn ggx_sample_visible(alpha: f32, w: vec3<f32>, u0: f32, u1: f32) -> vec3<f32> {
    var wh = normalize(vec3<f32>(alpha * w.x, alpha * w.y, w.z));
    if (wh.z < 0.0) {
        wh = -wh;
    }
    var t1 = vec3<f32>(1.0, 0.0, 0.0);
    if (wh.z < 0.99999) {
        t1 = normalize(cross(vec3<f32>(0.0, 0.0, 1.0), wh));
    }
    let t2 = cross(wh, t1);
    let r = sqrt(u0);
    let phi = 2.0 * PI * u1;
    let px = r * cos(phi);
    let py0 = r * sin(phi);
    let h = sqrt(max(1.0 - px * px, 0.0));
    let s = 0.5 * (1.0 + wh.z);
    let py = (1.0 - s) * h + s * py0;
    let pz = sqrt(max(1.0 - px * px - py * py, 0.0));
    let nh = px * t1 + py * t2 + pz * wh;
    return normalize(vec3<f32>(alpha * nh.x, alpha * nh.y, max(nh.z, 1e-6)));
}

// microfacet::beckmann_slopes_11: slopes of the unit Beckmann surface seen
// from cosine cos_i, the first inverted in erf space by Newton's method.
fn beckmann_slopes_11(cos_i: f32, u0_in: f32, u1_in: f32) -> vec2<f32> {
    let u0 = clamp(u0_in, 1e-6, 1.0 - 1e-6);
    let u1 = clamp(u1_in, 1e-6, 1.0 - 1e-6);
    let tan_i = sqrt(max(1.0 - cos_i * cos_i, 0.0)) / cos_i;
    let cot_i = 1.0 / tan_i;
    let inv_sqrt_pi = 1.0 / sqrt(PI);
    let max_v = erf_nr(cot_i);
    var v = max_v - (max_v + 1.0) * erf_nr(sqrt(-log(u0)));
    let target_c = u0 * (1.0 + max_v + inv_sqrt_pi * tan_i * exp(-cot_i * cot_i));
    for (var i = 0; i < 4; i++) {
        let x = erfinv_giles(v);
        let value = 1.0 + v + inv_sqrt_pi * tan_i * exp(-x * x) - target_c;
        let derivative = 1.0 - x * tan_i;
        v = clamp(v - value / derivative, -1.0 + 1e-7, max_v);
    }
    return vec2<f32>(erfinv_giles(v), erfinv_giles(2.0 * u1 - 1.0));
}

// Microfacet::sample_visible_beckmann (Heitz and d'Eon 2014).
fn beckmann_sample_visible(alpha: f32, w: vec3<f32>, u0: f32, u1: f32) -> vec3<f32> {
    var ws = normalize(vec3<f32>(alpha * w.x, alpha * w.y, w.z));
    if (ws.z < 0.0) {
        ws = -ws;
    }
    let sin_t = sqrt(max(1.0 - ws.z * ws.z, 0.0));
    var cos_phi = 1.0;
    var sin_phi = 0.0;
    if (sin_t > 1e-7) {
        cos_phi = ws.x / sin_t;
        sin_phi = ws.y / sin_t;
    }
    let s = beckmann_slopes_11(ws.z, u0, u1);
    let slope_x = (cos_phi * s.x - sin_phi * s.y) * alpha;
    let slope_y = (sin_phi * s.x + cos_phi * s.y) * alpha;
    return normalize(vec3<f32>(-slope_x, -slope_y, 1.0));
}

// Microfacet::sample
fn mf_sample(m: Microfacet, w: vec3<f32>, u0: f32, u1: f32) -> vec3<f32> {
    if (!m.sample_visible) {
        return mf_sample_all(m, u0, u1);
    }
    if (m.beckmann) {
        return beckmann_sample_visible(m.alpha, w, u0, u1);
    }
    return ggx_sample_visible(m.alpha, w, u0, u1);
}

// sample::sample_cosine: Malley's method with the concentric disk map.
fn sample_cosine(u0: f32, u1: f32) -> vec3<f32> {
    let a = 2.0 * u0 - 1.0;
    let b = 2.0 * u1 - 1.0;
    var x = 0.0;
    var y = 0.0;
    if (a != 0.0 || b != 0.0) {
        if (abs(a) > abs(b)) {
            let phi = PI / 4.0 * (b / a);
            x = a * cos(phi);
            y = a * sin(phi);
        } else {
            let phi = PI / 2.0 - PI / 4.0 * (a / b);
            x = b * cos(phi);
            y = b * sin(phi);
        }
    }
    return vec3<f32>(x, y, sqrt(max(1.0 - x * x - y * y, 0.0)));
}
