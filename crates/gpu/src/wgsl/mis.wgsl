// integrators::shared::balance: the balance-heuristic weight a / (a + b);
// a zero or non-finite sum weighs nothing rather than NaN.
fn balance(a: f32, b: f32) -> f32 {
    let d = a + b;
    if (d > 0.0 && d < F32_INF) {
        return a / d;
    }
    return 0.0;
}
