// PCG32 and PCG3D, bit-identical to fogbank_math::rng so that a pixel's
// random stream on the GPU is the CPU's. WGSL has no 64-bit integers: the
// 64-bit LCG state is a vec2<u32> (x = low word, y = high word).

struct Pcg32 {
    state: vec2<u32>,
    inc: vec2<u32>,
}

fn add64(a: vec2<u32>, b: vec2<u32>) -> vec2<u32> {
    let lo = a.x + b.x;
    let carry = select(0u, 1u, lo < a.x);
    return vec2<u32>(lo, a.y + b.y + carry);
}

// Full 64-bit product of two 32-bit words, from 16-bit halves.
fn mul32x32(a: u32, b: u32) -> vec2<u32> {
    let a0 = a & 0xffffu;
    let a1 = a >> 16u;
    let b0 = b & 0xffffu;
    let b1 = b >> 16u;
    let p00 = a0 * b0;
    let p01 = a0 * b1;
    let p10 = a1 * b0;
    let p11 = a1 * b1;
    let mid = (p00 >> 16u) + (p01 & 0xffffu) + (p10 & 0xffffu);
    let lo = (mid << 16u) | (p00 & 0xffffu);
    let hi = p11 + (p01 >> 16u) + (p10 >> 16u) + (mid >> 16u);
    return vec2<u32>(lo, hi);
}

// Low 64 bits of a 64 × 64-bit product.
fn mul64(a: vec2<u32>, b: vec2<u32>) -> vec2<u32> {
    let p = mul32x32(a.x, b.x);
    return vec2<u32>(p.x, p.y + a.x * b.y + a.y * b.x);
}

// 6364136223846793005 = 0x5851F42D_4C957F2D
const PCG_MULT: vec2<u32> = vec2<u32>(0x4C957F2Du, 0x5851F42Du);

fn pcg32_next_u32(rng: ptr<function, Pcg32>) -> u32 {
    let old = (*rng).state;
    (*rng).state = add64(mul64(old, PCG_MULT), (*rng).inc);
    // ((old >> 18) ^ old) >> 27, low 32 bits
    let s18 = vec2<u32>((old.x >> 18u) | (old.y << 14u), old.y >> 18u);
    let x = vec2<u32>(s18.x ^ old.x, s18.y ^ old.y);
    let xorshifted = (x.x >> 27u) | (x.y << 5u);
    let rot = old.y >> 27u;
    return (xorshifted >> rot) | (xorshifted << ((32u - rot) & 31u));
}

fn pcg32_next_f32(rng: ptr<function, Pcg32>) -> f32 {
    return f32(pcg32_next_u32(rng) >> 8u) * (1.0 / 16777216.0);
}

fn unit_f32(x: u32) -> f32 {
    return f32(x >> 8u) * (1.0 / 16777216.0);
}

fn pcg32_new(init_state: vec2<u32>, init_seq: vec2<u32>) -> Pcg32 {
    var rng: Pcg32;
    rng.state = vec2<u32>(0u, 0u);
    rng.inc = vec2<u32>((init_seq.x << 1u) | 1u, (init_seq.y << 1u) | (init_seq.x >> 31u));
    pcg32_next_u32(&rng);
    rng.state = add64(rng.state, init_state);
    pcg32_next_u32(&rng);
    return rng;
}

fn pcg3d(v: vec3<u32>) -> vec3<u32> {
    var x = v.x * 1664525u + 1013904223u;
    var y = v.y * 1664525u + 1013904223u;
    var z = v.z * 1664525u + 1013904223u;
    x += y * z;
    y += z * x;
    z += x * y;
    x ^= x >> 16u;
    y ^= y >> 16u;
    z ^= z >> 16u;
    x += y * z;
    y += z * x;
    z += x * y;
    return vec3<u32>(x, y, z);
}

// SampleKey { seed, pixel, sample, dimension }.rng()
fn sample_rng(seed: u32, pixel: u32, sample: u32, dimension: u32) -> Pcg32 {
    let h = pcg3d(vec3<u32>(pixel, sample, seed));
    return pcg32_new(vec2<u32>(h.y, h.x), vec2<u32>(dimension, h.z));
}
