// fogbank_render::lights: light records, selection by power (a CDF per vertex kind: LightSampler), the
// lat-long environment map (luminance × solid-angle 2D CDF, Mitsuba's
// layout) and light sampling, as in lights/sample.rs and lights/envmap.rs.


struct LightGpu {
    kind: u32,
    // Emitting triangles in the light BVH: the bit trail from its root.
    trail: u32,
    // LightSampler's CDF entry and pmf for points on surfaces (d.zw: in media).
    cdf_surface: f32,
    pmf_surface: f32,
    a: vec4<f32>,   // position (point, spot) or direction (directional)
    b: vec4<f32>,   // radiance / intensity / irradiance
    c: vec4<f32>,   // spot: axis direction, w = SpotCurve id
    d: vec4<f32>,   // spot: (cos_falloff_start, cos_total); z = CDF, w = pmf
    e: vec4<f32>,   // area: second edge (a = first corner and area, c = first edge)
}

struct EnvParams {
    to_local0: vec4<f32>,
    to_local1: vec4<f32>,
    to_local2: vec4<f32>,
    width: u32,
    height: u32,
    light_count: u32,
    integral: f32,
    // 0 when no light has power: the CPU's sampler then picks nothing.
    pickable: u32,
    // properties.wgsl: where the medium extensions and blackbody table
    // start in `shading`.
    props_ext: u32,
    props_blackbody: u32,
    // Lights from this index on are not environments (shapes' triangles).
    environments: u32,
    // 1: the map is read bilinearly, as Mitsuba 3's `envmap` (Envmap::bilinear).
    bilinear: u32,
    // Lights from this index on are picked through the light BVH
    // (light_bvh.wgsl; light_count: no tree), whose nodes start at this
    // vec4 of `shading`.
    bvh_first: u32,
    bvh_nodes: u32,
    pad0: u32,
}

@group(2) @binding(0) var<storage, read> lights: array<LightGpu>;
@group(2) @binding(1) var<uniform> env: EnvParams;
@group(2) @binding(2) var<storage, read> env_rgb: array<vec4<f32>>;
// Row CDF (height + 1), then per row the column CDF (width + 1 each).
@group(2) @binding(3) var<storage, read> env_cdf: array<f32>;

// LightSampler::pmf for a point on a surface or in a medium.
fn light_pmf(l: LightGpu, surface: bool) -> f32 {
    return select(l.d.w, l.pmf_surface, surface);
}

fn luminance(c: vec3<f32>) -> f32 {
    return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z;
}

// LightSampler::pick's answer: a light and its selection probability
// (index NO_LIGHT: none).
struct LightPick {
    index: u32,
    pmf: f32,
}

// LightSampler::pick at p: the first light whose CDF (for a point on a
// surface or in a medium) exceeds u (the last if none), by bisection;
// with a light BVH, the emitting triangles' shared entry descends the
// tree with u rescaled.
fn pick_light(u: f32, surface: bool, p: vec3<f32>) -> LightPick {
    var lo = 0u;
    var hi = env.light_count - 1u;
    while (lo < hi) {
        let mid = (lo + hi) / 2u;
        if (select(lights[mid].d.z, lights[mid].cdf_surface, surface) <= u) {
            lo = mid + 1u;
        } else {
            hi = mid;
        }
    }
    if (!LIGHT_BVH || lo < env.bvh_first) {
        return LightPick(lo, light_pmf(lights[lo], surface));
    }
    let shared_entry = lights[env.bvh_first];
    let width = light_pmf(shared_entry, surface);
    if (width <= 0.0) {
        return LightPick(NO_LIGHT, 0.0);
    }
    let below = select(shared_entry.d.z, shared_entry.cdf_surface, surface) - width;
    var b = light_bvh_pick(clamp((u - below) / width, 0.0, ONE_MINUS_EPSILON), p);
    b.pmf *= width;
    return b;
}

// LightSampler::pmf: the probability that pick_light at p returns li.
fn light_pmf_at(li: u32, surface: bool, p: vec3<f32>) -> f32 {
    if (!LIGHT_BVH || li < env.bvh_first) {
        return light_pmf(lights[li], surface);
    }
    return light_pmf(lights[env.bvh_first], surface) * light_bvh_pmf(li, p);
}

fn env_pixel(dir_world: vec3<f32>) -> u32 {
    let d = vec3<f32>(dot(env.to_local0.xyz, dir_world), dot(env.to_local1.xyz, dir_world),
                      dot(env.to_local2.xyz, dir_world));
    let theta = atan2(sqrt(d.x * d.x + d.z * d.z), d.y);
    var phi = atan2(d.x, -d.z);
    if (phi < 0.0) {
        phi += 2.0 * PI;
    }
    let row = min(u32(theta / PI * f32(env.height)), env.height - 1u);
    let col = min(u32(phi / (2.0 * PI) * f32(env.width)), env.width - 1u);
    return row * env.width + col;
}

fn env_pdf_of_pixel(p: u32) -> f32 {
    if (env.integral > 0.0) {
        return luminance(env_rgb[p].xyz) / env.integral;
    }
    return 0.0;
}

// sample_cdf over env_cdf[start .. start + n + 1]: (index, fraction).
fn sample_cdf(start: u32, n: u32, u: f32) -> vec2<f32> {
    var lo = 0u;
    var hi = n;   // first k in [0, n) with cdf[start + k + 1] > u
    while (lo < hi) {
        let mid = (lo + hi) / 2u;
        if (env_cdf[start + mid + 1u] <= u) {
            lo = mid + 1u;
        } else {
            hi = mid;
        }
    }
    let k = min(lo, n - 1u);
    let width = env_cdf[start + k + 1u] - env_cdf[start + k];
    var f = 0.5;
    if (width > 0.0) {
        f = clamp((u - env_cdf[start + k]) / width, 0.0, 1.0);
    }
    return vec2<f32>(f32(k), f);
}

fn to_world_dir(local: vec3<f32>) -> vec3<f32> {
    // to_local is a rotation: its transpose maps back.
    return normalize(env.to_local0.xyz * local.x + env.to_local1.xyz * local.y
                     + env.to_local2.xyz * local.z);
}

struct LightSample {
    wi: vec3<f32>,
    radiance: vec3<f32>,
    pdf: f32,
    distance: f32,
    is_delta: bool,
    valid: bool,
}

const EDGE_MARGIN: f32 = 1e-4;

fn envmap_sample(u0: f32, u1: f32) -> LightSample {
    var ls: LightSample;
    ls.distance = F32_INF;
    ls.is_delta = false;
    ls.valid = false;
    if (env.integral <= 0.0) {
        return ls;
    }
    let rv = sample_cdf(0u, env.height, u0);
    let i = u32(rv.x);
    let cu = sample_cdf(env.height + 1u + i * (env.width + 1u), env.width, u1);
    let j = u32(cu.x);
    let c0 = cos(PI * f32(i) / f32(env.height));
    let c1 = cos(PI * f32(i + 1u) / f32(env.height));
    let fv = clamp(rv.y, EDGE_MARGIN, 1.0 - EDGE_MARGIN);
    let fu = clamp(cu.y, EDGE_MARGIN, 1.0 - EDGE_MARGIN);
    let cos_theta = c0 + (c1 - c0) * fv;
    let phi = 2.0 * PI * (f32(j) + fu) / f32(env.width);
    let sin_theta = sqrt(max(1.0 - cos_theta * cos_theta, 0.0));
    let local = vec3<f32>(sin_theta * sin(phi), cos_theta, -sin_theta * cos(phi));
    ls.wi = to_world_dir(local);
    let p = env_pixel(ls.wi);
    ls.radiance = env_eval(ls.wi);
    ls.pdf = env_pdf_of_pixel(p);
    ls.valid = ls.pdf > 0.0;
    return ls;
}

fn is_environment(l: LightGpu) -> bool {
    return l.kind == LIGHT_CONSTANT || l.kind == LIGHT_ENVMAP;
}

fn light_le(l: LightGpu, dir: vec3<f32>) -> vec3<f32> {
    if (l.kind == LIGHT_CONSTANT) {
        return l.b.xyz;
    }
    if (l.kind == LIGHT_ENVMAP) {
        return env_eval(dir);
    }
    return vec3<f32>(0.0);
}

// Envmap::eval: the pixel's radiance, or bilinear between texels at
// u = (j + ½)/W (columns wrap) and v = i/(H − 1) (clamped), Mitsuba's
// lookup; sampling stays piecewise constant over pixels either way.
fn env_eval(dir_world: vec3<f32>) -> vec3<f32> {
    if (env.bilinear == 0u) {
        return env_rgb[env_pixel(dir_world)].xyz;
    }
    let d = vec3<f32>(dot(env.to_local0.xyz, dir_world), dot(env.to_local1.xyz, dir_world),
                      dot(env.to_local2.xyz, dir_world));
    var u = atan2(d.x, -d.z) / (2.0 * PI);
    u -= floor(u);
    let v = clamp(acos(clamp(d.y, -1.0, 1.0)) / PI, 0.0, 1.0);
    let w = f32(env.width);
    let h = f32(env.height);
    let x = u * w - 0.5;
    let y = v * (h - 1.0);
    if (!(finite(x) && finite(y))) {
        return vec3<f32>(0.0);
    }
    let x0 = floor(x);
    let y0 = floor(y);
    let fx = x - x0;
    let fy = y - y0;
    let c0 = min(u32(x0 - w * floor(x0 / w)), env.width - 1u);
    let c1 = min(u32((x0 + 1.0) - w * floor((x0 + 1.0) / w)), env.width - 1u);
    let r0 = min(u32(clamp(y0, 0.0, h - 1.0)), env.height - 1u);
    let r1 = min(u32(clamp(y0 + 1.0, 0.0, h - 1.0)), env.height - 1u);
    let top = env_rgb[r0 * env.width + c0].xyz * (1.0 - fx) + env_rgb[r0 * env.width + c1].xyz * fx;
    let bottom = env_rgb[r1 * env.width + c0].xyz * (1.0 - fx) + env_rgb[r1 * env.width + c1].xyz * fx;
    return top * (1.0 - fy) + bottom * fy;
}

fn light_pdf_li(l: LightGpu, dir: vec3<f32>) -> f32 {
    if (l.kind == LIGHT_CONSTANT) {
        return INV_4PI;
    }
    if (l.kind == LIGHT_ENVMAP) {
        return env_pdf_of_pixel(env_pixel(dir));
    }
    return 0.0;
}

// lights::sample::spot_falloff; curve: SpotCurve (0 smoothstep in cos θ,
// 1 linear in θ).
fn spot_falloff(cos_theta: f32, cos_start: f32, cos_total: f32, curve: f32) -> f32 {
    if (cos_theta >= cos_start) {
        return 1.0;
    }
    if (cos_theta <= cos_total || cos_start <= cos_total) {
        return 0.0;
    }
    if (curve == 1.0) {
        let total = acos(cos_total);
        return (total - acos(cos_theta)) / (total - acos(cos_start));
    }
    let x = (cos_theta - cos_total) / (cos_start - cos_total);
    return x * x * (3.0 - 2.0 * x);
}

fn light_sample_li(l: LightGpu, p: vec3<f32>, u0: f32, u1: f32) -> LightSample {
    var ls: LightSample;
    ls.valid = false;
    ls.is_delta = true;
    ls.pdf = 1.0;
    ls.distance = F32_INF;
    switch l.kind {
        case LIGHT_CONSTANT: {
            let z = 1.0 - 2.0 * u0;
            let r = sqrt(max(1.0 - z * z, 0.0));
            let phi = 2.0 * PI * u1;
            ls.wi = vec3<f32>(r * cos(phi), r * sin(phi), z);
            ls.radiance = l.b.xyz;
            ls.pdf = INV_4PI;
            ls.is_delta = false;
            ls.valid = true;
        }
        case LIGHT_ENVMAP: {
            ls = envmap_sample(u0, u1);
        }
        case LIGHT_DIRECTIONAL: {
            ls.wi = -l.a.xyz;
            ls.radiance = l.b.xyz;
            ls.valid = true;
        }
        case LIGHT_AREA, LIGHT_SPHERE, LIGHT_DISK: {
            ls = shape_light_sample(l, p, u0, u1);
        }
        case LIGHT_POINT, LIGHT_SPOT: {
            let d = l.a.xyz - p;
            let dist2 = dot(d, d);
            if (dist2 > 0.0) {
                let dist = sqrt(dist2);
                ls.wi = d / dist;
                ls.distance = dist;
                var k = 1.0;
                if (l.kind == LIGHT_SPOT) {
                    k = spot_falloff(dot(l.c.xyz, -ls.wi), l.d.x, l.d.y, l.c.w);
                }
                ls.radiance = l.b.xyz * (k / dist2);
                ls.valid = k > 0.0;
            }
        }
        default: {
            invalid_id();
        }
    }
    return ls;
}
