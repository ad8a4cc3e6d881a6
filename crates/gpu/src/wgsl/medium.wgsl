// The media of a scene in flat buffers (fogbank_volume's BrickGrid and
// SuperVoxelGrid, concatenated; each medium records its offsets).

struct MediumGpu {
    // Rows of the 3×4 world → index affine map.
    w2i0: vec4<f32>,
    w2i1: vec4<f32>,
    w2i2: vec4<f32>,
    dims: vec3<u32>,
    filter_mode: u32,   // 0 nearest, 1 trilinear, 2 stochastic trilinear
    bdims: vec3<u32>,
    storage: u32,       // 0 f16 (two per word), 1 f32
    sv_dims: vec3<u32>,
    sv_size: f32,
    scale: f32,
    table_offset: u32,
    constants_offset: u32,
    data_offset: u32,   // in 32-bit words
    sv_offset: u32,
    // A post-interpolative transfer function (scene_buffers::pack_transfer):
    // its points in brick_constants, (opacity | colour << 16), emission.
    tf_offset: u32,
    tf_counts: u32,
    tf_emission: u32,
    // The camera position in index space, transformed in f64 on the host
    // exactly as the CPU transforms every primary ray's origin.
    camera_index: vec4<f32>,
}

@group(0) @binding(0) var<storage, read> media: array<MediumGpu>;
@group(0) @binding(1) var<storage, read> brick_table: array<u32>;
@group(0) @binding(2) var<storage, read> brick_constants: array<f32>;
@group(0) @binding(3) var<storage, read> brick_data: array<u32>;
// (min, max, mean, importance) of σ_t per super-voxel.
@group(0) @binding(4) var<storage, read> supervoxels: array<vec4<f32>>;

const CONSTANT_BIT: u32 = 0x80000000u;

// BrickGrid::fetch: clamped voxel value (density, unscaled).
fn fetch(m: MediumGpu, i: i32, j: i32, k: i32) -> f32 {
    let c = vec3<u32>(clamp(vec3<i32>(i, j, k), vec3<i32>(0), vec3<i32>(m.dims) - vec3<i32>(1)));
    let b = ((c.z >> 3u) * m.bdims.y + (c.y >> 3u)) * m.bdims.x + (c.x >> 3u);
    let entry = brick_table[m.table_offset + b];
    if ((entry & CONSTANT_BIT) != 0u) {
        return brick_constants[m.constants_offset + (entry & ~CONSTANT_BIT)];
    }
    let local = ((c.z & 7u) << 6u) | ((c.y & 7u) << 3u) | (c.x & 7u);
    let idx = entry * 512u + local;
    if (m.storage == 0u) {
        let word = brick_data[m.data_offset + (idx >> 1u)];
        return unpack2x16float(word)[idx & 1u];
    }
    return bitcast<f32>(brick_data[m.data_offset + idx]);
}

// math::PiecewiseLinear over brick_constants[offset..]: `count` points of
// `stride` floats, x first. pl_find is partition_point(x <= s) (NaN → 0).
fn pl_find(offset: u32, count: u32, stride: u32, s: f32) -> u32 {
    var lo = 0u;
    var hi = count;
    while (lo < hi) {
        let mid = (lo + hi) / 2u;
        if (brick_constants[offset + mid * stride] <= s) {
            lo = mid + 1u;
        } else {
            hi = mid;
        }
    }
    return lo;
}

// PiecewiseLinear::eval, channel c, at s whose partition point is i:
// clamped outside, each segment clamped to its end values.
fn pl_channel(offset: u32, count: u32, stride: u32, i: u32, c: u32, s: f32) -> f32 {
    if (i == 0u) {
        return brick_constants[offset + 1u + c];
    }
    if (i == count) {
        return brick_constants[offset + (count - 1u) * stride + 1u + c];
    }
    let a = offset + (i - 1u) * stride;
    let b = a + stride;
    let x0 = brick_constants[a];
    let y0 = brick_constants[a + 1u + c];
    let y1 = brick_constants[b + 1u + c];
    let t = (s - x0) / (brick_constants[b] - x0);
    return clamp(y0 + t * (y1 - y0), min(y0, y1), max(y0, y1));
}

fn pl_rgb(offset: u32, count: u32, s: f32) -> vec3<f32> {
    let i = pl_find(offset, count, 4u, s);
    return vec3<f32>(pl_channel(offset, count, 4u, i, 0u, s), pl_channel(offset, count, 4u, i, 1u, s),
                     pl_channel(offset, count, 4u, i, 2u, s));
}

// GridView::classify: the transfer function's opacity α(s), or s itself.
fn classify(m: MediumGpu, s: f32) -> f32 {
    let n = m.tf_counts & 0xffffu;
    if (n == 0u) {
        return s;
    }
    return pl_channel(m.tf_offset, n, 2u, pl_find(m.tf_offset, n, 2u, s), 0u, s);
}

fn nearest(m: MediumGpu, p: vec3<f32>) -> f32 {
    let f = vec3<i32>(floor(p));
    return fetch(m, f.x, f.y, f.z);
}

fn trilinear(m: MediumGpu, p: vec3<f32>) -> f32 {
    let q = p - vec3<f32>(0.5);
    let f = floor(q);
    let w = q - f;
    let i = vec3<i32>(f);
    let c000 = fetch(m, i.x, i.y, i.z);
    let c100 = fetch(m, i.x + 1, i.y, i.z);
    let c010 = fetch(m, i.x, i.y + 1, i.z);
    let c110 = fetch(m, i.x + 1, i.y + 1, i.z);
    let c001 = fetch(m, i.x, i.y, i.z + 1);
    let c101 = fetch(m, i.x + 1, i.y, i.z + 1);
    let c011 = fetch(m, i.x, i.y + 1, i.z + 1);
    let c111 = fetch(m, i.x + 1, i.y + 1, i.z + 1);
    let c00 = c000 + w.x * (c100 - c000);
    let c10 = c010 + w.x * (c110 - c010);
    let c01 = c001 + w.x * (c101 - c001);
    let c11 = c011 + w.x * (c111 - c011);
    let c0 = c00 + w.y * (c10 - c00);
    let c1 = c01 + w.y * (c11 - c01);
    return c0 + w.z * (c1 - c0);
}

// fogbank_estimators::lookup::sigma_t_at: counts the lookup first, then draws
// the stochastic-filter jitter from the lookup count and one random word.
fn sigma_t_at(m: MediumGpu, p: vec3<f32>, rng: ptr<function, Pcg32>, lookups: ptr<function, u32>) -> f32 {
    *lookups += 1u;
    if (m.filter_mode == 2u) {
        let h = pcg3d(vec3<u32>(pcg32_next_u32(rng), *lookups, 0x9e3779b9u));
        let u = vec3<f32>(unit_f32(h.x), unit_f32(h.y), unit_f32(h.z));
        return m.scale * classify(m, nearest(m, p + u - vec3<f32>(0.5)));
    }
    if (m.filter_mode == 1u) {
        return m.scale * classify(m, trilinear(m, p));
    }
    return m.scale * classify(m, nearest(m, p));
}

fn supervoxel(m: MediumGpu, c: vec3<i32>) -> vec4<f32> {
    let u = vec3<u32>(c);
    return supervoxels[m.sv_offset + (u.z * m.sv_dims.y + u.y) * m.sv_dims.x + u.x];
}

struct Ray {
    o: vec3<f32>,
    d: vec3<f32>,
}

fn ray_at(r: Ray, t: f32) -> vec3<f32> {
    return r.o + t * r.d;
}

// Aabb::intersect on [0, hi]: (t0, t1, hit).
fn intersect_box(r: Ray, hi: vec3<f32>, t_lo: f32, t_hi: f32) -> vec3<f32> {
    var t0 = t_lo;
    var t1 = t_hi;
    for (var a = 0; a < 3; a++) {
        let o = r.o[a];
        let d = r.d[a];
        if (d == 0.0) {
            if (o < 0.0 || o > hi[a]) {
                return vec3<f32>(0.0, 0.0, 0.0);
            }
            continue;
        }
        let inv = 1.0 / d;
        let ta = (0.0 - o) * inv;
        let tb = (hi[a] - o) * inv;
        t0 = max(t0, min(ta, tb));
        t1 = min(t1, max(ta, tb));
        if (t0 > t1) {
            return vec3<f32>(0.0, 0.0, 0.0);
        }
    }
    return vec3<f32>(t0, t1, 1.0);
}

// Medium::to_index: the world ray in index space and its range inside the
// medium's box; z = 1 if it meets the box with t1 > t0.
fn to_index(m: MediumGpu, world: Ray, t_max: f32, out_ray: ptr<function, Ray>) -> vec3<f32> {
    let o = vec4<f32>(world.o, 1.0);
    let d = vec4<f32>(world.d, 0.0);
    (*out_ray).o = vec3<f32>(dot(m.w2i0, o), dot(m.w2i1, o), dot(m.w2i2, o));
    return clip_to_box(m, t_max, out_ray, d);
}

// Primary rays: the origin is the camera's, known exactly.
fn to_index_from_camera(m: MediumGpu, world: Ray, t_max: f32, out_ray: ptr<function, Ray>) -> vec3<f32> {
    (*out_ray).o = m.camera_index.xyz;
    return clip_to_box(m, t_max, out_ray, vec4<f32>(world.d, 0.0));
}

fn clip_to_box(m: MediumGpu, t_max: f32, out_ray: ptr<function, Ray>, d: vec4<f32>) -> vec3<f32> {
    (*out_ray).d = vec3<f32>(dot(m.w2i0, d), dot(m.w2i1, d), dot(m.w2i2, d));
    let hit = intersect_box(*out_ray, vec3<f32>(m.dims), 0.0, t_max);
    if (hit.z == 0.0 || !(hit.y > hit.x)) {
        return vec3<f32>(0.0, 0.0, 0.0);
    }
    return hit;
}
