//! A scene's surfaces on the device (bindings 5 and 6 of bind group 2,
//! `wgsl/surfaces.wgsl`): the BVH nodes as the CPU built them, and one
//! `vec4` array holding a header, the bounded-media flags, the shape
//! records with their materials, the triangles in the BVH's leaf order and
//! their shading data, the instance records, and the rough plastics'
//! coating tables. The nodes are the world's hierarchy, each shape group's
//! (in its own space), then the top level over the instances, one after
//! the other; leaf slots (triangle and shading records) likewise.
//!
//! | range | contents |
//! |---|---|
//! | 0 | header: shape records, triangles, shading data (bases), camera medium + 1 |
//! | 1 | `walk` (shadow rays walk surface to surface), shape count, instance records (0: none), the top level's first node |
//! | 2 … | per world medium, 1 when shapes bound it (four per `vec4`) |
//! | shapes | [`SHAPE_STRIDE`] `vec4` per shape: media, lights, flags, emission, two sides of [`crate::contract::SIDE_STRIDE`] |
//! | triangles | per leaf slot three corners; `w`: shape, primitive, passes light (an analytic shape: centre, radius; its primitive with [`PRIMITIVE_ANALYTIC`]) |
//! | shading | per leaf slot four `vec4`: vertex normals and UVs (an analytic shape: its world → object rows, quadric and flip) |
//! | instances | per top-level leaf slot [`INSTANCE_STRIDE`] `vec4`: world → group rows, group → world rows, the group's node and slot bases, mirrors, instance index |
//! | tables | 64 + 1 floats per rough plastic (tabulated transmittance, internal reflectance); bitmap texels (`channels` floats each, rows in file order, padded to a `vec4`) |

use crate::contract::{
    bsdf_id, texture_id, v4, BVH_STACK, INSTANCE_STRIDE, PRIMITIVE_ANALYTIC, SHAPE_STRIDE,
};
use crate::{Gpu, GpuError};
use fogbank_geometry::{Instances, MeshAccel, WideBvh};
use fogbank_render::world::bsdf::{Bsdf, Distribution, Microfacet};
use fogbank_render::world::surfaces::material::Side;
use fogbank_render::world::surfaces::Surfaces;
use fogbank_render::world::texture::Texture;
use fogbank_render::Scene;
use std::collections::HashMap;
use std::sync::Arc;

/// The two buffers, ready to bind.
pub(crate) struct SurfaceBuffers {
    pub(crate) nodes: wgpu::Buffer,
    pub(crate) data: wgpu::Buffer,
}

fn u(x: u32) -> f32 {
    f32::from_bits(x)
}

/// The wide BVH's nodes as the WGSL walk reads them: the CPU's, or for an
/// empty hierarchy one node of zeros (bindings cannot be empty; a node
/// without children hits nothing). Errors when the tree is deeper than the
/// walk's stack ([`BVH_STACK`]) could hold.
pub(crate) fn node_words(accel: &MeshAccel) -> Result<Vec<[u32; 20]>, GpuError> {
    check_depth(accel.wide.depth())?;
    Ok(tree_words(&accel.wide))
}

/// A hierarchy's nodes, or one node of zeros for an empty one.
fn tree_words(wide: &WideBvh) -> Vec<[u32; 20]> {
    match wide.node_words() {
        [] => vec![[0; 20]],
        words => words.to_vec(),
    }
}

/// Errors when a walk `depth` levels deep could overflow the stack.
fn check_depth(depth: usize) -> Result<(), GpuError> {
    if depth > BVH_STACK as usize {
        return Err(GpuError(format!(
            "[[shapes]]: the surfaces' BVH is {depth} levels deep; the GPU's walk holds {BVH_STACK}"
        )));
    }
    Ok(())
}

/// The nodes (as [`node_words`]) and the data array of one scene's surfaces.
pub(crate) type Packed = (Vec<[u32; 20]>, Vec<[f32; 4]>);

/// One hierarchy the walk reads: the world's or a group's, with per
/// primitive its shape, and where its nodes and leaf slots start in the
/// concatenated arrays.
struct Tree<'a> {
    accel: &'a MeshAccel,
    shape_of: &'a [u32],
    node_base: u32,
    slot_base: u32,
}

/// The hierarchies, their nodes one after the other, and where the top
/// level's nodes start.
type Trees<'a> = (Vec<Tree<'a>>, Vec<[u32; 20]>, u32);

/// The world's hierarchy, then each group's, their nodes concatenated;
/// with instances, the top level's nodes last.
fn trees(s: &Surfaces) -> Result<Trees<'_>, GpuError> {
    let mut trees = vec![(s.accel(), s.shape_of())];
    let mut depth = s.accel().wide.depth();
    if let Some((instances, shape_of)) = s.groups() {
        let groups = instances
            .groups
            .iter()
            .map(|g| g.wide.depth())
            .max()
            .unwrap_or(0);
        // The top level's groups, the instance's leaf group, then the group's.
        depth = depth.max(instances.tlas().depth() + 1 + groups);
        trees.extend(
            instances
                .groups
                .iter()
                .zip(shape_of)
                .map(|(g, o)| (g, o.as_slice())),
        );
    }
    check_depth(depth)?;
    let (mut nodes, mut slots, mut out) = (Vec::new(), 0u32, Vec::new());
    for (accel, shape_of) in trees {
        out.push(Tree {
            accel,
            shape_of,
            node_base: nodes.len() as u32,
            slot_base: slots,
        });
        nodes.extend(tree_words(&accel.wide));
        slots += accel.wide.order().len() as u32;
    }
    let tlas_base = nodes.len() as u32;
    if let Some((instances, _)) = s.groups() {
        nodes.extend(tree_words(instances.tlas()));
    }
    Ok((out, nodes, tlas_base))
}

/// The packed nodes and data of `scene`'s surfaces; without any, an empty
/// hierarchy and a header saying there are no shapes.
pub(crate) fn pack(scene: &Scene) -> Result<Packed, GpuError> {
    let Some(s) = scene.world.surfaces.as_ref() else {
        return Ok((vec![[0; 20]], vec![[0.0; 4], [0.0; 4]]));
    };
    let (trees, nodes, tlas_base) = trees(s)?;
    let slots: u32 = trees
        .iter()
        .map(|t| t.accel.wide.order().len() as u32)
        .sum();
    let instance_slots = s.groups().map_or(0, |(i, _)| i.tlas().order().len() as u32);
    let media = scene.world.media.len() as u32;
    let mut data = vec![[0.0f32; 4]; 2 + media.div_ceil(4) as usize];
    for i in 0..media {
        data[2 + i as usize / 4][i as usize % 4] = u(s.bounds_medium(i as usize) as u32);
    }
    let shape_base = data.len() as u32;
    let coating_base = shape_base
        + SHAPE_STRIDE * s.shapes.len() as u32
        + 7 * slots
        + INSTANCE_STRIDE * instance_slots;
    let mut tables = Tables {
        rows: Vec::new(),
        base: coating_base,
        bitmaps: HashMap::new(),
    };
    pack_shapes(s, &mut data, &mut tables);
    let tri_base = data.len() as u32;
    let shading_base = tri_base + 3 * slots;
    for t in &trees {
        pack_primitives(s, t, &mut data);
    }
    for t in &trees {
        pack_shading(t.accel, &mut data);
    }
    let instance_base = data.len() as u32;
    if let Some((instances, _)) = s.groups() {
        pack_instances(instances, &trees, &mut data);
    }
    debug_assert_eq!(data.len() as u32, coating_base);
    data.extend(tables.rows);
    data[0] = [
        u(shape_base),
        u(tri_base),
        u(shading_base),
        u(s.camera_medium.map_or(0, |m| m as u32 + 1)),
    ];
    data[1] = [
        u(s.shadows_walk() as u32),
        u(s.shapes.len() as u32),
        u(if instance_slots > 0 { instance_base } else { 0 }),
        u(tlas_base),
    ];
    Ok((nodes, data))
}

/// Per top-level leaf slot ([`INSTANCE_STRIDE`] vec4s): the instance's
/// world → group rows, group → world rows, and its group's node and slot
/// bases, whether it mirrors, and its index.
fn pack_instances(instances: &Instances, trees: &[Tree], data: &mut Vec<[f32; 4]>) {
    for &i in instances.tlas().order() {
        let inst = &instances.instances[i as usize];
        for m in [inst.to_object, inst.to_world] {
            for r in 0..3 {
                data.push(v4(m.matrix3.row(r).as_vec3(), m.translation[r] as f32));
            }
        }
        // The world's tree is first; group g's is tree g + 1.
        let tree = &trees[inst.group as usize + 1];
        data.push([
            u(tree.node_base),
            u(tree.slot_base),
            u(inst.reflects() as u32),
            u(i),
        ]);
    }
}

/// Per shape (`SHAPE_STRIDE` vec4s): its media, first light and
/// primitive, flags, emission, then its front and back sides.
fn pack_shapes(s: &Surfaces, data: &mut Vec<[f32; 4]>, tables: &mut Tables) {
    for (i, shape) in s.shapes.iter().enumerate() {
        let (normals, uvs) = shape.shading_data();
        let m = &shape.material;
        let flags = normals as u32
            | (uvs as u32) << 1
            | (shape.emission.is_some() as u32) << 2
            | (m.is_null() as u32) << 3
            | (m.back.is_some() as u32) << 4
            | (m.passes_light() as u32) << 5;
        let medium = |m: Option<usize>| m.map_or(0, |w| w as u32 + 1);
        data.push([
            u(medium(shape.interior)),
            u(medium(shape.exterior)),
            u(shape.first_light),
            u(shape.first_triangle),
        ]);
        data.push([u(flags), u(i as u32), 0.0, 0.0]);
        data.push(v4(shape.emission.unwrap_or_default(), 0.0));
        for side in [Some(&m.front), m.back.as_ref()] {
            pack_side(side.unwrap_or(&m.front), data, tables);
        }
    }
}

/// Per primitive of tree `t` in BVH leaf order, three vec4s: a triangle's
/// corners (with its shape, index and whether it passes light), or an
/// analytic shape's centre and radius.
fn pack_primitives(s: &Surfaces, t: &Tree, data: &mut Vec<[f32; 4]>) {
    let accel = t.accel;
    for (slot, &p) in accel.wide.order().iter().enumerate() {
        let corners = accel.leaf_corners()[slot];
        let shape = t.shape_of[p as usize];
        let passes = u(s.shape_passes_light(shape as usize) as u32);
        if let Some(a) = accel.analytic_of(p) {
            // Centre and radius (what hits are put back onto).
            let centre = a.to_world.translation.as_vec3();
            let radius = a.to_world.matrix3.x_axis.length() as f32;
            data.push(v4(centre, u(shape)));
            data.push([radius, 0.0, 0.0, u(p | PRIMITIVE_ANALYTIC)]);
            data.push([0.0, 0.0, 0.0, passes]);
            continue;
        }
        // A non-finite corner: a point, never hit (as on the CPU).
        let finite = corners.iter().all(|p| p.is_finite());
        let w = [u(shape), u(p), passes];
        for k in 0..3 {
            let c = if finite { corners[k] } else { glam::Vec3::ZERO };
            data.push(v4(c, w[k]));
        }
    }
}

/// Per primitive in BVH leaf order, four vec4s: a triangle's vertex
/// normals and uvs, or an analytic shape's world → object rows, quadric
/// and flip.
fn pack_shading(accel: &MeshAccel, data: &mut Vec<[f32; 4]>) {
    let mesh = &accel.mesh;
    for &t in accel.wide.order() {
        if let Some(a) = accel.analytic_of(t) {
            // The world → object map's rows, then the quadric and flip.
            let m = a.to_object;
            for r in 0..3 {
                let row = m.matrix3.row(r).as_vec3();
                data.push(v4(row, m.translation[r] as f32));
            }
            data.push([u(a.quadric as u32), u(a.flip as u32), 0.0, 0.0]);
            continue;
        }
        let tri = mesh.triangles[t as usize];
        let n = |k: usize| {
            mesh.normals
                .get(tri[k] as usize)
                .copied()
                .unwrap_or_default()
        };
        let uv = |k: usize| mesh.uvs.get(tri[k] as usize).copied().unwrap_or_default();
        data.push(v4(n(0), uv(0).x));
        data.push(v4(n(1), uv(0).y));
        data.push(v4(n(2), uv(1).x));
        data.push([uv(1).y, uv(2).x, uv(2).y, 0.0]);
    }
}

/// The tables after the triangles: rough plastics' coating tables and
/// bitmap texels, each bitmap file's texels once however many sides read
/// it (`BitmapFiles` shares them).
struct Tables {
    rows: Vec<[f32; 4]>,
    /// Where `rows` starts in the surface buffer.
    base: u32,
    /// Texel storage (by address) → its offset.
    bitmaps: HashMap<usize, u32>,
}

impl Tables {
    /// Appends `values`, four to a row (the last padded): their offset.
    fn push(&mut self, values: &[f32]) -> u32 {
        let offset = self.base + self.rows.len() as u32;
        self.rows.extend(values.chunks(4).map(|c| {
            let mut v = [0.0; 4];
            v[..c.len()].copy_from_slice(c);
            v
        }));
        offset
    }

    fn texels(&mut self, texels: &Arc<[f32]>) -> u32 {
        let key = Arc::as_ptr(texels) as *const f32 as usize;
        if let Some(&offset) = self.bitmaps.get(&key) {
            return offset;
        }
        let offset = self.push(texels);
        self.bitmaps.insert(key, offset);
        offset
    }
}

/// One side's record: (kind, α, η, flags), parameters a, b, c, texture.
/// Flags: bit 0 nonlinear, bit 1 Beckmann, bit 2 normals not sampled
/// visible, bits 8.. the texture's id.
fn pack_side(side: &Side, data: &mut Vec<[f32; 4]>, tables: &mut Tables) {
    let z = glam::Vec3::ZERO;
    let smooth = Microfacet::ggx(0.0);
    let (mf, eta, nonlinear, a, b, c) = match side.bsdf {
        Bsdf::Diffuse { reflectance } => (smooth, 1.0, false, reflectance, z, [0.0; 4]),
        Bsdf::Conductor {
            eta,
            k,
            mf,
            specular,
        } => (mf, 1.0, false, eta, k, v4(specular, 0.0)),
        Bsdf::Dielectric { eta, mf } => (mf, eta, false, z, z, [0.0; 4]),
        Bsdf::ThinDielectric { eta } => (smooth, eta, false, z, z, [0.0; 4]),
        Bsdf::Plastic(p) => (smooth, p.eta, p.nonlinear, p.diffuse, p.specular, [0.0; 4]),
        Bsdf::RoughPlastic(p) => {
            let (table, internal) = p.coating();
            let offset = tables.push(table);
            (
                p.mf,
                p.eta,
                p.nonlinear,
                p.diffuse,
                p.specular,
                [internal, u(offset), 0.0, 0.0],
            )
        }
        Bsdf::Null => (smooth, 1.0, false, z, z, [0.0; 4]),
    };
    let texture = side.texture.clone().unwrap_or(Texture::Constant(z));
    let beckmann = mf.distribution == Distribution::Beckmann;
    let flags = nonlinear as u32 | (beckmann as u32) << 1 | (!mf.sample_visible as u32) << 2;
    data.push([
        u(bsdf_id(&side.bsdf)),
        mf.alpha,
        eta,
        u(flags | texture_id(&texture) << 8),
    ]);
    data.push(v4(a, 0.0));
    data.push(v4(b, 0.0));
    data.push(c);
    match texture {
        Texture::Checkerboard {
            color0,
            color1,
            to_uv,
        } => {
            let (m, t) = (to_uv.matrix2, to_uv.translation);
            data.push(v4(color0, t.x));
            data.push(v4(color1, t.y));
            data.push([m.x_axis.x, m.x_axis.y, m.y_axis.x, m.y_axis.y]);
        }
        Texture::Bitmap(b) => {
            // Rows 4–6: texel offset, size and t.x; channels, filter and
            // wrap ids and t.y; the linear part of to_uv (as the
            // checkerboard's, so one to_uv reads both).
            let (m, t) = (b.to_uv.matrix2, b.to_uv.translation);
            let offset = tables.texels(&b.texels);
            data.push([u(offset), u(b.width), u(b.height), t.x]);
            let flags = b.channels | b.filter.id() << 2 | b.wrap.id() << 3;
            data.push([u(flags), 0.0, 0.0, t.y]);
            data.push([m.x_axis.x, m.x_axis.y, m.y_axis.x, m.y_axis.y]);
        }
        Texture::Constant(_) => data.extend([[0.0; 4]; 3]),
    }
}

impl SurfaceBuffers {
    pub(crate) fn upload(gpu: &Gpu, scene: &Scene) -> Result<SurfaceBuffers, GpuError> {
        let (nodes, data) = pack(scene)?;
        let limit = gpu.device.limits().max_storage_buffer_binding_size;
        for (what, bytes) in [
            ("BVH nodes", nodes.len() * 80),
            ("surface data", data.len() * 16),
        ] {
            if bytes as u64 > limit {
                return Err(GpuError(format!(
                    "[[shapes]]: {what}: {} MiB exceed the device's storage-buffer limit of {} MiB",
                    bytes >> 20,
                    limit >> 20
                )));
            }
        }
        Ok(SurfaceBuffers {
            nodes: gpu.storage_buffer("bvh_nodes", bytemuck::cast_slice(&nodes)),
            data: gpu.storage_buffer("surface_data", bytemuck::cast_slice(&data)),
        })
    }
}

#[cfg(test)]
mod surfaces_test {
    use super::pack;
    use fogbank_render::{parse_scene, Scene};
    use std::path::Path;

    fn scene(second: &str) -> Scene {
        let tex = "{ type = \"bitmap\", filename = \"mitsuba/textures/tiles_24x16.png\" }";
        let text = format!(
            "[[shapes]]\ntype = \"rectangle\"\nbsdf = {{ type = \"diffuse\", reflectance = {tex} }}\n\
             [[shapes]]\ntype = \"rectangle\"\nto_world = {{ translate = [0.0, 0.0, 1.0] }}\n\
             bsdf = {{ type = \"diffuse\", reflectance = {second} }}\n"
        );
        let base = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes");
        Scene::build(parse_scene(&text, "test", &[]).unwrap(), &base).unwrap()
    }

    /// Two shapes textured by one file upload its texels once: the buffer
    /// is as long as with the second shape untextured.
    #[test]
    fn a_bitmap_file_is_uploaded_once() {
        let shared = scene(
            "{ type = \"bitmap\", filename = \"mitsuba/textures/tiles_24x16.png\", filter_type = \"nearest\" }",
        );
        let plain = scene("0.5");
        let (_, a) = pack(&shared).unwrap();
        let (_, b) = pack(&plain).unwrap();
        assert_eq!(a.len(), b.len());
    }
}
