// Floating-point predicates every kernel shares.

// Finite, decided on the bits: compilers may assume floats are never NaN,
// so `x != x` is no test.
fn finite(x: f32) -> bool {
    return (bitcast<u32>(x) & 0x7f800000u) != 0x7f800000u;
}
