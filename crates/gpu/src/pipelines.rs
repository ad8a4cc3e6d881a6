//! Compute pipelines and bind group layouts, each built once per device.
//!
//! Building a pipeline is the costly part of a GPU render that is not the
//! rendering: naga translates the WGSL and the driver compiles it (on
//! lavapipe about 5 s for the scatter kernel and 20 s for ReSTIR's passes,
//! before the JIT compiles each pass at its first dispatch). Renders of the
//! same integrator and options in one process — the viewer's restarts,
//! `bench` and the experiments' repeated runs, the tests — get the same
//! pipeline object back instead.
//!
//! A pipeline is determined by its WGSL source, entry point, pipeline
//! constants and bind group layouts. wgpu compares layouts by object, so
//! layouts are shared too: one object per distinct list of entries.

use std::collections::HashMap;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex, OnceLock};

type Built = Result<wgpu::ComputePipeline, String>;

/// What determines a compute pipeline.
pub struct PipelineSpec<'a> {
    pub label: &'a str,
    /// WGSL, the whole module.
    pub source: &'a str,
    pub entry: &'a str,
    /// Pipeline-overridable constants (`override` in WGSL).
    pub constants: &'a [(&'a str, f64)],
    /// The bind group layouts by group index (from
    /// [`crate::Gpu::bind_group_layout`] for the pipeline to be shared), or `None`
    /// for the layout wgpu derives from the shader.
    pub layouts: Option<&'a [Option<&'a wgpu::BindGroupLayout>]>,
}

#[derive(PartialEq, Eq, Hash)]
struct PipelineKey {
    source: String,
    entry: String,
    /// Names and bit patterns of the constants.
    constants: Vec<(String, u64)>,
    layouts: Option<Vec<Option<wgpu::BindGroupLayout>>>,
}

/// The device's pipelines, layouts and shader modules built so far.
#[derive(Default)]
pub(crate) struct PipelineCache {
    /// One slot per pipeline: threads asking for the same one while it is
    /// being built wait for that build (tests start together); different
    /// pipelines build side by side.
    pipelines: Mutex<HashMap<PipelineKey, Arc<OnceLock<Built>>>>,
    layouts: Mutex<HashMap<Vec<wgpu::BindGroupLayoutEntry>, wgpu::BindGroupLayout>>,
    modules: Mutex<HashMap<String, wgpu::ShaderModule>>,
    built: AtomicU64,
}

impl PipelineCache {
    /// See [`crate::Gpu::bind_group_layout`].
    pub(crate) fn bind_group_layout(
        &self,
        device: &wgpu::Device,
        label: &str,
        entries: &[wgpu::BindGroupLayoutEntry],
    ) -> wgpu::BindGroupLayout {
        let mut layouts = self.layouts.lock().unwrap();
        layouts
            .entry(entries.to_vec())
            .or_insert_with(|| {
                device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                    label: Some(label),
                    entries,
                })
            })
            .clone()
    }

    /// See [`crate::Gpu::compute_pipeline`].
    pub(crate) fn compute_pipeline(
        &self,
        device: &wgpu::Device,
        spec: &PipelineSpec,
    ) -> Result<wgpu::ComputePipeline, String> {
        let key = PipelineKey {
            source: spec.source.to_owned(),
            entry: spec.entry.to_owned(),
            constants: spec
                .constants
                .iter()
                .map(|(n, v)| (n.to_string(), v.to_bits()))
                .collect(),
            layouts: spec
                .layouts
                .map(|ls| ls.iter().map(|l| l.cloned()).collect()),
        };
        let slot = self
            .pipelines
            .lock()
            .unwrap()
            .entry(key)
            .or_default()
            .clone();
        let built = slot.get_or_init(|| {
            self.built.fetch_add(1, Ordering::Relaxed);
            self.build(device, spec)
        });
        if built.is_err() {
            // Not kept: the same request fails again with its message.
            self.pipelines
                .lock()
                .unwrap()
                .retain(|_, s| !Arc::ptr_eq(s, &slot));
        }
        built.clone()
    }

    pub(crate) fn built(&self) -> u64 {
        self.built.load(Ordering::Relaxed)
    }

    fn build(
        &self,
        device: &wgpu::Device,
        spec: &PipelineSpec,
    ) -> Result<wgpu::ComputePipeline, String> {
        let module = self.shader_module(device, spec.label, spec.source)?;
        let layout = spec.layouts.map(|ls| {
            device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some(spec.label),
                bind_group_layouts: ls,
                immediate_size: 0,
            })
        });
        validated(
            device,
            &format!("{} pipeline `{}`", spec.label, spec.entry),
            || {
                device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                    label: Some(spec.label),
                    layout: layout.as_ref(),
                    module: &module,
                    entry_point: Some(spec.entry),
                    compilation_options: wgpu::PipelineCompilationOptions {
                        constants: spec.constants,
                        ..Default::default()
                    },
                    cache: None,
                })
            },
        )
    }

    /// The module of `source`, parsed and validated once.
    fn shader_module(
        &self,
        device: &wgpu::Device,
        label: &str,
        source: &str,
    ) -> Result<wgpu::ShaderModule, String> {
        if let Some(m) = self.modules.lock().unwrap().get(source) {
            return Ok(m.clone());
        }
        let module = validated(device, &format!("{label} kernel"), || {
            device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(label),
                source: wgpu::ShaderSource::Wgsl(source.into()),
            })
        })?;
        let mut modules = self.modules.lock().unwrap();
        Ok(modules.entry(source.to_owned()).or_insert(module).clone())
    }
}

/// Runs `f` (creating shader modules, pipelines) and turns a validation
/// error into an error message naming `what` instead of wgpu's default
/// panic.
pub(crate) fn validated<T>(
    device: &wgpu::Device,
    what: &str,
    f: impl FnOnce() -> T,
) -> Result<T, String> {
    let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
    let out = f();
    match pollster::block_on(scope.pop()) {
        None => Ok(out),
        Some(e) => Err(format!("{what}: {e}")),
    }
}
