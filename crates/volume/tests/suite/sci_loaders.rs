//! NIfTI and NRRD loaders against the reference tools: the fixtures in
//! `fixtures/sci` were written by nibabel and pynrrd (`make_fixtures.py`),
//! each with the dims, world affine and values those tools read back; one
//! is a real MRI (nibabel's `anatomical.nii`). Malformed input (truncated,
//! corrupted headers) must give errors — never a panic or an allocation
//! out of proportion to the input.

use crate::support;

use fogbank_math::{DAffine3, DVec3};
use fogbank_volume::loaders::{nifti, nrrd, scalar::ScalarVolume};
use std::path::{Path, PathBuf};
use support::{largest, panic_message, Rng};

const FILES: [&str; 6] = [
    "oblique_i16.nii.gz",
    "qform_be_f32.nii",
    "permuted_u16.nii",
    "lps_gzip.nrrd",
    "detached.nhdr",
    "anatomical.nii",
];

fn path(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures/sci")
        .join(name)
}

fn read(name: &str) -> Result<ScalarVolume, String> {
    let p = path(name);
    if name.contains(".nii") {
        nifti::read(&p, 0).map_err(|e| e.to_string())
    } else {
        nrrd::read(&p, 0).map_err(|e| e.to_string())
    }
}

/// `key numbers…` lines of a `.expected` file.
fn expected(name: &str) -> Vec<(String, Vec<f64>)> {
    std::fs::read_to_string(path(&format!("{name}.expected")))
        .unwrap()
        .lines()
        .map(|l| {
            let mut it = l.split_whitespace();
            let k = it.next().unwrap().to_string();
            (k, it.map(|x| x.parse().unwrap()).collect())
        })
        .collect()
}

fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol * (1.0 + b.abs())
}

#[test]
fn fixtures_match_the_reference_tools() {
    for name in FILES {
        let v = read(name).unwrap_or_else(|e| panic!("{e}"));
        // Back from fogbank's cell-centred index to the tools' voxel centres.
        let a = v.index_to_world * DAffine3::from_translation(DVec3::splat(0.5));
        for (k, x) in expected(name) {
            match k.as_str() {
                "dims" => assert_eq!(v.dims.map(f64::from).to_vec(), x, "{name} dims"),
                "affine" => {
                    let m = a.matrix3;
                    let t = a.translation;
                    let ours = [
                        m.x_axis.x, m.y_axis.x, m.z_axis.x, t.x, m.x_axis.y, m.y_axis.y,
                        m.z_axis.y, t.y, m.x_axis.z, m.y_axis.z, m.z_axis.z, t.z,
                    ];
                    for (o, e) in ours.iter().zip(&x) {
                        assert!(close(*o, *e, 1e-5), "{name} affine {ours:?} vs {x:?}");
                    }
                }
                "sum" => {
                    let s: f64 = v.values.iter().map(|&x| x as f64).sum();
                    assert!(close(s, x[0], 1e-6), "{name} sum {s} vs {}", x[0]);
                }
                "min" | "max" => {
                    let (lo, hi) = v.range().unwrap();
                    let ours = if k == "min" { lo } else { hi };
                    assert!(
                        close(ours as f64, x[0], 1e-6),
                        "{name} {k} {ours} vs {}",
                        x[0]
                    );
                }
                "values" => {
                    assert_eq!(v.values.len(), x.len(), "{name}");
                    for (i, (o, e)) in v.values.iter().zip(&x).enumerate() {
                        assert!(close(*o as f64, *e, 1e-6), "{name} value {i}: {o} vs {e}");
                    }
                }
                "voxel" => {
                    let [nx, ny, _] = v.dims.map(|d| d as usize);
                    let (i, j, l) = (x[0] as usize, x[1] as usize, x[2] as usize);
                    let o = v.values[(l * ny + j) * nx + i];
                    assert!(close(o as f64, x[3], 1e-6), "{name} voxel {x:?}: {o}");
                }
                _ => panic!("{name}: unknown key {k}"),
            }
        }
    }
}

#[test]
fn descriptions_name_format_type_and_placement() {
    let v = read("qform_be_f32.nii").unwrap();
    assert!(
        v.description.contains("NIfTI-1")
            && v.description.contains("big")
            && v.description.contains("qform"),
        "{}",
        v.description
    );
    let v = read("permuted_u16.nii").unwrap();
    assert!(
        v.description.contains("NIfTI-2") && v.description.contains("uint16"),
        "{}",
        v.description
    );
    let v = read("oblique_i16.nii.gz").unwrap();
    assert!(v.description.contains("× 0.5 + -10"), "{}", v.description);
    let v = read("lps_gzip.nrrd").unwrap();
    assert!(
        v.description.contains("gzip") && v.description.contains("left-posterior-superior"),
        "{}",
        v.description
    );
    assert_eq!(v.histogram(4).iter().sum::<u64>(), 60);
}

/// The bytes a parser sees for `name` (decompressed) and, for the
/// detached NRRD, its data file.
fn inputs(name: &str) -> (Vec<u8>, Option<Vec<u8>>) {
    let bytes = std::fs::read(path(name)).unwrap();
    if name.contains(".nii") {
        let b = fogbank_volume::loaders::scalar::decompress_if_gzip(&path(name), bytes, 1 << 26)
            .unwrap();
        (b, None)
    } else if name.ends_with(".nhdr") {
        (bytes, Some(std::fs::read(path("detached.raw")).unwrap()))
    } else {
        (bytes, None)
    }
}

fn try_parse(name: &str, bytes: &[u8], data: Option<&[u8]>) -> (Option<String>, bool) {
    let mut ok = false;
    let p = path(name);
    let panic = panic_message(|| {
        ok = if name.contains(".nii") {
            nifti::parse(&p, bytes, None, 0).is_ok()
        } else {
            nrrd::parse(&p, bytes, data, 0).is_ok()
        };
    });
    (panic, ok)
}

#[test]
fn truncated_and_corrupted_input_gives_errors() {
    support::in_own_process(|| {
        let mut failures = Vec::new();
        let mut rng = Rng(0x5C1E_17F1C);
        for name in FILES {
            let (bytes, data) = inputs(name);
            // Every cut of an attached file must fail (the data is needed).
            let step = (bytes.len() / 300).max(1);
            for cut in (0..bytes.len().min(700)).chain((700..bytes.len()).step_by(step)) {
                let (panic, ok) = try_parse(name, &bytes[..cut], data.as_deref());
                if let Some(m) = panic {
                    failures.push(format!("{name} cut at {cut}: panic {m}"));
                } else if ok && data.is_none() {
                    failures.push(format!("{name} cut at {cut} parsed"));
                }
            }
            if let Some(d) = &data {
                let (panic, ok) = try_parse(name, &bytes, Some(&d[..d.len() - 1]));
                assert!(panic.is_none() && !ok, "{name}: short data file parsed");
            }
            // Random flips in the header area, and every header byte set to
            // 0xFF and to '9' (a digit makes NRRD sizes huge).
            let head = bytes.len().min(600);
            for round in 0..600 {
                let mut b = bytes.clone();
                for _ in 0..1 + rng.next() % 4 {
                    let at = (rng.next() as usize) % head;
                    b[at] ^= 1 << (rng.next() % 8);
                }
                if let Some(m) = try_parse(name, &b, data.as_deref()).0 {
                    failures.push(format!("{name} round {round}: panic {m}"));
                }
            }
            for at in 0..head {
                for v in [0xFF, b'9'] {
                    let mut b = bytes.clone();
                    b[at] = v;
                    if let Some(m) = try_parse(name, &b, data.as_deref()).0 {
                        failures.push(format!("{name} byte {at} = {v:#x}: panic {m}"));
                    }
                }
            }
        }
        assert!(
            failures.is_empty(),
            "{}",
            failures[..failures.len().min(20)].join("\n")
        );
        let largest = largest();
        assert!(largest <= 16 << 20, "largest allocation {largest} bytes");
    });
}

#[test]
fn errors_name_the_file_and_the_field() {
    let p = path("qform_be_f32.nii");
    let mut b = std::fs::read(&p).unwrap();
    // datatype (big-endian i16 at byte 70) → 32, complex64.
    b[70] = 0;
    b[71] = 32;
    let e = nifti::parse(&p, &b, None, 0).unwrap_err().to_string();
    assert!(
        e.contains("qform_be_f32.nii") && e.contains("datatype 32"),
        "{e}"
    );
    let e = nifti::read(&path("anatomical.nii"), 3)
        .unwrap_err()
        .to_string();
    assert!(e.contains("volume index 3"), "{e}");
    let p = path("lps_gzip.nrrd");
    let text = std::fs::read(&p).unwrap();
    let s = String::from_utf8_lossy(&text).replace("sizes: 5 4 3", "sizes: 5 4");
    let e = nrrd::parse(&p, s.as_bytes(), None, 0)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("lps_gzip.nrrd") && e.contains("`sizes` has 2 entries"),
        "{e}"
    );
}

/// Inputs the fuzzers (`fuzz/`, targets `nifti` and `nrrd`) found crashing,
/// kept in `fixtures/sci/fuzz/`: each now gives an error, never a panic.
#[test]
fn fuzz_regressions_give_errors() {
    let dir = path("fuzz");
    let mut n = 0;
    for e in std::fs::read_dir(&dir).unwrap() {
        let p = e.unwrap().path();
        let name = format!("fuzz/{}", p.file_name().unwrap().to_str().unwrap());
        let bytes = std::fs::read(&p).unwrap();
        for data in [None, Some(bytes.as_slice())] {
            let panic = panic_message(|| {
                let _ = if name.contains(".nii") {
                    nifti::parse(&p, &bytes, data, 1)
                } else {
                    nrrd::parse(&p, &bytes, data, 1)
                };
            });
            assert_eq!(panic, None, "{name}");
        }
        n += 1;
    }
    assert!(n >= 1);
}
