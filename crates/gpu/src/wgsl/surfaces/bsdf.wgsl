// Surface scattering models, mirroring render/src/world/bsdf/ (model.rs,
// conductor.rs, dielectric.rs, plastic.rs, rough_plastic.rs): pbrt-v4's
// conventions (wo and wi point away from the surface, local frame, z along
// the shading normal), radiance-transport values, delta lobes reached only
// by sampling. One record per model, its kind a BSDF_* id.

struct Bsdf {
    kind: u32,
    // Microfacet normals (conductor, dielectric, rough plastic).
    mf: Microfacet,
    // Interior over exterior IOR (dielectrics, plastics).
    eta: f32,
    nonlinear: bool,
    // Diffuse: reflectance. Conductor: η, k, specular tint. Plastics:
    // diffuse, specular.
    a: vec3<f32>,
    b: vec3<f32>,
    c: vec3<f32>,
    // Rough plastic: the coating table's first vec4 in surface_data and
    // the internal diffuse reflectance.
    coating: u32,
    internal: f32,
}

struct BsdfSample {
    wi: vec3<f32>,
    f: vec3<f32>,
    pdf: f32,
    delta: bool,
    valid: bool,
}

fn no_bsdf_sample() -> BsdfSample {
    return BsdfSample(vec3<f32>(0.0), vec3<f32>(0.0), 0.0, false, false);
}

fn mirror_z(w: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(-w.x, -w.y, w.z);
}

fn mean3(v: vec3<f32>) -> f32 {
    return (v.x + v.y + v.z) / 3.0;
}

// Bsdf::is_delta
fn bsdf_is_delta(b: Bsdf) -> bool {
    switch b.kind {
        case BSDF_CONDUCTOR, BSDF_DIELECTRIC: {
            return b.mf.alpha < MF_SMOOTH;
        }
        case BSDF_THIN_DIELECTRIC, BSDF_NULL: {
            return true;
        }
        default: {
            return false;
        }
    }
}

// dielectric::thin_transmission: 1 − R′ with the slab's inter-reflections.
fn thin_transmission(c: f32, eta: f32) -> f32 {
    let r = fresnel_dielectric(abs(c), eta);
    if (r < 1.0) {
        let t = 1.0 - r;
        return 1.0 - (r + t * t * r / (1.0 - r * r));
    }
    return 0.0;
}

// Bsdf::null_transmission: the fraction passing straight through, or -1
// when the model lets nothing through unscattered.
fn bsdf_null_transmission(b: Bsdf, c: f32) -> f32 {
    if (b.kind == BSDF_NULL) {
        return 1.0;
    }
    if (b.kind == BSDF_THIN_DIELECTRIC) {
        return thin_transmission(c, b.eta);
    }
    return -1.0;
}

// conductor::eval / pdf
fn conductor_eval(b: Bsdf, wo: vec3<f32>, wi: vec3<f32>) -> vec3<f32> {
    let wm = wo + wi;
    if (b.mf.alpha < MF_SMOOTH || wo.z <= 0.0 || wi.z <= 0.0 || dot(wm, wm) == 0.0) {
        return vec3<f32>(0.0);
    }
    let h = normalize(wm);
    let f = fresnel_conductor(abs(dot(wo, h)), b.a, b.b);
    return mf_d(b.mf, h) * mf_g(b.mf, wo, wi) * f / (4.0 * wo.z * wi.z) * b.c;
}

fn conductor_pdf(b: Bsdf, wo: vec3<f32>, wi: vec3<f32>) -> f32 {
    let wm = wo + wi;
    if (b.mf.alpha < MF_SMOOTH || wo.z <= 0.0 || wi.z <= 0.0 || dot(wm, wm) == 0.0) {
        return 0.0;
    }
    let h = normalize(wm);
    return mf_pdf(b.mf, wo, h) / (4.0 * abs(dot(wo, h)));
}

fn conductor_sample(b: Bsdf, wo: vec3<f32>, u0: f32, u1: f32) -> BsdfSample {
    if (wo.z <= 0.0) {
        return no_bsdf_sample();
    }
    if (b.mf.alpha < MF_SMOOTH) {
        let wi = mirror_z(wo);
        return BsdfSample(wi, fresnel_conductor(wi.z, b.a, b.b) / wi.z * b.c, 1.0, true, true);
    }
    let wm = mf_sample(b.mf, wo, u0, u1);
    let wi = reflect_dir(wo, wm);
    if (wo.z * wi.z <= 0.0) {
        return no_bsdf_sample();
    }
    let pdf = conductor_pdf(b, wo, wi);
    return BsdfSample(wi, conductor_eval(b, wo, wi), pdf, false, pdf > 0.0);
}

struct HalfVector {
    wm: vec3<f32>,
    etap: f32,
    valid: bool,
}

// dielectric::half_vector: the generalised half vector in the upper
// hemisphere and the IOR ratio crossed (1 for reflection).
fn half_vector(wo: vec3<f32>, wi: vec3<f32>, eta: f32) -> HalfVector {
    let none = HalfVector(vec3<f32>(0.0), 1.0, false);
    let co = wo.z;
    let ci = wi.z;
    if (co == 0.0 || ci == 0.0) {
        return none;
    }
    var etap = 1.0;
    if (co * ci <= 0.0) {
        etap = select(1.0 / eta, eta, co > 0.0);
    }
    let m = wi * etap + wo;
    if (dot(m, m) == 0.0) {
        return none;
    }
    var wm = normalize(m);
    if (wm.z < 0.0) {
        wm = -wm;
    }
    if (dot(wm, wi) * ci < 0.0 || dot(wm, wo) * co < 0.0) {
        return none;
    }
    return HalfVector(wm, etap, true);
}

fn dielectric_eval(b: Bsdf, wo: vec3<f32>, wi: vec3<f32>) -> f32 {
    if (b.mf.alpha < MF_SMOOTH || b.eta == 1.0) {
        return 0.0;
    }
    let h = half_vector(wo, wi, b.eta);
    if (!h.valid) {
        return 0.0;
    }
    let f = fresnel_dielectric(dot(wo, h.wm), b.eta);
    let dg = mf_d(b.mf, h.wm) * mf_g(b.mf, wo, wi);
    if (h.etap == 1.0) {
        return dg * f / abs(4.0 * wi.z * wo.z);
    }
    let s = dot(wi, h.wm) + dot(wo, h.wm) / h.etap;
    let denom = s * s * wi.z * wo.z;
    return dg * (1.0 - f) * abs(dot(wi, h.wm) * dot(wo, h.wm) / denom) / (h.etap * h.etap);
}

fn dielectric_pdf(b: Bsdf, wo: vec3<f32>, wi: vec3<f32>) -> f32 {
    if (b.mf.alpha < MF_SMOOTH || b.eta == 1.0) {
        return 0.0;
    }
    let h = half_vector(wo, wi, b.eta);
    if (!h.valid) {
        return 0.0;
    }
    let r = fresnel_dielectric(dot(wo, h.wm), b.eta);
    if (h.etap == 1.0) {
        return mf_pdf(b.mf, wo, h.wm) / (4.0 * abs(dot(wo, h.wm))) * r;
    }
    let s = dot(wi, h.wm) + dot(wo, h.wm) / h.etap;
    return mf_pdf(b.mf, wo, h.wm) * abs(dot(wi, h.wm)) / (s * s) * (1.0 - r);
}

fn dielectric_sample(b: Bsdf, wo: vec3<f32>, uc: f32, u0: f32, u1: f32) -> BsdfSample {
    if (wo.z == 0.0) {
        return no_bsdf_sample();
    }
    if (b.mf.alpha < MF_SMOOTH || b.eta == 1.0) {
        let r = fresnel_dielectric(wo.z, b.eta);
        if (uc < r) {
            let wi = mirror_z(wo);
            return BsdfSample(wi, vec3<f32>(r / abs(wi.z)), r, true, true);
        }
        let t = refract_dir(wo, vec3<f32>(0.0, 0.0, 1.0), b.eta);
        if (!t.valid || t.wt.z == 0.0) {
            return no_bsdf_sample();
        }
        let tr = 1.0 - r;
        return BsdfSample(t.wt, vec3<f32>(tr / abs(t.wt.z) / (t.etap * t.etap)), tr, true, true);
    }
    let wm = mf_sample(b.mf, wo, u0, u1);
    let r = fresnel_dielectric(dot(wo, wm), b.eta);
    var wi: vec3<f32>;
    if (uc < r) {
        wi = reflect_dir(wo, wm);
        if (wo.z * wi.z <= 0.0) {
            return no_bsdf_sample();
        }
    } else {
        let t = refract_dir(wo, wm, b.eta);
        if (!t.valid || wo.z * t.wt.z > 0.0 || t.wt.z == 0.0) {
            return no_bsdf_sample();
        }
        wi = t.wt;
    }
    let pdf = dielectric_pdf(b, wo, wi);
    return BsdfSample(wi, vec3<f32>(dielectric_eval(b, wo, wi)), pdf, false, pdf > 0.0);
}

fn thin_dielectric_sample(b: Bsdf, wo: vec3<f32>, uc: f32) -> BsdfSample {
    if (wo.z == 0.0) {
        return no_bsdf_sample();
    }
    let t = thin_transmission(wo.z, b.eta);
    let r = 1.0 - t;
    var wi = -wo;
    var p = t;
    if (uc < r) {
        wi = mirror_z(wo);
        p = r;
    }
    return BsdfSample(wi, vec3<f32>(p / abs(wi.z)), p, true, true);
}

// plastic::diffuse_fresnel: Mitsuba's fits of the diffuse Fresnel reflectance.
fn diffuse_fresnel(eta: f32) -> f32 {
    let inv = 1.0 / eta;
    if (eta < 1.0) {
        return 0.0636 * inv + eta * (eta * -1.4399 + 0.7099) + 0.6681;
    }
    return ((((-1.36881 * inv + 4.98554) * inv - 7.80989) * inv + 6.75335) * inv - 3.4793) * inv
        + 0.919317;
}

// Plastic::specular_probability from the coating's reflectance at wo
// (plastic: Fresnel; rough plastic: 1 − its tabulated transmittance).
fn plastic_specular_probability(b: Bsdf, reflect: f32) -> f32 {
    let d = mean3(b.a);
    let s = mean3(b.b);
    let w = s / (d + s);
    let ps = reflect * w;
    let pd = (1.0 - reflect) * (1.0 - w);
    return ps / (ps + pd);
}

fn plastic_diffuse(b: Bsdf, wo: vec3<f32>, wi: vec3<f32>) -> vec3<f32> {
    let fdr = diffuse_fresnel(1.0 / b.eta);
    var base = b.a / (1.0 - fdr);
    if (b.nonlinear) {
        base = b.a / (vec3<f32>(1.0) - b.a * fdr);
    }
    let fo = fresnel_dielectric(wo.z, b.eta);
    let fi = fresnel_dielectric(wi.z, b.eta);
    return base * ((1.0 - fo) * (1.0 - fi) / (PI * b.eta * b.eta));
}

fn plastic_sample(b: Bsdf, wo: vec3<f32>, uc: f32, u0: f32, u1: f32) -> BsdfSample {
    if (wo.z <= 0.0) {
        return no_bsdf_sample();
    }
    let fo = fresnel_dielectric(wo.z, b.eta);
    let ps = plastic_specular_probability(b, fo);
    if (uc < ps) {
        let wi = mirror_z(wo);
        return BsdfSample(wi, b.b * fo / wi.z, ps, true, true);
    }
    let wi = sample_cosine(u0, u1);
    if (wi.z <= 0.0) {
        return no_bsdf_sample();
    }
    return BsdfSample(wi, plastic_diffuse(b, wo, wi), (1.0 - ps) * wi.z / PI, false, true);
}

// RoughPlastic::t: the coating's transmittance at cosine mu, linear in
// the 64-point table.
fn coating_t(b: Bsdf, mu: f32) -> f32 {
    let x = clamp(mu, 0.0, 1.0) * 63.0;
    let i = min(u32(x), 62u);
    let f = x - f32(i);
    let t0 = surface_data[b.coating + i / 4u][i % 4u];
    let t1 = surface_data[b.coating + (i + 1u) / 4u][(i + 1u) % 4u];
    return t0 * (1.0 - f) + t1 * f;
}

// rough_plastic's masking of one direction about microfacet m.
fn masked_g1(mf: Microfacet, v: vec3<f32>, m: vec3<f32>) -> f32 {
    if (dot(v, m) * v.z <= 0.0) {
        return 0.0;
    }
    return mf_g1(mf, v);
}

fn rough_plastic_eval(b: Bsdf, wo: vec3<f32>, wi: vec3<f32>) -> vec3<f32> {
    if (wo.z <= 0.0 || wi.z <= 0.0) {
        return vec3<f32>(0.0);
    }
    let h = normalize(wo + wi);
    let g = masked_g1(b.mf, wo, h) * masked_g1(b.mf, wi, h);
    let spec = fresnel_dielectric(dot(wo, h), b.eta) * mf_d(b.mf, h) * g / (4.0 * wo.z * wi.z);
    var denom = vec3<f32>(1.0 - b.internal);
    if (b.nonlinear) {
        denom = vec3<f32>(1.0) - b.a * b.internal;
    }
    let diff = b.a / denom * (coating_t(b, wo.z) * coating_t(b, wi.z) / (PI * b.eta * b.eta));
    return b.b * spec + diff;
}

fn rough_plastic_pdf(b: Bsdf, wo: vec3<f32>, wi: vec3<f32>) -> f32 {
    if (wo.z <= 0.0 || wi.z <= 0.0) {
        return 0.0;
    }
    let h = normalize(wo + wi);
    let ps = plastic_specular_probability(b, 1.0 - coating_t(b, wo.z));
    let spec = mf_pdf(b.mf, wo, h) / (4.0 * dot(wo, h));
    return ps * spec + (1.0 - ps) * wi.z / PI;
}

fn rough_plastic_sample(b: Bsdf, wo: vec3<f32>, uc: f32, u0: f32, u1: f32) -> BsdfSample {
    if (wo.z <= 0.0) {
        return no_bsdf_sample();
    }
    let ps = plastic_specular_probability(b, 1.0 - coating_t(b, wo.z));
    var wi: vec3<f32>;
    if (uc < ps) {
        let m = mf_sample(b.mf, wo, u0, u1);
        wi = 2.0 * dot(wo, m) * m - wo;
    } else {
        wi = sample_cosine(u0, u1);
    }
    if (wi.z <= 0.0) {
        return no_bsdf_sample();
    }
    let pdf = rough_plastic_pdf(b, wo, wi);
    return BsdfSample(wi, rough_plastic_eval(b, wo, wi), pdf, false, pdf > 0.0);
}

// Bsdf::eval
fn bsdf_eval(b: Bsdf, wo: vec3<f32>, wi: vec3<f32>) -> vec3<f32> {
    switch b.kind {
        case BSDF_DIFFUSE: {
            if (wo.z > 0.0 && wi.z > 0.0) {
                return b.a / PI;
            }
            return vec3<f32>(0.0);
        }
        case BSDF_CONDUCTOR: {
            return conductor_eval(b, wo, wi);
        }
        case BSDF_DIELECTRIC: {
            return vec3<f32>(dielectric_eval(b, wo, wi));
        }
        case BSDF_PLASTIC: {
            if (wo.z <= 0.0 || wi.z <= 0.0) {
                return vec3<f32>(0.0);
            }
            return plastic_diffuse(b, wo, wi);
        }
        case BSDF_ROUGH_PLASTIC: {
            return rough_plastic_eval(b, wo, wi);
        }
        case BSDF_THIN_DIELECTRIC, BSDF_NULL: {
            return vec3<f32>(0.0);
        }
        default: {
            invalid_id();
            return vec3<f32>(0.0);
        }
    }
}

// Bsdf::pdf
fn bsdf_pdf(b: Bsdf, wo: vec3<f32>, wi: vec3<f32>) -> f32 {
    switch b.kind {
        case BSDF_DIFFUSE: {
            if (wo.z > 0.0 && wi.z > 0.0) {
                return wi.z / PI;
            }
            return 0.0;
        }
        case BSDF_CONDUCTOR: {
            return conductor_pdf(b, wo, wi);
        }
        case BSDF_DIELECTRIC: {
            return dielectric_pdf(b, wo, wi);
        }
        case BSDF_PLASTIC: {
            if (wo.z <= 0.0 || wi.z <= 0.0) {
                return 0.0;
            }
            let ps = plastic_specular_probability(b, fresnel_dielectric(wo.z, b.eta));
            return (1.0 - ps) * wi.z / PI;
        }
        case BSDF_ROUGH_PLASTIC: {
            return rough_plastic_pdf(b, wo, wi);
        }
        default: {
            return 0.0;
        }
    }
}

// Bsdf::sample from three uniform numbers (uc picks the lobe).
fn bsdf_sample(b: Bsdf, wo: vec3<f32>, uc: f32, u0: f32, u1: f32) -> BsdfSample {
    switch b.kind {
        case BSDF_DIFFUSE: {
            if (wo.z <= 0.0) {
                return no_bsdf_sample();
            }
            let wi = sample_cosine(u0, u1);
            return BsdfSample(wi, b.a / PI, wi.z / PI, false, wi.z > 0.0);
        }
        case BSDF_CONDUCTOR: {
            return conductor_sample(b, wo, u0, u1);
        }
        case BSDF_DIELECTRIC: {
            return dielectric_sample(b, wo, uc, u0, u1);
        }
        case BSDF_THIN_DIELECTRIC: {
            return thin_dielectric_sample(b, wo, uc);
        }
        case BSDF_PLASTIC: {
            return plastic_sample(b, wo, uc, u0, u1);
        }
        case BSDF_ROUGH_PLASTIC: {
            return rough_plastic_sample(b, wo, uc, u0, u1);
        }
        case BSDF_NULL: {
            return BsdfSample(-wo, vec3<f32>(1.0 / abs(wo.z)), 1.0, true, wo.z != 0.0);
        }
        default: {
            invalid_id();
            return no_bsdf_sample();
        }
    }
}
