#!/usr/bin/env python3
"""Checks fogbank's FLIP against NVIDIA's reference implementation.

    pip install flip-evaluator numpy
    python3 tools/check_flip.py --generate   # (re)write the fixture pairs and reference means
    python3 tools/check_flip.py              # compare `fogbank compare --metric flip` with them

`--generate` makes small procedural image pairs (LDR PNG and HDR EXR, both
float and half), writes them to crates/image/tests/fixtures/metrics/, asks
`flip_evaluator` for the mean FLIP of each pair, and stores the values in
flip_reference.json there; crates/image/tests/suite/metrics_flip.rs asserts that
ours agrees to 1e-3. Without `--generate` the script runs our implementation
(the fogbank binary, built with cargo unless --fogbank is given) on every
pair and prints both values side by side; it also recomputes the reference
when flip_evaluator is installed.

The images are generated here, with fixed seeds, and written with the small
PNG/EXR writers below so that the script needs nothing beyond numpy.
"""

import argparse
import json
import os
import struct
import subprocess
import sys
import zlib

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
FIXTURES = os.path.join(ROOT, "crates", "image", "tests", "fixtures", "metrics")
REFERENCE_JSON = os.path.join(FIXTURES, "flip_reference.json")


# --- writers -----------------------------------------------------------------

def write_png(path, srgb):
    """8-bit RGB PNG of values in [0, 1] (already sRGB-encoded)."""
    h, w, _ = srgb.shape
    data = np.clip(np.round(srgb * 255.0), 0, 255).astype(np.uint8)
    raw = b"".join(b"\x00" + data[y].tobytes() for y in range(h))

    def chunk(kind, payload):
        body = kind + payload
        return struct.pack(">I", len(payload)) + body + struct.pack(">I", zlib.crc32(body) & 0xFFFFFFFF)

    png = b"\x89PNG\r\n\x1a\n"
    png += chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
    png += chunk(b"IDAT", zlib.compress(raw, 9))
    png += chunk(b"IEND", b"")
    with open(path, "wb") as f:
        f.write(png)


def write_exr(path, rgb, half=False):
    """Uncompressed scanline EXR with channels B, G, R (float or half)."""
    h, w, _ = rgb.shape
    dtype = np.float16 if half else np.float32
    pixel_type = 1 if half else 2

    def attr(name, kind, value):
        return name.encode() + b"\0" + kind.encode() + b"\0" + struct.pack("<i", len(value)) + value

    chlist = b"".join(
        c.encode() + b"\0" + struct.pack("<iB3xii", pixel_type, 0, 1, 1) for c in ("B", "G", "R")
    ) + b"\0"
    box = struct.pack("<iiii", 0, 0, w - 1, h - 1)
    header = b"\x76\x2f\x31\x01" + struct.pack("<i", 2)
    header += attr("channels", "chlist", chlist)
    header += attr("compression", "compression", b"\0")
    header += attr("dataWindow", "box2i", box)
    header += attr("displayWindow", "box2i", box)
    header += attr("lineOrder", "lineOrder", b"\0")
    header += attr("pixelAspectRatio", "float", struct.pack("<f", 1.0))
    header += attr("screenWindowCenter", "v2f", struct.pack("<ff", 0.0, 0.0))
    header += attr("screenWindowWidth", "float", struct.pack("<f", 1.0))
    header += b"\0"
    chunks = []
    for y in range(h):
        line = b"".join(rgb[y, :, c].astype(dtype).astype("<" + np.dtype(dtype).str[1:]).tobytes() for c in (2, 1, 0))
        chunks.append(struct.pack("<ii", y, len(line)) + line)
    offset = len(header) + 8 * h
    table = b""
    for c in chunks:
        table += struct.pack("<Q", offset)
        offset += len(c)
    with open(path, "wb") as f:
        f.write(header + table + b"".join(chunks))


# --- procedural images ---------------------------------------------------------

def base_pattern(w, h, rng):
    """Smooth colour gradients, a sinusoid, hard-edged shapes and fine noise:
    something for every part of FLIP (colour, edges, points)."""
    y, x = np.mgrid[0:h, 0:w].astype(np.float64)
    u, v = x / (w - 1), y / (h - 1)
    img = np.stack([0.15 + 0.7 * u, 0.2 + 0.6 * v, 0.8 - 0.6 * u * v], axis=-1)
    img += 0.15 * np.sin(2 * np.pi * (3 * u + 2 * v))[..., None]
    box = (np.abs(u - 0.3) < 0.12) & (np.abs(v - 0.6) < 0.2)
    img[box] = [0.9, 0.2, 0.1]
    disc = (u - 0.7) ** 2 + (v - 0.35) ** 2 < 0.02
    img[disc] = [0.1, 0.3, 0.85]
    img[h // 2, ::7] = 1.0  # isolated bright points
    img += 0.03 * rng.standard_normal(img.shape)
    return np.clip(img, 0.0, 1.0)


def box_blur(img, r=1):
    out = np.zeros_like(img)
    pad = np.pad(img, ((r, r), (r, r), (0, 0)), mode="edge")
    h, w = img.shape[:2]
    for dy in range(2 * r + 1):
        for dx in range(2 * r + 1):
            out += pad[dy:dy + h, dx:dx + w]
    return out / (2 * r + 1) ** 2


def hdr_scene(w, h, rng):
    """A linear HDR image: sky gradient, a sun of radiance 60, a darker
    cloud-like band with texture, and a few black pixels."""
    y, x = np.mgrid[0:h, 0:w].astype(np.float64)
    u, v = x / (w - 1), y / (h - 1)
    sky = np.stack([0.4 + 0.6 * v, 0.6 + 0.6 * v, 1.2 + 0.8 * v], axis=-1) * 1.5
    cloud = 0.5 + 0.5 * np.sin(9 * u + 4 * np.sin(5 * v)) * np.cos(7 * v)
    band = np.exp(-((v - 0.6) / 0.15) ** 2) * cloud
    img = sky * (1 - 0.8 * band[..., None]) + 0.05 * band[..., None]
    sun = (u - 0.75) ** 2 + (v - 0.2) ** 2 < 0.004
    img[sun] = [60.0, 55.0, 45.0]
    img[h - 3:, :5] = 0.0
    img *= 1 + 0.02 * rng.standard_normal(img.shape)
    return np.maximum(img, 0.0)


def transmittance_scene(w, h, rng):
    """Grey transmittance in [0, 1] in front of a white background, like the
    default fogbank render."""
    y, x = np.mgrid[0:h, 0:w].astype(np.float64)
    u, v = x / (w - 1) - 0.5, y / (h - 1) - 0.5
    tau = 3.0 * np.exp(-(u * u / 0.05 + v * v / 0.03)) * (1 + 0.4 * np.sin(20 * u) * np.sin(17 * v))
    t = np.exp(-np.maximum(tau, 0.0))
    return np.repeat(t[..., None], 3, axis=-1)


def make_pairs():
    """(name, mode, reference file, test file) after writing the images."""
    os.makedirs(FIXTURES, exist_ok=True)
    pairs = []
    rng = np.random.RandomState(2020)

    # LDR: blurred copy (edges and points change, colours barely).
    ref = base_pattern(96, 64, rng)
    write_png(os.path.join(FIXTURES, "ldr_blur_ref.png"), ref)
    write_png(os.path.join(FIXTURES, "ldr_blur_test.png"), box_blur(ref, 1))
    pairs.append(("ldr_blur", "LDR", "ldr_blur_ref.png", "ldr_blur_test.png"))

    # LDR: colour shift plus noise.
    ref = base_pattern(64, 64, rng)
    test = ref * np.array([0.88, 1.0, 1.0]) + np.array([0.0, 0.0, 0.06])
    test = np.clip(test + 0.04 * rng.standard_normal(test.shape), 0.0, 1.0)
    write_png(os.path.join(FIXTURES, "ldr_color_ref.png"), ref)
    write_png(os.path.join(FIXTURES, "ldr_color_test.png"), test)
    pairs.append(("ldr_color", "LDR", "ldr_color_ref.png", "ldr_color_test.png"))

    # HDR (float): Monte-Carlo-like multiplicative noise.
    ref = hdr_scene(96, 72, rng)
    test = np.maximum(ref * (1 + 0.25 * rng.standard_normal(ref.shape)), 0.0)
    write_exr(os.path.join(FIXTURES, "hdr_noise_ref.exr"), ref)
    write_exr(os.path.join(FIXTURES, "hdr_noise_test.exr"), test)
    pairs.append(("hdr_noise", "HDR", "hdr_noise_ref.exr", "hdr_noise_test.exr"))

    # HDR (half): a transmittance image against a 5 % brighter, blurred one.
    ref = transmittance_scene(80, 60, rng)
    test = box_blur(ref * 1.05, 1)
    write_exr(os.path.join(FIXTURES, "hdr_bias_ref.exr"), ref, half=True)
    write_exr(os.path.join(FIXTURES, "hdr_bias_test.exr"), test, half=True)
    pairs.append(("hdr_bias_half", "HDR", "hdr_bias_ref.exr", "hdr_bias_test.exr"))
    return pairs


# --- reference and ours --------------------------------------------------------

def reference_flip(ref_path, test_path, mode):
    import flip_evaluator as flip

    r = flip.load(ref_path)
    t = flip.load(test_path)
    _, mean, params = flip.evaluate(r, t, mode, applyMagma=False)
    return float(mean), params


def ours(fogbank, ref_path, test_path):
    out = subprocess.run(
        fogbank + ["compare", ref_path, test_path, "--metric", "flip", "--json"],
        check=True, capture_output=True, text=True,
    )
    return json.loads(out.stdout)["flip"]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--generate", action="store_true", help="rewrite fixtures and flip_reference.json")
    ap.add_argument("--fogbank", help="path of the fogbank binary (default: cargo run --release)")
    args = ap.parse_args()

    if args.generate:
        import flip_evaluator  # noqa: F401  (fail early when it is missing)
        from importlib.metadata import version

        entries = []
        for name, mode, r, t in make_pairs():
            mean, params = reference_flip(os.path.join(FIXTURES, r), os.path.join(FIXTURES, t), mode)
            e = {"name": name, "mode": mode, "reference": r, "test": t, "mean": mean, "ppd": params["ppd"]}
            if mode == "HDR":
                e.update(start_exposure=params["startExposure"], stop_exposure=params["stopExposure"],
                         num_exposures=params["numExposures"])
            entries.append(e)
        doc = {"generator": "tools/check_flip.py --generate",
               "flip_evaluator_version": version("flip-evaluator"), "pairs": entries}
        with open(REFERENCE_JSON, "w") as f:
            json.dump(doc, f, indent=2)
            f.write("\n")
        print(f"wrote {len(entries)} pairs to {os.path.relpath(REFERENCE_JSON, ROOT)}")
        for e in entries:
            print(f"  {e['name']:<15} {e['mode']}  mean FLIP {e['mean']:.6f}")
        return 0

    with open(REFERENCE_JSON) as f:
        doc = json.load(f)
    fogbank = [args.fogbank] if args.fogbank else ["cargo", "run", "--release", "-q", "-p", "fogbank-cli", "--"]
    try:
        import flip_evaluator  # noqa: F401
        live = True
    except ImportError:
        live = False
    print(f"{'pair':<15} {'mode':<4} {'reference':>10} {'ours':>10} {'|diff|':>9}  exposures (ref | ours)")
    worst = 0.0
    for e in doc["pairs"]:
        r, t = os.path.join(FIXTURES, e["reference"]), os.path.join(FIXTURES, e["test"])
        ref_mean = reference_flip(r, t, e["mode"])[0] if live else e["mean"]
        o = ours(fogbank, r, t)
        diff = abs(o["mean"] - ref_mean)
        worst = max(worst, diff)
        exp = ""
        if e["mode"] == "HDR":
            oe = o.get("exposures") or {}
            exp = (f"[{e['start_exposure']:.4f}, {e['stop_exposure']:.4f}] x{e['num_exposures']} | "
                   f"[{oe.get('start', float('nan')):.4f}, {oe.get('stop', float('nan')):.4f}] x{oe.get('count')}")
        print(f"{e['name']:<15} {e['mode']:<4} {ref_mean:>10.6f} {o['mean']:>10.6f} {diff:>9.2e}  {exp}")
    print(f"largest |ours - reference| = {worst:.2e} ({'ok' if worst <= 1e-3 else 'FAIL'}, tolerance 1e-3)")
    return 0 if worst <= 1e-3 else 1


if __name__ == "__main__":
    sys.exit(main())
