// integrators::shared::balance and next_event::escaped, shared by the
// scattering kernels.

// integrators::shared::balance: the balance-heuristic weight a / (a + b);
// a zero or non-finite sum weighs nothing rather than NaN.
fn balance(a: f32, b: f32) -> f32 {
    let d = a + b;
    if (d > 0.0 && d < F32_INF) {
        return a / d;
    }
    return 0.0;
}

// next_event::escaped; phase_pdf < 0 means a camera ray or a delta lobe,
// `surface` that the direction was sampled at a surface.
fn escaped(d: vec3<f32>, phase_pdf: f32, surface: bool) -> vec3<f32> {
    var l = vec3<f32>(0.0);
    for (var i = 0u; i < env.environments; i++) {
        let light = lights[i];
        if (is_environment(light)) {
            var w = 1.0;
            if (phase_pdf >= 0.0) {
                w = balance(phase_pdf, light_pmf(light, surface) * light_pdf_li(light, d));
            }
            l += light_le(light, d) * w;
        }
    }
    return l;
}
