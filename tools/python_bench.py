#!/usr/bin/env python3
"""The Python package against the command, measured side by side in one
run (docs/results/python.md):

1. render: `fogbank.render(scene, spp)` in a fresh interpreter against
   `fogbank render SCENE --spp N`, alternating A B A B…, whole processes
   (wall time, start-up included) and the render loop alone (both report
   `render_seconds` in their statistics);
2. transmittance: `fogbank.transmittance` on the camera rays of `fogbank
   bench`'s cloud (256³ procedural cumulus, σ_t scale 60, stochastic
   trilinear, 512² rays × 4 estimates per ray = 1 048 576) against `fogbank
   bench`'s Mrays/s for the same estimator, medium and thread count.

Usage: tools/python_bench.py --python v/bin/python --cli target/release/fogbank
       [--rounds 5] [--threads 2]
Both should be release builds (`pip install ./python`, `cargo build --release`).
"""

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time

SCENES = {
    "default scene": [],
    "scenes/smoke.toml (dragon VDB)": ["scenes/smoke.toml"],
}

CLOUD = {
    "camera": {"from": [0.0, 0.05, 2.2], "to": [0.0, -0.05, 0.0], "fov": 32.0, "width": 512, "height": 512},
    "media": [{"density": {"procedural": "cloud", "resolution": 256, "seed": 7}, "sigma_t_scale": 60.0,
               "filter": "stochastic_trilinear"}],
}

PY_RENDER = """
import json, sys, fogbank
args = json.loads(sys.argv[1])
s = fogbank.load(args["scene"]) if args["scene"] else fogbank.default_scene()
img = fogbank.render(s, spp=args["spp"], threads=args["threads"], progress=False)
img.save(args["out"])
print(json.dumps({"render_seconds": img.stats["render_seconds"]}))
"""

PY_RAYS = """
import json, sys, time, fogbank
args = json.loads(sys.argv[1])
s = fogbank.load_dict(args["cloud"])
o, d, t = s.camera_rays()
fogbank.transmittance(s.media[0], o[:4096], d[:4096], t[:4096], estimator=args["estimator"], threads=args["threads"])
times = []
for _ in range(args["repeat"]):
    start = time.perf_counter()
    fogbank.transmittance(s.media[0], o, d, t, estimator=args["estimator"], per_ray=4, seed=1, threads=args["threads"])
    times.append(time.perf_counter() - start)
rays = 4 * len(t)
print(json.dumps({"mrays": rays / min(times) / 1e6}))
"""


def timed(cmd):
    start = time.perf_counter()
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"{' '.join(cmd)}: {r.stderr}")
    return time.perf_counter() - start, r.stdout


def bench_render(a, tmp):
    rows = []
    for label, scene in SCENES.items():
        spp = a.spp
        py_wall, cli_wall, py_loop, cli_loop = [], [], [], []
        for _ in range(a.rounds):
            args = json.dumps({"scene": scene[0] if scene else None, "spp": spp, "threads": a.threads,
                               "out": os.path.join(tmp, "py.exr")})
            w, out = timed([a.python, "-c", PY_RENDER, args])
            py_wall.append(w)
            py_loop.append(json.loads(out.splitlines()[-1])["render_seconds"])
            stats = os.path.join(tmp, "cli.json")
            w, _ = timed([a.cli, "render", *scene, "--spp", str(spp), "--threads", str(a.threads), "--quiet",
                          "-o", os.path.join(tmp, "cli.exr"), "--stats", stats])
            cli_wall.append(w)
            cli_loop.append(json.load(open(stats))["render_seconds"])
        rows.append((label, spp, py_wall, cli_wall, py_loop, cli_loop))
    return rows


def bench_rays(a, tmp):
    rows = []
    for e in a.estimators:
        py, cli = [], []
        for _ in range(a.rounds):
            _, out = timed([a.python, "-c", PY_RAYS, json.dumps({"cloud": CLOUD, "estimator": e, "threads": a.threads,
                                                                   "repeat": 3})])
            py.append(json.loads(out.splitlines()[-1])["mrays"])
            j = os.path.join(tmp, "bench.json")
            timed([a.cli, "bench", "--resolution", "256", "--size", "512", "--frames", "4", "--threads",
                   str(a.threads), "--estimators", e, "--stats-size", "0", "--json", j])
            cli.append(json.load(open(j))[0]["mrays_per_s"])
        rows.append((e, py, cli))
    return rows


def med(x):
    return statistics.median(x)


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--python", required=True)
    p.add_argument("--cli", required=True)
    p.add_argument("--rounds", type=int, default=5)
    p.add_argument("--threads", type=int, default=2)
    p.add_argument("--spp", type=int, default=32)
    p.add_argument("--estimators", default="ratio_tracking,jackknife,track_length")
    a = p.parse_args()
    a.estimators = a.estimators.split(",")
    with tempfile.TemporaryDirectory() as tmp:
        print(f"{a.rounds} rounds, {a.threads} threads; medians (ratios: median of the rounds' ratios)\n")
        print("| scene | spp | Python wall s | CLI wall s | wall ratio | Python render s | CLI render s | render ratio |")
        print("|---|---:|---:|---:|---:|---:|---:|---:|")
        for label, spp, pw, cw, pl, cl in bench_render(a, tmp):
            wr = med([x / y for x, y in zip(pw, cw)])
            lr = med([x / y for x, y in zip(pl, cl)])
            print(f"| {label} | {spp} | {med(pw):.2f} | {med(cw):.2f} | {wr:.3f}× | {med(pl):.2f} | {med(cl):.2f} | {lr:.3f}× |")
        print("\n| estimator | Python Mrays/s | `fogbank bench` Mrays/s | ratio |")
        print("|---|---:|---:|---:|")
        for e, py, cli in bench_rays(a, tmp):
            r = med([x / y for x, y in zip(py, cli)])
            print(f"| {e} | {med(py):.2f} | {med(cli):.2f} | {r:.3f}× |")


if __name__ == "__main__":
    main()
