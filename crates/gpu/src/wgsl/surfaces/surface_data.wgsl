// The scene's surfaces as the BVH walk (bvh.wgsl) reads them: the bindings
// of the lights group that hold the hierarchy and the surface records
// (layout: fogbank-gpu's surfaces.rs), and each triangle's corners.

@group(2) @binding(5) var<storage, read> bvh_nodes: array<BvhNode>;
@group(2) @binding(6) var<storage, read> surface_data: array<vec4<f32>>;

fn surface_word(i: u32, k: u32) -> u32 {
    return bitcast<u32>(surface_data[i][k]);
}

fn surface_corner(slot: u32, k: u32) -> vec3<f32> {
    return surface_data[surface_word(0u, 1u) + 3u * slot + k].xyz;
}

// Whether light passes straight through the slot's shape (null, thin
// dielectric): the corner records' third w.
fn surface_passes(slot: u32) -> bool {
    return surface_word(surface_word(0u, 1u) + 3u * slot + 2u, 3u) != 0u;
}
