// Bitmap::eval (fogbank-render world/bitmap.rs, Mitsuba 3's `bitmap`):
// texels in the surface data's tables, `channels` floats each, rows in
// file order; Dr.Jit's tex_eval and tex_wrap.

// One float of the surface data, by flat index.
fn surface_float(i: u32) -> f32 {
    return surface_data[i / 4u][i % 4u];
}

// WrapMode::wrap: the texel index of integer coordinate i on a side of n.
fn bitmap_wrap(i: i32, n: i32, mode: u32) -> i32 {
    if (mode == WRAP_CLAMP) {
        return clamp(i, 0, n - 1);
    }
    // Euclidean modulo (WGSL's % keeps the dividend's sign).
    let m = ((i % n) + n) % n;
    if (mode == WRAP_REPEAT) {
        return m;
    }
    let q = (i - m) / n;
    return select(n - 1 - m, m, (q & 1) == 0);
}

// at = (texel offset in vec4s, width, height); flags = channels | filter
// << 2 | wrap << 3.
fn bitmap_texel(at: vec3<u32>, flags: u32, x: i32, y: i32) -> vec3<f32> {
    let wrap = flags >> 3u;
    let channels = flags & 3u;
    let tx = u32(bitmap_wrap(x, i32(at.y), wrap));
    let ty = u32(bitmap_wrap(y, i32(at.z), wrap));
    let i = at.x * 4u + (ty * at.y + tx) * channels;
    if (channels == 1u) {
        return vec3<f32>(surface_float(i));
    }
    return vec3<f32>(surface_float(i), surface_float(i + 1u), surface_float(i + 2u));
}

// Bitmap::eval after to_uv; texel coordinates clamped to ±2^24 as on the CPU.
fn bitmap_eval(at: vec3<u32>, flags: u32, uv: vec2<f32>) -> vec3<f32> {
    let res = vec2<f32>(f32(at.y), f32(at.z));
    let limit = vec2<f32>(16777216.0);
    if (((flags >> 2u) & 1u) == FILTER_NEAREST) {
        let p = floor(clamp(uv * res, -limit, limit));
        return bitmap_texel(at, flags, i32(p.x), i32(p.y));
    }
    let p = clamp(uv * res - 0.5, -limit, limit);
    let f = floor(p);
    let w1 = p - f;
    let w0 = vec2<f32>(1.0) - w1;
    let x = i32(f.x);
    let y = i32(f.y);
    return bitmap_texel(at, flags, x, y) * (w0.x * w0.y)
        + bitmap_texel(at, flags, x + 1, y) * (w1.x * w0.y)
        + bitmap_texel(at, flags, x, y + 1) * (w0.x * w1.y)
        + bitmap_texel(at, flags, x + 1, y + 1) * (w1.x * w1.y);
}
