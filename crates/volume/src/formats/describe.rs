//! What `fogbank info` prints the same way for every format: the index →
//! world transform, value ranges. (The brick grid's memory and the pin
//! grid are the caller's [`super::format::Footprint`].)

use fogbank_math::DAffine3;

/// `writeln!` into the description; writing into a `String` cannot fail.
macro_rules! say {
    ($out:expr, $($arg:tt)*) => {{
        let _ = std::fmt::Write::write_fmt($out, format_args!("{}\n", format_args!($($arg)*)));
    }};
}
pub(crate) use say;

pub(crate) fn print_transform(out: &mut String, m: &DAffine3) {
    let c = m.matrix3;
    let t = m.translation;
    say!(out, "  transform (index → world):");
    for r in 0..3 {
        say!(
            out,
            "    [{:>12.6} {:>12.6} {:>12.6} | {:>12.6}]",
            c.x_axis[r],
            c.y_axis[r],
            c.z_axis[r],
            t[r]
        );
    }
}

pub(crate) fn range_and_sum(values: impl Iterator<Item = f32>) -> (f32, f32, f64) {
    values.fold((f32::INFINITY, f32::NEG_INFINITY, 0.0), |(lo, hi, s), v| {
        (lo.min(v), hi.max(v), s + v as f64)
    })
}
