// fogbank_render::world::phase::HenyeyGreenstein: eval, and exact sampling (so
// f / pdf = 1), written in the split 1 ∓ cos form that stays accurate as
// |g| → 1.

const INV_4PI: f32 = 0.07957747154594767;
const PI: f32 = 3.141592653589793;

fn hg_eval_split(g: f32, one_minus_cos: f32, one_plus_cos: f32) -> f32 {
    let one_minus_g = 1.0 - g;
    let one_plus_g = 1.0 + g;
    var denom: f32;
    if (g >= 0.0) {
        denom = one_minus_g * one_minus_g + 2.0 * g * one_minus_cos;
    } else {
        denom = one_plus_g * one_plus_g - 2.0 * g * one_plus_cos;
    }
    return INV_4PI * one_minus_g * one_plus_g / (denom * sqrt(denom));
}

fn hg_eval(g: f32, cos_theta: f32) -> f32 {
    let c = clamp(cos_theta, -1.0, 1.0);
    return hg_eval_split(g, 1.0 - c, 1.0 + c);
}

// glam's Vec3::any_orthonormal_pair (Duff et al. 2017).
fn orthonormal_pair(n: vec3<f32>) -> array<vec3<f32>, 2> {
    let sign = select(-1.0, 1.0, n.z >= 0.0);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    return array<vec3<f32>, 2>(
        vec3<f32>(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x),
        vec3<f32>(b, sign + n.y * n.y * a, -n.y),
    );
}

// Returns (wi, pdf) as vec4; wo points away from the scattering point.
fn hg_sample(g: f32, wo: vec3<f32>, u0: f32, u1: f32) -> vec4<f32> {
    let one_minus_g = 1.0 - g;
    let one_plus_g = 1.0 + g;
    let one_minus_g2 = one_minus_g * one_plus_g;
    var d: f32;
    if (g >= 0.0) {
        d = one_minus_g + 2.0 * g * (1.0 - u0);
    } else {
        d = one_plus_g - 2.0 * g * u0;
    }
    let s = one_minus_g2 / d;
    let one_minus_cos = one_minus_g * u0 * (s + one_minus_g) / d;
    let one_plus_cos = one_plus_g * (1.0 - u0) * (s + one_plus_g) / d;
    var cos_theta: f32;
    if (one_minus_cos <= one_plus_cos) {
        cos_theta = 1.0 - one_minus_cos;
    } else {
        cos_theta = one_plus_cos - 1.0;
    }
    let sin_theta = sqrt(max(one_minus_cos * one_plus_cos, 0.0));
    let phi = 2.0 * PI * u1;
    let forward = -wo;
    let t = orthonormal_pair(forward);
    let wi = (t[0] * cos(phi) + t[1] * sin(phi)) * sin_theta + forward * cos_theta;
    let pdf = INV_4PI * d * d * d / (one_minus_g2 * one_minus_g2);
    return vec4<f32>(wi, pdf);
}

// HenyeyGreenstein::pdf(wo, wi), both pointing away from the scattering
// point: 1 ∓ cos θ from |wi ± wo|² / 2, accurate where the dot product has
// lost its digits.
fn hg_pdf(g: f32, wo: vec3<f32>, wi: vec3<f32>) -> f32 {
    let a = wi + wo;
    let b = wi - wo;
    return hg_eval_split(g, 0.5 * dot(a, a), 0.5 * dot(b, b));
}
