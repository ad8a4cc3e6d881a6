// The scene's surfaces as the BVH walk (bvh.wgsl) reads them: the bindings
// of the lights group that hold the hierarchy and the surface records
// (layout: fogbank-gpu's surfaces.rs), each triangle's corners and each
// analytic shape's map.

@group(2) @binding(5) var<storage, read> bvh_nodes: array<vec4<u32>>;
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

// Whether the slot holds an analytic shape: its primitive index (the
// second corner's w) carries PRIMITIVE_ANALYTIC.
fn surface_is_analytic(slot: u32) -> bool {
    return (surface_word(surface_word(0u, 1u) + 3u * slot + 1u, 3u) & PRIMITIVE_ANALYTIC) != 0u;
}

// An analytic slot: its world → object map in the slot's four shading
// records (rows, then quadric and flip), centre and radius in its corners.
fn surface_analytic(slot: u32) -> Analytic {
    let sh = surface_word(0u, 2u) + 4u * slot;
    let c = surface_word(0u, 1u) + 3u * slot;
    let k = surface_data[sh + 3u];
    return Analytic(surface_data[sh], surface_data[sh + 1u], surface_data[sh + 2u],
                    bitcast<u32>(k.x), bitcast<u32>(k.y) != 0u, surface_data[c].xyz,
                    surface_data[c + 1u].x);
}
