#!/usr/bin/env python3
"""Equal-RMSE benchmark: fogbank `volpath` versus Mitsuba 3 `volpath` (issue 5, item 5).

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
     mitsuba volpath     variant --variant (default scalar_rgb)
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

GPU (issue 21 item 3): --device gpu renders fogbank on the GPU and times it
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
        [--spp-list 16,32,64,128,256,512,1024] [--variant scalar_rgb]
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


def mse(img, ref, ref_var):
    return float(np.mean((img - ref) ** 2) - np.mean(ref_var))


def mitsuba_sweep(mi, scene, spps, gpu):
    """[(spp, wall, cpu, image)] of Mitsuba's render at each spp; on a GPU
    variant each spp renders once untimed first (kernel compilation)."""
    import drjit as dr

    out = []
    for spp in spps:
        if gpu:
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


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--fogbank", default=default_fogbank())
    ap.add_argument("--out", default="mitsuba_bench_out")
    ap.add_argument("--variant", default="scalar_rgb")
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
                    help="fogbank configurations (short names)")
    ap.add_argument("--budgets-ms", default="",
                    help="time budgets (ms) for equal-time MSE ratios")
    args = ap.parse_args()

    mi, out, vol, _grid = mc.setup_mitsuba(args)
    gpu = args.device == "gpu"
    clocks = ("wall",) if gpu else ("cpu", "wall")
    budgets = [float(b) / 1000.0 for b in args.budgets_ms.split(",") if b]
    configs = {n: c for n, c in FOGBANK_CONFIGS.items()
               if n.split()[1] in args.configs.split(",")}
    spps = [int(s) for s in args.spp_list.split(",")]
    m_spps = [int(s) for s in (args.mitsuba_spp_list or args.spp_list).split(",")]
    report = dict(versions=mc.versions(args.fogbank), threads=args.threads,
                  variant=args.variant, width=args.width, height=args.height,
                  device=args.device, ref_device=args.ref_device,
                  ref_spp=args.ref_spp, spp_list=spps, mitsuba_spp_list=m_spps, scenes={})
    rows = []
    for sc in args.scenes.split(","):
        # Reference.
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
            toml = os.path.join(out, f"{sc}_{name.split()[1]}.toml")
            with open(toml, "w") as f:
                f.write(mc.fogbank_toml(sc, vol, args.width, args.height, spps[0], seed=1,
                                        estimator=cfg["estimator"], preset=cfg.get("preset")))
            pts = []
            if gpu:  # an idle GPU runs at a fraction of its clock
                mc.run_fogbank(args.fogbank, toml, os.path.join(out, "warm.exr"), args.threads,
                               spp=spps[-1], device="gpu")
            for spp in spps:
                exr = os.path.join(out, f"{sc}_{name.split()[1]}_{spp}.exr")
                st_path = exr[:-4] + ".json"
                wall, cpu, st = mc.run_fogbank(args.fogbank, toml, exr, args.threads,
                                               spp=spp, stats=st_path, device=args.device)
                if gpu:  # the render loop, after upload and compilation
                    wall = st["render_seconds"]
                img, _ = mc.read_exr(mi, exr)
                e = mse(img, ref, ref_var)
                pts.append(dict(spp=spp, wall=wall, cpu=cpu,
                                render_seconds=st["render_seconds"], mse=e))
                print(f"[{sc}] {name:18s} {spp:6d} spp  wall {wall:7.2f} s  cpu {cpu:7.2f} s"
                      f"  rmse {math.sqrt(max(e, 0)):.4e}")
            curves[name] = pts
        scene = mi.load_dict(mc.mitsuba_dict(mi, sc, vol, args.width, args.height, m_spps[0]))
        pts = []
        for spp, wall, cpu, img in mitsuba_sweep(mi, scene, m_spps,
                                                 args.variant.startswith("cuda")):
            e = mse(img, ref, ref_var)
            pts.append(dict(spp=spp, wall=wall, cpu=cpu, mse=e))
            print(f"[{sc}] {'mitsuba volpath':18s} {spp:6d} spp  wall {wall:7.2f} s  cpu "
                  f"{cpu:7.2f} s  rmse {math.sqrt(max(e, 0)):.4e}")
        mname = f"mitsuba volpath ({args.variant})"
        curves[mname] = pts

        target = max(math.sqrt(max(p[-1]["mse"], 0)) for p in curves.values())
        res = {}
        for name, pts in curves.items():
            r = {}
            r["cpu"] = None
            for clock in clocks:
                r[clock] = time_to([(p[clock], math.sqrt(max(p["mse"], 1e-300)))
                                    for p in pts], target)
            last = pts[-1]
            r["mse_x_cpu_last"] = last["mse"] * last[clocks[0]]
            curve = [(p["wall"], max(p["mse"], 1e-300)) for p in pts]
            r["mse_at_budget"] = {f"{b * 1000:g}": mc.mse_at(curve, b) for b in budgets}
            res[name] = r
        for name, r in res.items():
            ratio_cpu = (res[mname]["cpu"] / r["cpu"]) if r["cpu"] else None
            ratio_wall = (res[mname]["wall"] / r["wall"]) if r["wall"] else None
            r["mitsuba_over_this_cpu"] = ratio_cpu
            r["mitsuba_over_this_wall"] = ratio_wall
            r["mitsuba_mse_over_this_at_budget"] = {
                b: res[mname]["mse_at_budget"][b] / e for b, e in r["mse_at_budget"].items()}
            rows.append(dict(scene=sc, config=name, target_rmse=target,
                             cpu_s=r["cpu"], wall_s=r["wall"],
                             mitsuba_over_this_cpu=ratio_cpu,
                             mitsuba_over_this_wall=ratio_wall,
                             mse_x_cpu_last=r["mse_x_cpu_last"],
                             **{f"mitsuba_mse_over_this_at_{b}ms": v for b, v
                                in r["mitsuba_mse_over_this_at_budget"].items()}))
        report["scenes"][sc] = dict(target_rmse=target, curves=curves, results=res,
                                    reference_noise_rmse=math.sqrt(float(np.mean(ref_var))))
        with open(os.path.join(out, "bench.json"), "w") as f:
            json.dump(report, f, indent=2)

    with open(os.path.join(out, "bench.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    print()
    print(f"threads = {args.threads} (both renderers), {args.width}x{args.height},"
          f" fogbank on {args.device}, Mitsuba {args.variant}")
    print("| scene | configuration | target RMSE | CPU s to target | wall s to target |"
          " Mitsuba / this (CPU) | Mitsuba / this (wall) | MSE x CPU s at max spp |")
    print("|---|---|---|---|---|---|---|---|")
    fmt = lambda v, f: "–" if v is None else format(v, f)  # noqa: E731
    for r in rows:
        print(f"| {r['scene']} | {r['config']} | {r['target_rmse']:.3e} | {fmt(r['cpu_s'], '.2f')}"
              f" | {fmt(r['wall_s'], '.2f')} | {fmt(r['mitsuba_over_this_cpu'], '.2f')}"
              f" | {fmt(r['mitsuba_over_this_wall'], '.2f')} | {r['mse_x_cpu_last']:.3e} |")
    if budgets:
        keys = [k for k in rows[0] if k.startswith("mitsuba_mse_over_this_at_")]
        print()
        print("Equal time: Mitsuba's MSE / this configuration's MSE at each budget")
        print("| scene | configuration | " + " | ".join(k.split("_at_")[1] for k in keys) + " |")
        print("|---|---|" + "---|" * len(keys))
        for r in rows:
            print(f"| {r['scene']} | {r['config']} | "
                  + " | ".join(f"{r[k]:.2f}" for k in keys) + " |")


if __name__ == "__main__":
    main()
