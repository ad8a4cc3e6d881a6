// Floating-point predicates every kernel shares.

// Finite, decided on the bits: compilers may assume floats are never NaN,
// so `x != x` is no test.
fn finite(x: f32) -> bool {
    return (bitcast<u32>(x) & 0x7f800000u) != 0x7f800000u;
}

// The null-collision probability 1 − σ_t/σ̄ of ratio tracking, exactly 0
// when σ_t = σ̄ as the CPU's correctly rounded division gives: Vulkan's
// division may be 2.5 ulp off, and on an H100 x/x left a weight of ~1e-7
// that kept tight-majorant walks (one-voxel super-voxels, nearest filter)
// reading the grid after the CPU's had stopped.
fn null_probability(sigma_t: f32, sigma_maj: f32) -> f32 {
    return select(1.0 - sigma_t / sigma_maj, 0.0, sigma_t == sigma_maj);
}
