// The lights of emitting shapes (render/src/lights: area.rs, sphere.rs,
// disk.rs): emitting triangles and disks sampled by area, spheres by the
// cone they subtend. Record layout: fogbank-gpu's lights.rs.

// Shadow rays toward a point on an emitter stop this fraction short of it
// (lights/area.rs SHADOW_SHORTEN), so the emitter does not occlude itself.
const SHADOW_SHORTEN: f32 = 1e-4;

// Below sin²(1.5°) the sphere's cone takes 1 − cos θ_max from its Taylor
// series (sphere.rs SMALL_CONE).
const SMALL_CONE: f32 = 0.00068523;

fn is_shape_light(l: LightGpu) -> bool {
    return l.kind == LIGHT_AREA || l.kind == LIGHT_SPHERE || l.kind == LIGHT_DISK;
}

// The emitting normal of a triangle or disk: the winding's (u × v for a
// disk), flipped to the side the shape's normals give (the sign is in c.w).
fn area_normal(l: LightGpu) -> vec3<f32> {
    return normalize(cross(l.c.xyz, l.e.xyz)) * l.c.w;
}

// d² / (|cos θ_l| A) for the point q seen from p (area sampling).
fn area_pdf_solid(l: LightGpu, p: vec3<f32>, q: vec3<f32>, wi: vec3<f32>) -> f32 {
    let c = abs(dot(area_normal(l), wi));
    if (c <= 0.0) {
        return 0.0;
    }
    let d = q - p;
    return dot(d, d) / (c * l.a.w);
}

// SphereLight: centre and radius in a, 1 in c.w when it emits inward.
fn sphere_inward(l: LightGpu) -> bool {
    return l.c.w != 0.0;
}

// SphereLight::sees_front: outside an outward sphere, inside an inward one.
fn sphere_sees_front(l: LightGpu, p: vec3<f32>) -> bool {
    let d = p - l.a.xyz;
    return (dot(d, d) > l.a.w * l.a.w) != sphere_inward(l);
}

// SphereLight::cone: (sin²θ_max, 1 − cos θ_max) seen from p outside.
fn sphere_cone(l: LightGpu, p: vec3<f32>) -> vec2<f32> {
    let d = p - l.a.xyz;
    let sin2_max = l.a.w * l.a.w / dot(d, d);
    if (sin2_max < SMALL_CONE) {
        return vec2<f32>(sin2_max, 0.5 * sin2_max);
    }
    return vec2<f32>(sin2_max, 1.0 - sqrt(max(1.0 - sin2_max, 0.0)));
}

// Light::pdf_solid: the solid-angle density at p of sampling the point q
// of an emitting shape, seen along unit wi.
fn shape_pdf_solid(l: LightGpu, p: vec3<f32>, q: vec3<f32>, wi: vec3<f32>) -> f32 {
    if (l.kind != LIGHT_SPHERE) {
        return area_pdf_solid(l, p, q, wi);
    }
    if (!sphere_sees_front(l, p)) {
        return 0.0;
    }
    if (!sphere_inward(l)) {
        return 1.0 / (2.0 * PI * sphere_cone(l, p).y);
    }
    let c = abs(dot((q - l.a.xyz) / l.a.w, wi));
    if (c <= 0.0) {
        return 0.0;
    }
    let d = q - p;
    return dot(d, d) / (c * 4.0 * PI * l.a.w * l.a.w);
}

// Radiance leaving q toward -wi (zero on the dark side).
fn shape_le(l: LightGpu, q: vec3<f32>, wi: vec3<f32>) -> vec3<f32> {
    var front: bool;
    if (l.kind == LIGHT_SPHERE) {
        front = (dot(q - l.a.xyz, wi) < 0.0) != sphere_inward(l);
    } else {
        front = dot(area_normal(l), wi) < 0.0;
    }
    return select(vec3<f32>(0.0), l.b.xyz, front);
}

// A uniform point of a triangle (Heitz's square-to-triangle map).
fn triangle_point(l: LightGpu, u0: f32, u1: f32) -> vec3<f32> {
    var b0: f32;
    var b1: f32;
    if (u0 < u1) {
        b0 = 0.5 * u0;
        b1 = u1 - b0;
    } else {
        b1 = 0.5 * u1;
        b0 = u0 - b1;
    }
    return l.a.xyz + b0 * l.c.xyz + b1 * l.e.xyz;
}

// A uniform point of a disk (math::warp::concentric_disk).
fn disk_point(l: LightGpu, u0: f32, u1: f32) -> vec3<f32> {
    let a = 2.0 * u0 - 1.0;
    let b = 2.0 * u1 - 1.0;
    var xy = vec2<f32>(0.0);
    if (a != 0.0 || b != 0.0) {
        if (abs(a) > abs(b)) {
            let phi = 0.25 * PI * (b / a);
            xy = a * vec2<f32>(cos(phi), sin(phi));
        } else {
            let phi = 0.5 * PI - 0.25 * PI * (a / b);
            xy = b * vec2<f32>(cos(phi), sin(phi));
        }
    }
    return l.a.xyz + xy.x * l.c.xyz + xy.y * l.e.xyz;
}

// SphereLight::sample's point: uniform over the sphere from inside an
// inward sphere, else uniform in the cone seen from p (the angle α at the
// centre from the cone's θ).
fn sphere_point(l: LightGpu, p: vec3<f32>, u0: f32, u1: f32) -> vec3<f32> {
    let centre = l.a.xyz;
    let r = l.a.w;
    if (sphere_inward(l)) {
        let z = 1.0 - 2.0 * u0;
        let s = sqrt(max(1.0 - z * z, 0.0));
        let phi = 2.0 * PI * u1;
        return centre + r * vec3<f32>(s * cos(phi), s * sin(phi), z);
    }
    let cone = sphere_cone(l, p);
    let sin2_max = cone.x;
    var sin2: f32;
    var c: f32;
    if (sin2_max < SMALL_CONE) {
        sin2 = sin2_max * u0;
        c = sqrt(1.0 - sin2);
    } else {
        c = 1.0 - u0 * cone.y;
        sin2 = 1.0 - c * c;
    }
    let cos_alpha = sin2 / sqrt(sin2_max) + c * sqrt(max(1.0 - sin2 / sin2_max, 0.0));
    let sin_alpha = sqrt(max(1.0 - cos_alpha * cos_alpha, 0.0));
    let phi = 2.0 * PI * u1;
    let axis = normalize(centre - p);
    let st = orthonormal_pair(axis);
    let n = -(st[0] * (sin_alpha * cos(phi)) + st[1] * (sin_alpha * sin(phi)) + axis * cos_alpha);
    return centre + r * n;
}

// Light::sample_point_li's point of an emitting shape seen from p (w = 0:
// none, the sphere's dark side faces p).
fn shape_light_point(l: LightGpu, p: vec3<f32>, u0: f32, u1: f32) -> vec4<f32> {
    switch l.kind {
        case LIGHT_SPHERE: {
            if (!sphere_sees_front(l, p)) {
                return vec4<f32>(0.0);
            }
            return vec4<f32>(sphere_point(l, p, u0, u1), 1.0);
        }
        case LIGHT_DISK: {
            return vec4<f32>(disk_point(l, u0, u1), 1.0);
        }
        default: {
            return vec4<f32>(triangle_point(l, u0, u1), 1.0);
        }
    }
}

// Light::sample_li for an emitting shape: a point on it, its solid-angle
// pdf and radiance; the shadow ray stops short of the emitter.
fn shape_light_sample(l: LightGpu, p: vec3<f32>, u0: f32, u1: f32) -> LightSample {
    var ls: LightSample;
    ls.is_delta = false;
    ls.valid = false;
    let qv = shape_light_point(l, p, u0, u1);
    if (qv.w == 0.0) {
        return ls;
    }
    let q = qv.xyz;
    let d = q - p;
    let dist = length(d);
    ls.wi = d / dist;
    ls.pdf = shape_pdf_solid(l, p, q, ls.wi);
    ls.radiance = shape_le(l, q, ls.wi);
    ls.distance = dist * (1.0 - SHADOW_SHORTEN);
    ls.valid = dist > 0.0 && ls.pdf > 0.0 && finite(ls.pdf) && any(ls.radiance != vec3<f32>(0.0));
    return ls;
}

// Light::area_factor: |cos θ_q| / |q − p|², the solid angle at p per unit
// area of the shape at its point q.
fn shape_area_factor(l: LightGpu, p: vec3<f32>, q: vec3<f32>) -> f32 {
    var n: vec3<f32>;
    if (l.kind == LIGHT_SPHERE) {
        n = (q - l.a.xyz) / l.a.w;
    } else {
        n = area_normal(l);
    }
    let d = q - p;
    let dist2 = dot(d, d);
    if (!(dist2 > 0.0)) {
        return 0.0;
    }
    return abs(dot(n, d)) / (dist2 * sqrt(dist2));
}

// Light::toward_point: the point q of an emitting shape seen from p in
// q's area measure — the direction, L_e·|cos θ_q|/|q − p|², the shadow
// distance (valid: a finite positive factor).
fn shape_toward_point(l: LightGpu, p: vec3<f32>, q: vec3<f32>) -> LightSample {
    var ls: LightSample;
    ls.is_delta = false;
    ls.pdf = 1.0;
    let g = shape_area_factor(l, p, q);
    ls.valid = g > 0.0 && finite(g);
    if (!ls.valid) {
        return ls;
    }
    let d = q - p;
    let dist = length(d);
    ls.wi = d / dist;
    ls.radiance = shape_le(l, q, ls.wi) * g;
    ls.distance = dist * (1.0 - SHADOW_SHORTEN);
    return ls;
}
