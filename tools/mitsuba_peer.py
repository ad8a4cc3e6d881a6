#!/usr/bin/env python3
"""Peer check of fogbank `volpath` against Mitsuba 3 `volpath`.

Renders two scenes with both renderers and compares them with fogbank's
per-pixel z-test (`fogbank compare --metric ztest`, Sidak-corrected,
family-wise alpha = 0.01):

  env    a heterogeneous 64^3 grid (Mitsuba .vol, trilinear) in the unit cube
         under a constant environment, isotropic phase;
  point  the same grid lit by a point light, Henyey-Greenstein g = 0.7.

Mitsuba (variant scalar_rgb by default) renders K independent runs of M spp
(seeds 1..K); the script writes their mean and the variance of the mean
(sample variance over runs / K) as an EXR with R, G, B, variance.R/G/B, the
layout fogbank writes, and uses it as the z-test reference. fogbank renders
N spp in one run (its EXR carries the per-pixel variance of the mean).

The scene conventions (cell-centred voxels, camera, filter, depth, lights)
are matched in tools/mitsuba_common.py; the script also checks numerically
that Mitsuba's gridvolume equals fogbank's cell-centred, border-clamped
trilinear interpolant, and, as a negative control, that the z-test rejects
the horizontally mirrored Mitsuba image.

Not part of CI (needs `pip install mitsuba`). Usage:

    cargo build --release -p fogbank-cli
    python3 tools/mitsuba_peer.py [--fogbank target/release/fogbank] [--out DIR]
        [--width 64] [--height 64] [--fogbank-spp 4096] [--runs 128]
        [--run-spp 32] [--threads 2] [--variant scalar_rgb] [--scenes env,point]

Exit status 0 iff every scene passes the z-test (and the mirrored control
fails); writes DIR/peer.json with every number.
"""

import argparse
import json
import os
import subprocess
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mitsuba_common as mc  # noqa: E402


def default_fogbank():
    tgt = os.environ.get("CARGO_TARGET_DIR") or os.path.join(
        os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "target")
    return os.path.join(tgt, "release", "fogbank")


def ztest(fogbank, ref, test):
    out = subprocess.run([fogbank, "compare", ref, test, "--metric", "ztest", "--json"],
                         check=True, capture_output=True, text=True).stdout
    return json.loads(out)["ztest"]


def render_mitsuba_runs(mi, scene_dict, runs, spp):
    import drjit as dr

    scene = mi.load_dict(scene_dict)
    s = s2 = None
    t0 = time.perf_counter()
    for k in range(runs):
        img = np.array(mi.render(scene, seed=k + 1, spp=spp), dtype=np.float64)
        if s is None:
            s, s2 = np.zeros_like(img), np.zeros_like(img)
        s += img
        s2 += img * img
    secs = time.perf_counter() - t0
    mean = s / runs
    var_run = np.maximum(s2 / runs - mean * mean, 0.0) * runs / (runs - 1)
    del dr
    return mean, var_run / runs, secs


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--fogbank", default=default_fogbank())
    ap.add_argument("--out", default="mitsuba_peer_out")
    ap.add_argument("--variant", default="scalar_rgb")
    ap.add_argument("--width", type=int, default=64)
    ap.add_argument("--height", type=int, default=64)
    ap.add_argument("--fogbank-spp", type=int, default=4096)
    ap.add_argument("--runs", type=int, default=128, help="independent Mitsuba runs")
    ap.add_argument("--run-spp", type=int, default=32, help="spp per Mitsuba run")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--scenes", default="env,point")
    ap.add_argument("--estimator", default="ratio_tracking", help="fogbank NEE estimator")
    args = ap.parse_args()

    mi, out, vol, grid = mc.setup_mitsuba(args)
    grid_err = mc.check_grid_convention(mi, vol, grid)
    print(f"gridvolume vs cell-centred clamped trilinear: max |diff| = {grid_err:.2e}")
    report = dict(versions=mc.versions(args.fogbank), threads=args.threads,
                  variant=args.variant, width=args.width, height=args.height,
                  fogbank_spp=args.fogbank_spp, mitsuba_runs=args.runs,
                  mitsuba_run_spp=args.run_spp, grid_convention_max_diff=grid_err,
                  estimator=args.estimator, scenes={})
    ok = grid_err < 1e-4
    for sc in args.scenes.split(","):
        toml = os.path.join(out, f"{sc}.toml")
        with open(toml, "w") as f:
            f.write(mc.fogbank_toml(sc, vol, args.width, args.height, args.fogbank_spp,
                                    seed=1, estimator=args.estimator))
        f_exr = os.path.join(out, f"fogbank_{sc}.exr")
        wall, cpu, st = mc.run_fogbank(args.fogbank, toml, f_exr, args.threads,
                                       stats=os.path.join(out, f"fogbank_{sc}.json"))
        print(f"[{sc}] fogbank {args.fogbank_spp} spp: {wall:.1f} s")
        mean, var, msecs = render_mitsuba_runs(
            mi, mc.mitsuba_dict(mi, sc, vol, args.width, args.height, args.run_spp),
            args.runs, args.run_spp)
        print(f"[{sc}] mitsuba {args.runs} x {args.run_spp} spp: {msecs:.1f} s")
        m_exr = os.path.join(out, f"mitsuba_{sc}.exr")
        mc.write_exr(mi, m_exr, mean, var)
        mirrored = os.path.join(out, f"mitsuba_{sc}_mirrored.exr")
        mc.write_exr(mi, mirrored, mean[:, ::-1], var[:, ::-1])
        zt = ztest(args.fogbank, m_exr, f_exr)
        zt_m = ztest(args.fogbank, mirrored, f_exr)

        # Per-pixel diagnostics in numpy: the fraction of pixel-channel
        # tests beyond the *uncorrected* two-sided 1 % level (|z| > 2.576;
        # about 1 % expected under H0) and beyond the Sidak threshold.
        f_rgb, f_var = mc.read_exr(mi, f_exr)
        v = f_var + var
        mask = v > 0
        z = np.zeros_like(v)
        z[mask] = (f_rgb - mean)[mask] / np.sqrt(v[mask])
        frac_1pct = float(np.mean(np.abs(z[mask]) > 2.5758))
        frac_sidak_px = float(np.mean((np.abs(z) > zt["threshold"]).any(axis=2)))
        rel = float(np.sum(f_rgb - mean) / np.sum(mean))
        print(f"[{sc}] z-test: pass={zt['pass']} failing pixels {zt['failing_pixels']}"
              f"/{args.width * args.height} max|z| {zt['max_abs_z']:.2f} "
              f"(threshold {zt['threshold']:.2f}, {zt['tests']} tests), mean z "
              f"{[round(x, 3) for x in zt['mean_z']]}, |z|>2.576: {100 * frac_1pct:.2f} % "
              f"of tests, relative mean difference {100 * rel:+.3f} %")
        print(f"[{sc}] control (Mitsuba mirrored): pass={zt_m['pass']} failing pixels "
              f"{zt_m['failing_pixels']}")
        report["scenes"][sc] = dict(
            ztest=zt, mirrored_control=dict(pass_=zt_m["pass"],
                                            failing_pixels=zt_m["failing_pixels"]),
            frac_tests_beyond_uncorrected_1pct=frac_1pct,
            frac_pixels_beyond_sidak=frac_sidak_px,
            relative_mean_difference=rel,
            mean_fogbank=f_rgb.mean(axis=(0, 1)).tolist(),
            mean_mitsuba=mean.mean(axis=(0, 1)).tolist(),
            fogbank_seconds=wall, mitsuba_seconds=msecs,
            fogbank_stats=st)
        ok = ok and zt["pass"] and not zt_m["pass"]
    report["pass"] = ok
    with open(os.path.join(out, "peer.json"), "w") as f:
        json.dump(report, f, indent=2)
    print("PASS" if ok else "FAIL")
    sys.exit(0 if ok else 1)


if __name__ == "__main__":
    main()
