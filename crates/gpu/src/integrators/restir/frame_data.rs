//! One frame of a restir sequence on the device (bind groups 0–2): its
//! media with the medium's mips (and a velocity grid's channels), its
//! lights, and its frame uniform (camera, seed, shading estimator), with
//! the velocity the candidate pass moves reprojected points by.

use super::uniform::VelocityGpu;
use crate::accumulation::Frame;
use crate::contract::{gpu_estimator, GpuEstimator};
use crate::lights::LightBuffers;
use crate::scene_buffers::SceneBuffers;
use crate::{Gpu, GpuError};
use fogbank_render::integrators::restir::Restir;
use fogbank_render::integrators::IntegratorKind;
use fogbank_render::world::velocity::Velocity;
use fogbank_render::Scene;

pub(super) fn restir_of(scene: &Scene) -> Result<&Restir, GpuError> {
    match &scene.integrator {
        IntegratorKind::Restir(r) => Ok(r),
        _ => Err(GpuError(
            "the restir kernels render integrator `restir`".into(),
        )),
    }
}

/// The GPU kernel of the scene's final-shading estimator.
pub(super) fn shading_estimator(scene: &Scene) -> Result<GpuEstimator, GpuError> {
    let e = restir_of(scene)?.params.estimator;
    gpu_estimator(e).ok_or_else(|| {
        GpuError(format!(
            "restir: shading estimator `{}` has no GPU kernel",
            e.name()
        ))
    })
}

/// One frame's data on the device: its media (with the mips), lights and
/// camera (bind groups 0–2).
pub struct FrameGpu {
    pub(super) media: SceneBuffers,
    pub(super) lights: LightBuffers,
    pub(super) frame_buf: wgpu::Buffer,
    pub(super) frame_group: wgpu::BindGroup,
    pub(super) frame: Frame,
    pub(super) velocity: VelocityGpu,
}

impl FrameGpu {
    /// Sets the seed the frame's passes key their random numbers with.
    pub fn set_seed(&mut self, gpu: &Gpu, seed: u32) {
        self.frame.seed = seed;
        gpu.queue
            .write_buffer(&self.frame_buf, 0, bytemuck::bytes_of(&self.frame));
    }
}

pub(super) fn upload_frame(
    gpu: &Gpu,
    scene: &Scene,
    frame_layout: &wgpu::BindGroupLayout,
    moments: &wgpu::Buffer,
    lookups: &wgpu::Buffer,
) -> Result<FrameGpu, GpuError> {
    let restir = restir_of(scene)?;
    let frame = Frame::of_scene(scene, &shading_estimator(scene)?);
    let full = &scene.media[0].medium;
    let mut extra: Vec<&fogbank_volume::Medium> =
        (1..=3).map(|l| restir.mips.level(full, l)).collect();
    if restir.params.reuse_bc4 {
        extra.push(restir.mips.reuse(full, restir.params.reuse_mip));
    }
    let sm = &scene.media[0];
    let fields: Vec<&fogbank_render::world::field::Field> = match &sm.velocity {
        Some(Velocity::Grid { field, .. }) => vec![field],
        _ => vec![],
    };
    let media = SceneBuffers::upload_with(gpu, scene, &extra, &fields)?;
    let velocity = VelocityGpu::new(
        sm.velocity.as_ref(),
        media.field_first.first().copied().unwrap_or(0),
        scene.world.frame_dt,
    );
    let lights = LightBuffers::upload(gpu, scene, &restir_of(scene)?.lights, &media.grids)?;
    let frame_buf = gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("frame"),
        size: std::mem::size_of::<Frame>() as u64,
        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    gpu.queue
        .write_buffer(&frame_buf, 0, bytemuck::bytes_of(&frame));
    // ReSTIR reduces into the film itself (shade.wgsl): the chunk slots of
    // the per-sample kernels are bound empty.
    let chunks = gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("accum_chunks (unused)"),
        size: 48,
        usage: wgpu::BufferUsages::STORAGE,
        mapped_at_creation: false,
    });
    let frame_group = gpu.bind_group_of(
        "frame",
        frame_layout,
        &[&frame_buf, moments, lookups, &chunks],
    );
    Ok(FrameGpu {
        media,
        lights,
        frame_buf,
        frame_group,
        frame,
        velocity,
    })
}
