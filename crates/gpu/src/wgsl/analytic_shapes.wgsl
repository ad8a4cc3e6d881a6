// Analytic spheres and disks (fogbank_geometry::analytic): the unit shape
// under an affine map, intersected in object space. WGSL has no f64: the
// sphere's quadratic keeps the cancellation-free form of Haines et al.
// (Ray Tracing Gems, ch. 7) in f32, so distant rays lose a little more
// precision than on the CPU.

struct Analytic {
    // World → object: rows of the linear map, w the translation.
    r0: vec4<f32>,
    r1: vec4<f32>,
    r2: vec4<f32>,
    quadric: u32,
    flip: bool,
    // World-space centre and (sphere) radius, to put hits back on it.
    centre: vec3<f32>,
    radius: f32,
}

fn analytic_point(a: Analytic, p: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(dot(a.r0.xyz, p) + a.r0.w, dot(a.r1.xyz, p) + a.r1.w, dot(a.r2.xyz, p) + a.r2.w);
}

fn analytic_vector(a: Analytic, v: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(dot(a.r0.xyz, v), dot(a.r1.xyz, v), dot(a.r2.xyz, v));
}

// AnalyticShape::intersect: the nearest hit in (0, t_max) (b1 = b2 = 0).
fn intersect_analytic(a: Analytic, o_world: vec3<f32>, d_world: vec3<f32>, t_max: f32) -> TriHit {
    let none = TriHit(false, 0.0, 0.0, 0.0);
    let o = analytic_point(a, o_world);
    let d = analytic_vector(a, d_world);
    var t = -1.0;
    if (a.quadric == QUADRIC_SPHERE) {
        let qa = dot(d, d);
        if (qa == 0.0) {
            return none;
        }
        let b = -dot(o, d);
        let perp = o + (b / qa) * d;
        let disc = qa * (1.0 - dot(perp, perp));
        if (disc < 0.0) {
            return none;
        }
        let q = b + select(-1.0, 1.0, b >= 0.0) * sqrt(disc);
        let c = dot(o, o) - 1.0;
        var t0 = 0.0;
        var t1 = 0.0;
        if (q != 0.0) {
            t0 = min(c / q, q / qa);
            t1 = max(c / q, q / qa);
        }
        if (t0 > 0.0 && t0 < t_max) {
            t = t0;
        } else if (t1 > 0.0 && t1 < t_max) {
            t = t1;
        }
    } else {
        if (d.z == 0.0) {
            return none;
        }
        let td = -o.z / d.z;
        let p = o + td * d;
        if (td > 0.0 && td < t_max && p.x * p.x + p.y * p.y <= 1.0) {
            t = td;
        }
    }
    if (t <= 0.0) {
        return none;
    }
    return TriHit(true, t, 0.0, 0.0);
}

struct AnalyticHit {
    p: vec3<f32>,
    n: vec3<f32>,
    uv: vec2<f32>,
}

// φ/2π in [0, 1) of an object-space point.
fn analytic_azimuth(p: vec3<f32>) -> f32 {
    let v = atan2(p.y, p.x) / (2.0 * 3.141592653589793);
    return select(v, v + 1.0, v < 0.0);
}

// AnalyticShape::hit: the point put back on the surface, the normal (by
// the inverse transpose, flipped with `flip`), Mitsuba's UVs.
fn analytic_hit(a: Analytic, o_world: vec3<f32>, d_world: vec3<f32>, t: f32) -> AnalyticHit {
    var local = analytic_point(a, o_world) + t * analytic_vector(a, d_world);
    var h: AnalyticHit;
    var n_object = vec3<f32>(0.0, 0.0, 1.0);
    h.p = o_world + t * d_world;
    if (a.quadric == QUADRIC_SPHERE) {
        local = normalize(local);
        n_object = local;
        h.uv = vec2<f32>(analytic_azimuth(local), acos(clamp(local.z, -1.0, 1.0)) / 3.141592653589793);
    } else {
        h.uv = vec2<f32>(length(local.xy), analytic_azimuth(local));
    }
    let n = a.r0.xyz * n_object.x + a.r1.xyz * n_object.y + a.r2.xyz * n_object.z;
    h.n = normalize(n) * select(1.0, -1.0, a.flip);
    if (a.quadric == QUADRIC_SPHERE) {
        h.p = a.centre + a.radius * normalize(n);
    }
    return h;
}
