// Diagnostics: closest and any hit of each query ray against one mesh's
// BVH (bvh.wgsl), to compare with fogbank_geometry::MeshAccel ray by ray.
// Per query: [leaf slot of the closest hit (u32 max: none), its t as bits,
// b1 as bits, 1 if the any-hit query found something].

struct BvhQuery {
    // xyz origin, w t_max.
    o: vec4<f32>,
    d: vec4<f32>,
}

@group(0) @binding(0) var<storage, read> bvh_nodes: array<vec4<u32>>;
// Per leaf slot its three corners.
@group(0) @binding(1) var<storage, read> surface_triangles: array<vec4<f32>>;
@group(0) @binding(2) var<storage, read> bvh_queries: array<BvhQuery>;
@group(0) @binding(3) var<storage, read_write> bvh_answers: array<vec4<u32>>;

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if (i >= arrayLength(&bvh_queries)) {
        return;
    }
    let q = bvh_queries[i];
    let c = bvh_trace(q.o.xyz, q.d.xyz, q.o.w, false, false);
    let a = bvh_trace(q.o.xyz, q.d.xyz, q.o.w, true, false);
    bvh_answers[i] = vec4<u32>(c.slot, bitcast<u32>(c.t), bitcast<u32>(c.b1), select(0u, 1u, a.slot != 0xffffffffu));
}

fn surface_corner(slot: u32, k: u32) -> vec3<f32> {
    return surface_triangles[3u * slot + k].xyz;
}

fn surface_passes(slot: u32) -> bool {
    return false;
}

// The queries' meshes are triangles only.
fn surface_is_analytic(slot: u32) -> bool {
    return false;
}

fn surface_analytic(slot: u32) -> Analytic {
    let z = vec4<f32>(0.0);
    return Analytic(z, z, z, 0u, false, z.xyz, 0.0);
}

// The queries' meshes are one hierarchy: no instances.
fn surface_instance_base() -> u32 {
    return 0u;
}

fn surface_tlas_base() -> u32 {
    return 0u;
}

fn instance_bases(i: u32) -> vec2<u32> {
    return vec2<u32>(0u);
}

fn instance_object_ray(i: u32, o: vec3<f32>, d: vec3<f32>) -> WalkRay {
    return walk_ray(o, d);
}
