#!/usr/bin/env python3
"""Equal-RMSE benchmark: fogbank `volpath` versus Mitsuba 3 `volpath`.

Same scenes as tools/mitsuba_peer.py (conventions in tools/mitsuba_common.py).
For each scene:

1. Reference: fogbank `volpath` with ratio-tracking NEE at --ref-spp (seed
   1000, unbiased; its agreement with Mitsuba is what mitsuba_peer.py
   checks). Its own noise is removed from every MSE below:
   MSE = mean((img - ref)^2) - mean(var_ref), var_ref from its EXR.
2. Sweep: each configuration renders at spp = --spp-list (seed 1, one
   process per render, --threads T for both renderers):
     fogbank jackknife   estimator = "jackknife" (NEE), delta tracking
     fogbank ratio       estimator = "ratio_tracking" (NEE), delta tracking
     fogbank baseline    preset = "baseline" (decomposition tracking +
                         residual ratio tracking)
     mitsuba volpath     each of --variants (default scalar_rgb; e.g.
                         scalar_rgb,llvm_ad_rgb: all timed in this run)
   and, with --best, fogbank's configuration space: NEE
   estimator (ratio / residual ratio tracking, jackknife) x free-flight
   sampler (delta / decomposition tracking) x super-voxel edge (4, 8, 16);
   the best per scene (least time to the target) is reported against every
   variant. llvm_* variants render each spp once untimed first (Dr.Jit
   compiles per launch shape) and need DRJIT_LIBLLVM_PATH (set to Debian's
   libLLVM-19 when it exists).
   recording wall time and CPU time (fogbank: the whole child process,
   including start-up and loading the grid; Mitsuba: `mi.render` only, the
   scene is loaded once beforehand) and the RMSE against the reference.
3. Time to equal RMSE: the target is the worst final RMSE over the
   configurations (so every one reaches it); each configuration's time to
   reach it is interpolated log-log between the two sweep points around it.
   The ratio Mitsuba/fogbank is reported on CPU time (robust when the
   machine is shared) and on wall time.
4. Equal time (--budgets-ms): each configuration's MSE at each time budget,
   interpolated log-log between its sweep points (MSE ~ 1/time beyond
   them), and Mitsuba's MSE over it.

GPU: --device gpu renders fogbank on the GPU and times it
by the render loop's wall time (`render_seconds` of --stats: after upload
and pipeline compilation, as Mitsuba's time is after a warm-up render that
compiles its kernels); with --variant cuda_ad_rgb Mitsuba runs on the same
GPU, each spp once untimed (Dr.Jit compiles per launch shape) and then
timed up to dr.sync_thread(). Only wall time means anything there.
--ref-device gpu makes the reference on the GPU too.

Not part of CI (needs `pip install mitsuba`). Usage:

    cargo build --release -p fogbank-cli
    python3 tools/mitsuba_bench.py [--fogbank target/release/fogbank] [--out DIR]
        [--scenes point,env] [--threads 1] [--ref-spp 65536]
        [--spp-list 16,32,64,128,256,512,1024] [--variants scalar_rgb,llvm_ad_rgb]
        [--best]
        [--device cpu|gpu] [--ref-device cpu|gpu] [--configs jackknife,ratio,baseline]
        [--budgets-ms 15,25,60]

Writes DIR/bench.json, DIR/bench.csv and prints a Markdown table.
"""

import argparse
import csv
import json
import math
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mitsuba_common as mc  # noqa: E402
from mitsuba_peer import default_fogbank  # noqa: E402

FOGBANK_CONFIGS = {
    "fogbank jackknife": dict(estimator="jackknife"),
    "fogbank ratio": dict(estimator="ratio_tracking"),
    "fogbank baseline": dict(estimator="ratio_tracking", preset="baseline"),
}

# --best: fogbank's configuration space searched for its
# best time to equal RMSE: NEE estimator x distance sampler x super-voxel edge.
BEST_ESTIMATORS = {"rt": "ratio_tracking", "rrt": "residual_ratio_tracking", "jk": "jackknife"}
BEST_SAMPLERS = {"delta": "delta_tracking", "decomp": "decomposition_tracking"}
BEST_SUPERVOXELS = (4, 8, 16)


def best_configs():
    """{name: config} of the --best grid."""
    out = {}
    for en, est in BEST_ESTIMATORS.items():
        for dn, ds in BEST_SAMPLERS.items():
            for sv in BEST_SUPERVOXELS:
                out[f"fogbank {en}-{dn}-sv{sv}"] = dict(
                    estimator=est, extra={"distance_sampler": ds},
                    medium_extra={"supervoxel": sv})
    return out


def mse(img, ref, ref_var):
    return float(np.mean((img - ref) ** 2) - np.mean(ref_var))


def mitsuba_sweep(mi, scene, spps, warm):
    """[(spp, wall, cpu, image)] of Mitsuba's render at each spp; on a JIT
    variant (`warm`: cuda_*, llvm_*) each spp renders once untimed first,
    since Dr.Jit compiles a kernel per launch shape."""
    import drjit as dr

    out = []
    for spp in spps:
        if warm:
            np.array(mi.render(scene, seed=2, spp=spp))
            dr.sync_thread()
        c0, t0 = time.process_time(), time.perf_counter()
        img = mi.render(scene, seed=1, spp=spp)
        dr.sync_thread()
        wall, cpu = time.perf_counter() - t0, time.process_time() - c0
        out.append((spp, wall, cpu, np.array(img, dtype=np.float64)))
    return out


def time_to(points, target):
    """points: [(time, rmse)] by increasing spp; the time at which the RMSE
    first falls to `target`, interpolated log-log between the sweep points
    around it (before the first point: extrapolated with MSE ~ 1/time;
    None if never reached)."""
    t0, e0 = points[0]
    if e0 <= target:
        return t0 * (e0 / target) ** 2
    for (t0, e0), (t1, e1) in zip(points, points[1:]):
        if e1 <= target:
            a = math.log(target / e0) / math.log(e1 / e0)
            return math.exp(math.log(t0) + a * (math.log(t1) - math.log(t0)))
    return None


def fogbank_curve(args, sc, vol, out, name, cfg, spps, ref, ref_var, mi):
    """[{spp, wall, cpu, render_seconds, mse}] of one fogbank configuration."""
    gpu = args.device == "gpu"
    short = name.split()[1]
    toml = os.path.join(out, f"{sc}_{short}.toml")
    with open(toml, "w") as f:
        f.write(mc.fogbank_toml(sc, vol, args.width, args.height, spps[0], seed=1,
                                estimator=cfg["estimator"], preset=cfg.get("preset"),
                                extra=cfg.get("extra"), medium_extra=cfg.get("medium_extra")))
    pts = []
    if gpu:  # an idle GPU runs at a fraction of its clock
        mc.run_fogbank(args.fogbank, toml, os.path.join(out, "warm.exr"), args.threads,
                       spp=spps[-1], device="gpu")
    for spp in spps:
        exr = os.path.join(out, f"{sc}_{short}_{spp}.exr")
        st_path = exr[:-4] + ".json"
        wall, cpu, st = mc.run_fogbank(args.fogbank, toml, exr, args.threads,
                                       spp=spp, stats=st_path, device=args.device)
        if gpu:  # the render loop, after upload and compilation
            wall = st["render_seconds"]
        img, _ = mc.read_exr(mi, exr)
        e = mse(img, ref, ref_var)
        pts.append(dict(spp=spp, wall=wall, cpu=cpu, render_seconds=st["render_seconds"], mse=e))
        print(f"[{sc}] {name:28s} {spp:6d} spp  wall {wall:7.2f} s  cpu {cpu:7.2f} s"
              f"  rmse {math.sqrt(max(e, 0)):.4e}", flush=True)
    return pts


def mitsuba_curve(args, sc, vol, variant, m_spps, ref, ref_var):
    """Switches Mitsuba to `variant` and sweeps it; returns its points."""
    import drjit as dr
    import mitsuba as mi

    mi.set_variant(variant)
    dr.set_thread_count(args.threads)
    scene = mi.load_dict(mc.mitsuba_dict(mi, sc, vol, args.width, args.height, m_spps[0]))
    pts = []
    jit = variant.startswith(("cuda", "llvm"))
    for spp, wall, cpu, img in mitsuba_sweep(mi, scene, m_spps, jit):
        e = mse(img, ref, ref_var)
        pts.append(dict(spp=spp, wall=wall, cpu=cpu, mse=e))
        print(f"[{sc}] {'mitsuba ' + variant:28s} {spp:6d} spp  wall {wall:7.2f} s  cpu "
              f"{cpu:7.2f} s  rmse {math.sqrt(max(e, 0)):.4e}", flush=True)
    return pts


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--fogbank", default=default_fogbank())
    ap.add_argument("--out", default="mitsuba_bench_out")
    ap.add_argument("--variant", default=None, help="one Mitsuba variant (old spelling)")
    ap.add_argument("--variants", default="scalar_rgb",
                    help="Mitsuba variants, comma-separated, all timed in this run")
    ap.add_argument("--scenes", default="point,env")
    ap.add_argument("--width", type=int, default=64)
    ap.add_argument("--height", type=int, default=64)
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--ref-threads", type=int, default=2)
    ap.add_argument("--ref-spp", type=int, default=65536)
    ap.add_argument("--spp-list", default="16,32,64,128,256,512,1024")
    ap.add_argument("--mitsuba-spp-list", default=None,
                    help="Mitsuba's spp list (default: --spp-list)")
    ap.add_argument("--device", default="cpu", choices=["cpu", "gpu"],
                    help="fogbank's device for the sweep")
    ap.add_argument("--ref-device", default="cpu", choices=["cpu", "gpu"])
    ap.add_argument("--configs", default="jackknife,ratio,baseline",
                    help="fogbank configurations (short names; empty for none)")
    ap.add_argument("--best", action="store_true",
                    help="also sweep fogbank's NEE estimator x distance sampler x super-voxel"
                         " grid and report its best configuration per scene")
    ap.add_argument("--budgets-ms", default="",
                    help="time budgets (ms) for equal-time MSE ratios")
    args = ap.parse_args()
    variants = (args.variant or args.variants).split(",")
    args.variant = variants[0]

    mi, out, vol, _grid = mc.setup_mitsuba(args)
    gpu = args.device == "gpu"
    clocks = ("wall",) if gpu else ("cpu", "wall")
    budgets = [float(b) / 1000.0 for b in args.budgets_ms.split(",") if b]
    configs = {n: c for n, c in FOGBANK_CONFIGS.items()
               if n.split()[1] in args.configs.split(",")}
    if args.best:
        configs.update(best_configs())
    spps = [int(s) for s in args.spp_list.split(",")]
    m_spps = [int(s) for s in (args.mitsuba_spp_list or args.spp_list).split(",")]
    mnames = [f"mitsuba volpath ({v})" for v in variants]
    report = dict(versions=mc.versions(args.fogbank), threads=args.threads,
                  variants=variants, width=args.width, height=args.height,
                  device=args.device, ref_device=args.ref_device,
                  ref_spp=args.ref_spp, spp_list=spps, mitsuba_spp_list=m_spps,
                  configs={n: c for n, c in configs.items()}, scenes={})
    rows, best_rows = [], []
    for sc in args.scenes.split(","):
        mi.set_variant(variants[0])
        ref_toml = os.path.join(out, f"{sc}_ref.toml")
        with open(ref_toml, "w") as f:
            f.write(mc.fogbank_toml(sc, vol, args.width, args.height, args.ref_spp, seed=1000))
        ref_exr = os.path.join(out, f"{sc}_ref.exr")
        if not os.path.exists(ref_exr):
            w, c, _ = mc.run_fogbank(args.fogbank, ref_toml, ref_exr, args.ref_threads,
                                     device=args.ref_device)
            print(f"[{sc}] reference {args.ref_spp} spp: {w:.1f} s wall")
        ref, ref_var = mc.read_exr(mi, ref_exr)
        print(f"[{sc}] reference noise RMSE {math.sqrt(np.mean(ref_var)):.3e}")
        curves = {}
        for name, cfg in configs.items():
            curves[name] = fogbank_curve(args, sc, vol, out, name, cfg, spps, ref, ref_var, mi)
        for v, mname in zip(variants, mnames):
            curves[mname] = mitsuba_curve(args, sc, vol, v, m_spps, ref, ref_var)

        target = max(math.sqrt(max(p[-1]["mse"], 0)) for p in curves.values())
        res = {}
        for name, pts in curves.items():
            r = {"cpu": None}
            for clock in clocks:
                r[clock] = time_to([(p[clock], math.sqrt(max(p["mse"], 1e-300)))
                                    for p in pts], target)
            last = pts[-1]
            r["mse_x_cpu_last"] = last["mse"] * last[clocks[0]]
            curve = [(p["wall"], max(p["mse"], 1e-300)) for p in pts]
            r["mse_at_budget"] = {f"{b * 1000:g}": mc.mse_at(curve, b) for b in budgets}
            res[name] = r
        for name, r in res.items():
            row = dict(scene=sc, config=name, target_rmse=target, cpu_s=r["cpu"],
                       wall_s=r["wall"], mse_x_cpu_last=r["mse_x_cpu_last"])
            for v, mname in zip(variants, mnames):
                for clock in ("cpu", "wall"):
                    m, t = res[mname][clock], r[clock]
                    row[f"{v}_over_this_{clock}"] = (m / t) if (m and t) else None
                for b, e in r["mse_at_budget"].items():
                    row[f"{v}_mse_over_this_at_{b}ms"] = res[mname]["mse_at_budget"][b] / e
            r["ratios"] = {k: v for k, v in row.items() if "_over_this_" in k}
            rows.append(row)
        fog = [n for n in configs if res[n][clocks[0]] is not None]
        if fog:
            best = min(fog, key=lambda n: res[n][clocks[0]])
            best_rows.append(next(r for r in rows if r["scene"] == sc and r["config"] == best))
        report["scenes"][sc] = dict(target_rmse=target, curves=curves, results=res,
                                    best=best_rows[-1]["config"] if fog else None,
                                    reference_noise_rmse=math.sqrt(float(np.mean(ref_var))))
        with open(os.path.join(out, "bench.json"), "w") as f:
            json.dump(report, f, indent=2)

    with open(os.path.join(out, "bench.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    print_tables(args, variants, rows, best_rows, budgets)


def print_tables(args, variants, rows, best_rows, budgets):
    fmt = lambda v, f: "–" if v is None else format(v, f)  # noqa: E731
    print()
    print(f"threads = {args.threads} (both renderers), {args.width}x{args.height},"
          f" fogbank on {args.device}, Mitsuba {', '.join(variants)}")
    head = "".join(f" {v} / this (CPU) | {v} / this (wall) |" for v in variants)
    print("| scene | configuration | target RMSE | CPU s to target | wall s to target |" + head
          + " MSE x CPU s at max spp |")
    print("|---|---|---|---|---|" + "---|---|" * len(variants) + "---|")
    for r in rows:
        cells = "".join(f" {fmt(r[f'{v}_over_this_cpu'], '.2f')} |"
                        f" {fmt(r[f'{v}_over_this_wall'], '.2f')} |" for v in variants)
        print(f"| {r['scene']} | {r['config']} | {r['target_rmse']:.3e} | {fmt(r['cpu_s'], '.2f')}"
              f" | {fmt(r['wall_s'], '.2f')} |{cells} {r['mse_x_cpu_last']:.3e} |")
    if best_rows:
        print()
        print("fogbank's best configuration per scene (least time to the target RMSE):")
        print("| scene | configuration | CPU s to target |" + head)
        print("|---|---|---|" + "---|---|" * len(variants))
        for r in best_rows:
            cells = "".join(f" {fmt(r[f'{v}_over_this_cpu'], '.2f')} |"
                            f" {fmt(r[f'{v}_over_this_wall'], '.2f')} |" for v in variants)
            print(f"| {r['scene']} | {r['config']} | {fmt(r['cpu_s'], '.2f')} |{cells}")
    if budgets:
        keys = [k for k in rows[0] if "_mse_over_this_at_" in k]
        print()
        print("Equal time: Mitsuba's MSE / this configuration's MSE at each budget")
        print("| scene | configuration | " + " | ".join(keys) + " |")
        print("|---|---|" + "---|" * len(keys))
        for r in rows:
            print(f"| {r['scene']} | {r['config']} | "
                  + " | ".join(f"{r[k]:.2f}" for k in keys) + " |")


if __name__ == "__main__":
    main()
