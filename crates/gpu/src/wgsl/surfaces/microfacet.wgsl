// Fresnel terms, Snell refraction and the GGX microfacet distribution,
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

// Ggx::SMOOTH: rougher than this is a microfacet lobe, else a delta.
const GGX_SMOOTH: f32 = 1e-3;

fn ggx_d(alpha: f32, wm: vec3<f32>) -> f32 {
    let cos2 = wm.z * wm.z;
    if (cos2 <= 0.0) {
        return 0.0;
    }
    let a2 = alpha * alpha;
    let tan2 = max(1.0 - cos2, 0.0) / cos2;
    let e = 1.0 + tan2 / a2;
    return 1.0 / (PI * a2 * cos2 * cos2 * e * e);
}

fn ggx_g1(alpha: f32, w: vec3<f32>) -> f32 {
    let cos2 = w.z * w.z;
    if (cos2 <= 0.0) {
        return 0.0;
    }
    let tan2 = max(1.0 - cos2, 0.0) / cos2;
    return 1.0 / (1.0 + 0.5 * (sqrt(1.0 + alpha * alpha * tan2) - 1.0));
}

// Mitsuba's separable G1(wo) G1(wi).
fn ggx_g(alpha: f32, wo: vec3<f32>, wi: vec3<f32>) -> f32 {
    return ggx_g1(alpha, wo) * ggx_g1(alpha, wi);
}

// Ggx::d_visible: the pdf of ggx_sample_visible in solid angle of wm.
fn ggx_d_visible(alpha: f32, w: vec3<f32>, wm: vec3<f32>) -> f32 {
    let c = abs(w.z);
    if (c == 0.0) {
        return 0.0;
    }
    let facing = max(dot(w, wm) * select(-1.0, 1.0, w.z >= 0.0), 0.0);
    return ggx_g1(alpha, w) / c * ggx_d(alpha, wm) * facing;
}

// Ggx::sample_visible (Heitz 2018; w below the surface mirrored up).
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
