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

// Where the instance records start (0: no instances) and the top level's
// first node.
fn surface_instance_base() -> u32 {
    return surface_word(1u, 2u);
}

fn surface_tlas_base() -> u32 {
    return surface_word(1u, 3u);
}

fn instance_record(i: u32) -> u32 {
    return surface_instance_base() + INSTANCE_STRIDE * i;
}

// The instance's group's first node and leaf slot.
fn instance_bases(i: u32) -> vec2<u32> {
    let b = instance_record(i);
    return vec2<u32>(surface_word(b + 6u, 0u), surface_word(b + 6u, 1u));
}

// An affine map stored as three rows (xyz linear, w translation) from
// `base`, applied to a point and to a vector.
fn affine_point(base: u32, p: vec3<f32>) -> vec3<f32> {
    let r0 = surface_data[base];
    let r1 = surface_data[base + 1u];
    let r2 = surface_data[base + 2u];
    return vec3<f32>(dot(r0.xyz, p) + r0.w, dot(r1.xyz, p) + r1.w, dot(r2.xyz, p) + r2.w);
}

fn affine_vector(base: u32, v: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(dot(surface_data[base].xyz, v), dot(surface_data[base + 1u].xyz, v),
                     dot(surface_data[base + 2u].xyz, v));
}

// Instance::object_ray: the ray in the group's space (direction not
// renormalised: the same t reaches the same point).
fn instance_object_ray(i: u32, o: vec3<f32>, d: vec3<f32>) -> WalkRay {
    let b = instance_record(i);
    return walk_ray(affine_point(b, o), affine_vector(b, d));
}
