#!/usr/bin/env python3
"""Equal-time MSE: fogbank versus Mitsuba 3 `scalar_rgb` and `llvm_ad_rgb`
on the Mitsuba XML scenes of scenes/mitsuba/,
and fogbank's GPU backend (`fogbank_gpu`) versus `cuda_ad_rgb`.

Reference: the high-sample Mitsuba references scenes/mitsuba/refs/<name>.exr
(for a scene given as a path, refs/<name>.exr beside it: scenes/street/refs/)
(R, G, B + variance.R/G/B = variance of the mean, ~2.5e7 samples). The error
of an image is

    MSE = mean over pixels and channels of (img - ref)^2  -  mean(var_ref)

(the second term removes the reference's own noise, so MSE estimates the
image's error against the true expectation).

For each scene and renderer:

1. calibration: fogbank renders at two small spp (t = a + b * spp fitted,
   a = start-up + scene loading); Mitsuba loads the scene once
   (`mi.load_file`, timed), renders once as warm-up (for `llvm_ad_rgb` this
   is the JIT compile; reported as `first render`), then at two small spp
   for the fit;
2. sweep: for each budget T (seconds) the spp with predicted time T, each at
   every seed, records wall time, CPU time and MSE. fogbank is timed as the
   whole `fogbank render` process (start-up, XML + mesh loading, render,
   EXR write); Mitsuba as the `mi.render` call only (scene already loaded,
   kernels already compiled, also the kernel that Dr.Jit's variants
   compile for each new spp: the steady state, favourable to Mitsuba).
   `fogbank_gpu` (`--device gpu`) is timed by its render loop
   (`render_seconds`: after device start-up, upload and pipeline
   compilation), the GPU counterpart of Mitsuba's steady state;
3. equal-time MSE: per renderer, the seed-averaged (time, MSE) points are
   interpolated log-log (extrapolated with MSE ~ 1/t outside the measured
   range) at each budget; ratio = MSE_mitsuba(T) / MSE_fogbank(T). Also
   MSE x seconds per point (constant in the 1/N regime; lower is better).

`llvm_ad_rgb` renders at most --max-lanes samples per `mi.render` call
(wavefront size = pixels x spp); above that the image is the average of
several calls with distinct seeds (all timed).

Both renderers run --threads threads (`fogbank --threads`,
`dr.set_thread_count`). Needs the Mitsuba venv; `llvm_ad_rgb` needs
libLLVM (DRJIT_LIBLLVM_PATH, default /usr/lib/x86_64-linux-gnu/libLLVM-19.so).
Not part of CI. Usage:

    python tools/mitsuba_equal_time.py --fogbank target/release/fogbank \
        [--scenes null_mesh_medium,dielectric_media] \
        [--renderers fogbank,scalar_rgb,llvm_ad_rgb] [--budgets 2,4,8] \
        [--seeds 1,2] [--threads 2] [--out /tmp/equal_time]

Writes OUT/equal_time.json and prints Markdown tables.
"""

import argparse
import json
import os
import resource
import subprocess
import sys
import time

import numpy as np

TOOLS = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(TOOLS)
SCENE_DIR = os.path.join(ROOT, "scenes", "mitsuba")
sys.path.insert(0, TOOLS)
import mitsuba_common as mc  # noqa: E402

DEFAULT_LLVM = "/usr/lib/x86_64-linux-gnu/libLLVM-19.so"


def scene_path(name):
    return name if name.endswith(".xml") else os.path.join(SCENE_DIR, name + ".xml")


def ref_path(name):
    """The reference beside the scene: refs/<name>.exr in the scene's folder."""
    base = os.path.splitext(os.path.basename(name))[0]
    return os.path.join(os.path.dirname(scene_path(name)), "refs", base + ".exr")


def mse_of(img, ref, ref_var):
    return float(np.mean((img - ref) ** 2) - np.mean(ref_var))


def fit_linear(points):
    """points [(spp, seconds)] -> (a, b) of t = a + b * spp (a >= 0)."""
    (s0, t0), (s1, t1) = points
    b = max((t1 - t0) / (s1 - s0), 1e-9)
    a = max(t0 - b * s0, 0.0)
    return a, b


def spp_for(budget, a, b, cal_max, lo=1):
    """The spp of predicted time `budget`, extrapolating at most 64× past the
    largest calibration point (a fit on start-up-dominated points can give a
    slope near zero)."""
    return min(max(lo, int(round((budget - a) / b))), 64 * cal_max)


# ------------------------------------------------------------ Mitsuba worker

def worker(args):
    """Runs in its own process (one Mitsuba variant): prints one JSON line."""
    if args.variant.startswith("llvm"):
        os.environ.setdefault("DRJIT_LIBLLVM_PATH", args.llvm_path)
    import drjit as dr
    import mitsuba as mi

    mi.set_variant(args.variant)
    dr.set_thread_count(args.threads)
    ref, ref_var = mc.read_exr(mi, ref_path(args.scene))
    t0 = time.perf_counter()
    scene = mi.load_file(scene_path(args.scene))
    load_s = time.perf_counter() - t0
    w, h = scene.sensors()[0].film().crop_size()
    pixels = int(w) * int(h)
    max_spp = max(1, args.max_lanes // pixels) if args.variant.startswith("llvm") else 1 << 30

    def render(spp, seed):
        acc, done, k = None, 0, 0
        c0, t0 = time.process_time(), time.perf_counter()
        while done < spp:
            n = min(max_spp, spp - done)
            img = mi.render(scene, spp=n, seed=seed * 1000 + k if k else seed)
            img = np.array(img, dtype=np.float64)  # forces evaluation
            acc = img * n if acc is None else acc + img * n
            done += n
            k += 1
        wall, cpu = time.perf_counter() - t0, time.process_time() - c0
        return acc / spp, wall, cpu, k

    out = dict(variant=args.variant, scene=args.scene, load_s=load_s, pixels=pixels,
               max_spp_per_call=max_spp if max_spp < (1 << 30) else None, points=[])
    # Warm-up (JIT compile for llvm), then a second identical render.
    _, w0, c0, _ = render(args.cal_spp[0], 999)
    _, w1, c1, _ = render(args.cal_spp[0], 998)
    out["first_render"] = dict(spp=args.cal_spp[0], wall=w0, cpu=c0)
    out["second_render"] = dict(spp=args.cal_spp[0], wall=w1, cpu=c1)
    cal = []
    for spp in args.cal_spp:
        _, wall, _, _ = render(spp, 997)
        cal.append((spp, wall))
    a, b = fit_linear(cal)
    out["calibration"] = dict(points=cal, a=a, b=b)
    for budget in args.budgets:
        spp = spp_for(budget, a, b, max(args.cal_spp))
        if not args.variant.startswith("scalar"):
            # Dr.Jit compiles a kernel per spp (it is a literal in the
            # traced program): render once untimed so that every timed
            # render is the steady state.
            render(spp, 990)
        for seed in args.seeds:
            img, wall, cpu, calls = render(spp, seed)
            e = mse_of(img, ref, ref_var)
            out["points"].append(dict(budget=budget, spp=spp, seed=seed, wall=wall, cpu=cpu,
                                      calls=calls, mse=e))
            print(f"  [{args.variant}] {args.scene} {spp} spp seed {seed}: {wall:.2f} s "
                  f"(cpu {cpu:.2f}) MSE {e:.3e}", file=sys.stderr, flush=True)
    out["versions"] = dict(mitsuba=mi.__version__, drjit=dr.__version__)
    print(json.dumps(out), flush=True)


def run_mitsuba(args, variant, scene):
    cmd = [sys.executable, os.path.abspath(__file__), "--worker", "--variant", variant,
           "--scene", scene, "--threads", str(args.threads),
           "--budgets", ",".join(map(str, args.budgets)),
           "--seeds", ",".join(map(str, args.seeds)),
           "--cal-spp", ",".join(map(str, args.cal_spp)),
           "--max-lanes", str(args.max_lanes), "--llvm-path", args.llvm_path]
    env = dict(os.environ)
    if variant.startswith("llvm") and args.cold_jit:
        # Dr.Jit caches compiled kernels in $HOME/.drjit: a fresh HOME makes
        # the first render include the real JIT compile.
        home = os.path.join(args.out, f"home_{variant}_{os.path.basename(scene)}")
        os.makedirs(home, exist_ok=True)
        env["HOME"] = home
    r = subprocess.run(cmd, stdout=subprocess.PIPE, text=True, env=env)
    if r.returncode != 0:
        return dict(variant=variant, scene=scene, error=f"worker exit {r.returncode}")
    return json.loads(r.stdout.strip().splitlines()[-1])


# ------------------------------------------------------------ fogbank

def run_fogbank_once(args, scene, spp, seed, exr, gpu=False):
    cmd = [args.fogbank, "render", scene_path(scene), "--spp", str(spp), "--seed", str(seed),
           "--threads", str(args.threads), "--quiet", "-o", exr, "--stats", exr[:-4] + ".json"]
    if gpu:
        cmd += ["--device", "gpu"]
    for kv in args.fogbank_set:
        cmd += ["--set", kv]
    r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    p = subprocess.run(cmd, capture_output=True, text=True)
    wall = time.perf_counter() - t0
    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    if p.returncode != 0:
        raise RuntimeError(p.stderr.strip())
    cpu = (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime)
    with open(exr[:-4] + ".json") as f:
        st = json.load(f)
    if gpu:  # the render loop, after device start-up, upload and compilation
        wall = st["render_seconds"]
    return wall, cpu, st


def run_fogbank(args, mi, scene, gpu=False):
    ref, ref_var = mc.read_exr(mi, ref_path(scene))
    name = "fogbank_gpu" if gpu else "fogbank"
    d = os.path.join(args.out, name + "_" + os.path.splitext(os.path.basename(scene))[0])
    os.makedirs(d, exist_ok=True)
    out = dict(variant=name, scene=scene, points=[])
    try:
        cal = []
        if gpu:  # an idle GPU runs at a fraction of its clock
            run_fogbank_once(args, scene, args.cal_spp[-1], 996, os.path.join(d, "cal.exr"), gpu)
        for spp in args.cal_spp:
            wall, _, _ = run_fogbank_once(args, scene, spp, 997, os.path.join(d, "cal.exr"), gpu)
            cal.append((spp, wall))
    except RuntimeError as e:
        out["error"] = str(e)
        return out
    a, b = fit_linear(cal)
    out["calibration"] = dict(points=cal, a=a, b=b)
    for budget in args.budgets:
        spp = spp_for(budget, a, b, max(args.cal_spp))
        for seed in args.seeds:
            exr = os.path.join(d, f"spp{spp}_seed{seed}.exr")
            wall, cpu, st = run_fogbank_once(args, scene, spp, seed, exr, gpu)
            img, _ = mc.read_exr(mi, exr)
            e = mse_of(img, ref, ref_var)
            out["points"].append(dict(budget=budget, spp=spp, spp_rendered=st.get("spp"),
                                      seed=seed, wall=wall, cpu=cpu,
                                      render_seconds=st.get("render_seconds"), mse=e))
            print(f"  [{name}] {scene} {spp} spp seed {seed}: {wall:.2f} s (cpu {cpu:.2f}, "
                  f"render {st.get('render_seconds', 0):.2f}) MSE {e:.3e}",
                  file=sys.stderr, flush=True)
    return out


# ------------------------------------------------------------ analysis

def curve(points):
    """Seed-averaged (wall, mse) per spp, sorted by time."""
    by = {}
    for p in points:
        by.setdefault(p["spp"], []).append(p)
    c = []
    for spp, ps in sorted(by.items()):
        c.append((float(np.mean([p["wall"] for p in ps])), float(np.mean([p["mse"] for p in ps]))))
    return sorted(c)


def report(res, budgets, threads):
    lines = []
    for scene, rs in res["scenes"].items():
        lines.append(f"\n### {scene}\n")
        base = next((n for n in rs if n.startswith("fogbank")), "fogbank")
        fb = rs.get(base)
        fbc = curve(fb["points"]) if fb and fb.get("points") else None
        lines.append("| renderer | spp | seed | seconds (wall) | CPU s | MSE | MSE × s |"
                     f" MSE×s / {base}'s |")
        lines.append("|---|---|---|---|---|---|---|---|")
        fb_mxs = {}
        if fb and fb.get("points"):
            for p in fb["points"]:
                fb_mxs.setdefault(p["budget"], []).append(p["mse"] * p["wall"])
        for name, r in rs.items():
            if r.get("error"):
                lines.append(f"| {name} | – | – | – | – | refused: {r['error']} | – | – |")
                continue
            for p in r["points"]:
                mxs = p["mse"] * p["wall"]
                ref_mxs = np.mean(fb_mxs.get(p["budget"], [np.nan]))
                lines.append(f"| {name} | {p['spp']} | {p['seed']} | {p['wall']:.2f} | "
                             f"{p['cpu']:.2f} | {p['mse']:.3e} | {mxs:.3e} | "
                             f"{mxs / ref_mxs:.2f} |")
        lines.append("")
        lines.append("Equal-time MSE (log-log interpolation of the seed-averaged points):\n")
        hdr = "| budget (s) | " + " | ".join(f"{n} MSE" for n in rs) + " | " + \
              " | ".join(f"{n} / {base}" for n in rs if n != base) + " |"
        lines.append(hdr)
        lines.append("|" + "---|" * (1 + len(rs) + len(rs) - 1))
        for T in budgets:
            vals = {}
            for name, r in rs.items():
                vals[name] = mc.mse_at(curve(r["points"]), T) if r.get("points") else None
            fmt = lambda v: "–" if v is None else f"{v:.3e}"  # noqa: E731
            row = f"| {T} | " + " | ".join(fmt(vals[n]) for n in rs) + " | "
            row += " | ".join(
                "–" if vals[n] is None or not vals.get(base) else f"{vals[n] / vals[base]:.2f}"
                for n in rs if n != base) + " |"
            lines.append(row)
        for name, r in rs.items():
            if "first_render" in r:
                lines.append(f"\n{name}: scene load {r['load_s']:.2f} s, first render "
                             f"({r['first_render']['spp']} spp) {r['first_render']['wall']:.2f} s, "
                             f"second {r['second_render']['wall']:.2f} s; fit t = "
                             f"{r['calibration']['a']:.3f} + {r['calibration']['b']:.3e}·spp")
            elif "calibration" in r:
                lines.append(f"\n{name}: fit t = {r['calibration']['a']:.3f} + "
                             f"{r['calibration']['b']:.3e}·spp "
                             f"({'render loop' if name == 'fogbank_gpu' else 'whole process'})")
    return "\n".join(lines)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--fogbank", default=os.path.join(ROOT, "target", "release", "fogbank"))
    ap.add_argument("--scenes", default="null_mesh_medium,dielectric_media")
    ap.add_argument("--renderers", default="fogbank,scalar_rgb,llvm_ad_rgb")
    ap.add_argument("--budgets", default="2,4,8")
    ap.add_argument("--seeds", default="1,2")
    ap.add_argument("--cal-spp", default="32,128")
    ap.add_argument("--warm-jit", dest="cold_jit", action="store_false",
                    help="let llvm_ad_rgb use the user's Dr.Jit kernel cache")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--fogbank-set", action="append", default=[], metavar="KEY=VALUE",
                    help="passed to `fogbank render --set` (repeatable)")
    ap.add_argument("--max-lanes", type=int, default=1 << 22)
    ap.add_argument("--llvm-path", default=os.environ.get("DRJIT_LIBLLVM_PATH", DEFAULT_LLVM))
    ap.add_argument("--out", default="/tmp/equal_time")
    # worker mode
    ap.add_argument("--worker", action="store_true", help=argparse.SUPPRESS)
    ap.add_argument("--variant", help=argparse.SUPPRESS)
    ap.add_argument("--scene", help=argparse.SUPPRESS)
    args = ap.parse_args()
    args.budgets = [float(x) for x in str(args.budgets).split(",")]
    args.seeds = [int(x) for x in str(args.seeds).split(",")]
    args.cal_spp = [int(x) for x in str(args.cal_spp).split(",")]
    if args.worker:
        return worker(args)

    import drjit as dr
    import mitsuba as mi

    # EXR I/O only (a pack for a GPU machine may hold cuda_ad_rgb alone).
    for v in ["scalar_rgb"] + list(mi.variants()):
        try:
            mi.set_variant(v)
            break
        except ImportError:
            continue
    dr.set_thread_count(args.threads)
    os.makedirs(args.out, exist_ok=True)
    args.out = os.path.abspath(args.out)
    res = dict(threads=args.threads, budgets=args.budgets, seeds=args.seeds,
               versions=mc.versions(args.fogbank), scenes={})
    res["versions"]["fogbank_binary"] = args.fogbank
    res["fogbank_set"] = args.fogbank_set
    res["versions"]["fogbank"] = subprocess.run([args.fogbank, "--version"], capture_output=True,
                                                text=True).stdout.strip()
    for scene in args.scenes.split(","):
        res["scenes"][scene] = {}
        for r in args.renderers.split(","):
            print(f"[{scene}] {r}", file=sys.stderr, flush=True)
            if r in ("fogbank", "fogbank_gpu"):
                out = run_fogbank(args, mi, scene, gpu=r == "fogbank_gpu")
            else:
                out = run_mitsuba(args, r, scene)
            res["scenes"][scene][r] = out
            with open(os.path.join(args.out, "equal_time.json"), "w") as f:
                json.dump(res, f, indent=1)
    md = report(res, args.budgets, args.threads)
    with open(os.path.join(args.out, "equal_time.md"), "w") as f:
        f.write(md + "\n")
    print(md)


if __name__ == "__main__":
    main()
