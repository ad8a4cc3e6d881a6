//! An external image denoiser, for experiments that compare denoised
//! renders (Lerzer and Dachsbacher 2025, Fig. 6). fogbank does not link a denoiser: the
//! maintained one for path-traced images, Intel Open Image Denoise, is a
//! native library, so an experiment pipes its image through a command
//! instead — by default `python3 tools/denoise.py` (OIDN from the `oidn`
//! wheel), or whatever `FOGBANK_DENOISER` names.
//!
//! Protocol: the command gets `WIDTH HEIGHT` as its last two arguments,
//! reads WIDTH·HEIGHT·3 little-endian f32 (rows top to bottom, RGB) from
//! stdin, writes as many to stdout, and ends stderr with a line
//! `execute_ms <float>` (the filter's own time, without process start).

use std::io::Write;
use std::path::Path;
use std::process::{Command, Stdio};

/// A denoised image and the time the filter itself took.
pub struct Denoised {
    pub rgb: Vec<[f32; 3]>,
    pub execute_ms: f64,
}

/// The denoiser command: `FOGBANK_DENOISER` split on whitespace, or
/// `python3 <repository>/tools/denoise.py`.
pub fn command() -> Vec<String> {
    match std::env::var("FOGBANK_DENOISER") {
        Ok(c) if !c.trim().is_empty() => c.split_whitespace().map(String::from).collect(),
        _ => {
            let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tools/denoise.py");
            vec!["python3".into(), script.display().to_string()]
        }
    }
}

/// Runs the denoiser of [`command`] on `rgb` (`width`×`height`).
pub fn denoise(rgb: &[[f32; 3]], width: u32, height: u32) -> Result<Denoised, String> {
    denoise_with(&command(), rgb, width, height)
}

/// Runs `cmd` on `rgb` (`width`×`height`). Errors name the command and
/// carry its stderr, so a missing OIDN reads as such.
pub fn denoise_with(
    cmd: &[String],
    rgb: &[[f32; 3]],
    width: u32,
    height: u32,
) -> Result<Denoised, String> {
    let n = width as usize * height as usize;
    if rgb.len() != n {
        return Err(format!(
            "denoise: {} pixels for a {width}×{height} image",
            rgb.len()
        ));
    }
    if cmd.is_empty() {
        return Err("denoise: empty denoiser command".into());
    }
    let shown = cmd.join(" ");
    let mut child = Command::new(&cmd[0])
        .args(&cmd[1..])
        .arg(width.to_string())
        .arg(height.to_string())
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| format!("denoiser `{shown}`: {e}"))?;
    let bytes: Vec<u8> = rgb.iter().flatten().flat_map(|v| v.to_le_bytes()).collect();
    // Write from a thread: a denoiser that fails early and closes stdin
    // must not leave us blocked on a full pipe.
    let mut stdin = child.stdin.take().ok_or("denoiser: no stdin")?;
    let writer = std::thread::spawn(move || stdin.write_all(&bytes));
    let out = child
        .wait_with_output()
        .map_err(|e| format!("denoiser `{shown}`: {e}"))?;
    let wrote = writer.join().map_err(|_| "denoiser: writer panicked")?;
    let stderr = String::from_utf8_lossy(&out.stderr);
    if !out.status.success() {
        return Err(format!(
            "denoiser `{shown}` failed ({}): {}",
            out.status,
            stderr.trim()
        ));
    }
    wrote.map_err(|e| format!("denoiser `{shown}`: writing the image: {e}"))?;
    if out.stdout.len() != 12 * n {
        return Err(format!(
            "denoiser `{shown}`: {} bytes back, expected {}",
            out.stdout.len(),
            12 * n
        ));
    }
    let execute_ms = stderr
        .lines()
        .rev()
        .find_map(|l| l.strip_prefix("execute_ms "))
        .and_then(|v| v.trim().parse::<f64>().ok())
        .ok_or_else(|| format!("denoiser `{shown}`: no `execute_ms` line on stderr"))?;
    let f = |c: &[u8]| f32::from_le_bytes([c[0], c[1], c[2], c[3]]);
    let rgb = out
        .stdout
        .chunks_exact(12)
        .map(|p| {
            // A denoiser may emit NaN or negative values; clamp so that no
            // non-finite pixel reaches a file or a metric.
            let c = |i: usize| {
                let v = f(&p[4 * i..4 * i + 4]);
                if v.is_finite() {
                    v.max(0.0)
                } else {
                    0.0
                }
            };
            [c(0), c(1), c(2)]
        })
        .collect();
    Ok(Denoised { rgb, execute_ms })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A stand-in denoiser (`cat`, which echoes the image) exercises the
    /// protocol without OIDN; a failing command reports its stderr.
    #[test]
    fn protocol_round_trip_and_errors() {
        let img: Vec<[f32; 3]> = (0..6).map(|i| [i as f32, 0.5, f32::NAN]).collect();
        let dir = std::env::temp_dir().join(format!("fogbank-denoise-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let ok = dir.join("ok.sh");
        std::fs::write(&ok, "cat\necho execute_ms 1.5 >&2\n").unwrap();
        let bad = dir.join("bad.sh");
        std::fs::write(&bad, "echo no oidn here >&2\nexit 3\n").unwrap();

        let sh = |f: &std::path::Path| vec!["sh".to_string(), f.display().to_string()];
        let d = denoise_with(&sh(&ok), &img, 3, 2).unwrap();
        assert_eq!(d.execute_ms, 1.5);
        assert_eq!(d.rgb[4], [4.0, 0.5, 0.0], "NaN is cleared");

        let e = denoise_with(&sh(&bad), &img, 3, 2).err().unwrap();
        assert!(e.contains("no oidn here"), "{e}");
        assert!(denoise_with(&sh(&ok), &img, 4, 2).is_err(), "size mismatch");
        assert!(denoise_with(&[], &img, 3, 2).is_err());
        std::fs::remove_dir_all(&dir).ok();
    }
}
