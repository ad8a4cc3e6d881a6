//! The colour spaces FLIP compares in (Andersson et al. 2020, Sec. 3.1–3.2):
//! linear sRGB ↔ CIE XYZ (D65), XYZ ↔ YCxCz (where its spatial filters
//! apply), CIELab with the Hunt adjustment, and the HyAB distance.

/// An RGB, XYZ, YCxCz or Lab triple.
pub(super) type C3 = [f32; 3];

/// Linear sRGB (D65) to CIE XYZ: the sRGB primaries' matrix, exact rational
/// entries so that white maps to the D65 white point below.
pub(super) fn rgb_to_xyz(c: C3) -> C3 {
    const M: [[f32; 3]; 3] = [
        [
            10135552.0 / 24577794.0,
            8788810.0 / 24577794.0,
            4435075.0 / 24577794.0,
        ],
        [
            2613072.0 / 12288897.0,
            8788810.0 / 12288897.0,
            887015.0 / 12288897.0,
        ],
        [
            1425312.0 / 73733382.0,
            8788810.0 / 73733382.0,
            70074185.0 / 73733382.0,
        ],
    ];
    mat(&M, c)
}

/// The inverse of [`rgb_to_xyz`].
pub(super) fn xyz_to_rgb(c: C3) -> C3 {
    const M: [[f32; 3]; 3] = [
        [3.241_003_3, -1.537_398_9, -0.498_615_9],
        [-0.969_224_3, 1.875_93, 0.041_554_227],
        [0.055_639_42, -0.204_011_2, 1.057_148_9],
    ];
    mat(&M, c)
}

fn mat(m: &[[f32; 3]; 3], c: C3) -> C3 {
    [0, 1, 2].map(|i| m[i][0] * c[0] + m[i][1] * c[1] + m[i][2] * c[2])
}

/// D65 white in XYZ (the row sums of the RGB→XYZ matrix).
const WHITE: C3 = [0.950_428_55, 1.0, 1.088_900_3];

/// XYZ to YCxCz, the linearised CIELab of Zhang & Wandell's S-CIELAB in
/// which FLIP applies its spatial filters (Andersson et al. 2020, Sec. 3.1).
pub(super) fn xyz_to_ycxcz(c: C3) -> C3 {
    let (x, y, z) = (c[0] / WHITE[0], c[1] / WHITE[1], c[2] / WHITE[2]);
    [116.0 * y - 16.0, 500.0 * (x - y), 200.0 * (y - z)]
}

pub(super) fn ycxcz_to_xyz(c: C3) -> C3 {
    let y = (c[0] + 16.0) / 116.0;
    let x = y + c[1] / 500.0;
    let z = y - c[2] / 200.0;
    [x * WHITE[0], y * WHITE[1], z * WHITE[2]]
}

/// CIE 1976 L*a*b* relative to D65.
pub(super) fn xyz_to_lab(c: C3) -> C3 {
    let delta = 6.0f32 / 29.0;
    let f = |t: f32| {
        if t > delta * delta * delta {
            t.powf(1.0 / 3.0)
        } else {
            t / (3.0 * delta * delta) + 4.0 / 29.0
        }
    };
    let (fx, fy, fz) = (f(c[0] / WHITE[0]), f(c[1] / WHITE[1]), f(c[2] / WHITE[2]));
    [116.0 * fy - 16.0, 500.0 * (fx - fy), 200.0 * (fy - fz)]
}

/// Hunt effect: chroma scaled by 0.01·L (Andersson et al. 2020, Eq. 2), so
/// that colour differences shrink in dark regions.
pub(super) fn hunt(lab: C3) -> C3 {
    [lab[0], 0.01 * lab[0] * lab[1], 0.01 * lab[0] * lab[2]]
}

/// HyAB distance: city-block in L, Euclidean in (a, b) (Abasi et al. 2020;
/// Andersson et al. 2020, Eq. 3).
pub(super) fn hyab(p: C3, q: C3) -> f32 {
    (p[0] - q[0]).abs() + ((p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2)).sqrt()
}
