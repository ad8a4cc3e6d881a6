//! The restir kernel without a device: naga's full validation (what
//! pipeline creation checks), and SPIR-V generation of every entry point
//! with the pipeline constant set (what the Vulkan backend does; naga's
//! writer has panicked on constructs the validator accepts, such as a
//! pointer to a struct member passed to a function).

use super::kernels::PASSES;

fn module() -> (naga::Module, naga::valid::ModuleInfo, String) {
    let src = super::source::source();
    let module =
        naga::front::wgsl::parse_str(&src).unwrap_or_else(|e| panic!("{}", e.emit_to_string(&src)));
    let info = naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::all(),
    )
    .validate(&module)
    .unwrap_or_else(|e| panic!("{}", e.emit_to_string(&src)));
    (module, info, src)
}

#[test]
fn restir_kernel_validates() {
    module();
}

#[test]
fn every_restir_pass_compiles_to_spirv() {
    let (module, info, _) = module();
    let mut constants = naga::back::PipelineConstants::default();
    constants.insert("ESTIMATOR".to_string(), 3.0);
    for entry in PASSES {
        let stage = naga::ShaderStage::Compute;
        let (m, i) = naga::back::pipeline_constants::process_overrides(
            &module,
            &info,
            Some((stage, entry)),
            &constants,
        )
        .unwrap();
        let options = naga::back::spv::PipelineOptions {
            shader_stage: stage,
            entry_point: entry.to_string(),
        };
        naga::back::spv::write_vec(&m, &i, &Default::default(), Some(&options))
            .unwrap_or_else(|e| panic!("{entry}: {e}"));
    }
}
