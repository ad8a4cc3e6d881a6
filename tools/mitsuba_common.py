"""Shared scene description for the Mitsuba 3 peer check and benchmark.

One Python description of each scene produces both a fogbank scene TOML and
a Mitsuba 3 scene dictionary, with every convention matched:

* grid: a Mitsuba `.vol` (version 3, float32, 1 channel, x fastest) whose
  bbox is the unit cube [0, 1]^3. Mitsuba 3's `gridvolume` ignores the bbox
  stored in the file and maps the grid's [0, 1]^3 through `to_world`
  (identity here); fogbank places a `.vol` in its file bbox. Both put voxel
  (i, j, k) at the cell centre ((i, j, k) + 1/2) / res and clamp the
  trilinear interpolant within half a voxel of the border (checked
  numerically against `gridvolume.eval` by `check_grid_convention`).
* medium: sigma_t = scale * density (Mitsuba `heterogeneous.scale`, fogbank
  `sigma_t_scale`), RGB albedo, Henyey-Greenstein g > 0 = forward in both.
  Mitsuba needs a boundary shape: a `cube` ([-1, 1]^3, scaled by 1/2 and
  moved to [0, 1]^3) with a `null` BSDF and the medium as interior.
* camera: perspective, `fov` along x, look-at with the same up vector; both
  renderers put world +x to the image right for this camera (verified by
  the z-test itself, the grid is asymmetric, and by `check_orientation`).
* film: Mitsuba `box` reconstruction filter + `independent` sampler = plain
  per-pixel average of samples uniform in the pixel, as fogbank's jittered
  pixel samples.
* integrator: Mitsuba `volpath` with max_depth = -1 (unbounded), fogbank
  `volpath` with max_depth = 100000 (never reached: Russian roulette ends
  every path first); rr_depth only changes variance.
* lights: Mitsuba `constant` (radiance) = fogbank `constant`; Mitsuba
  `point` (intensity, W/sr) = fogbank `point` (intensity / d^2).
"""

import json
import math
import os
import resource
import struct
import subprocess
import time

import numpy as np

RES = 64  # grid resolution
BIG_DEPTH = 100000


def make_grid(res=RES, seed=5):
    """Smooth heterogeneous density in [0, ~1.3]: a sum of Gaussian blobs
    plus a low-frequency sinusoid, non-zero at the faces (tests the border
    clamp), deliberately asymmetric (tests orientation)."""
    rng = np.random.default_rng(seed)
    c = (np.arange(res) + 0.5) / res
    z, y, x = np.meshgrid(c, c, c, indexing="ij")  # array[z, y, x]: x fastest
    d = 0.15 + 0.1 * np.sin(5.0 * x + 2.0 * y) * np.cos(3.0 * z + 1.0)
    for _ in range(7):
        p = rng.uniform(0.15, 0.85, 3)
        s = rng.uniform(0.08, 0.2)
        a = rng.uniform(0.4, 1.0)
        d += a * np.exp(-((x - p[0]) ** 2 + (y - p[1]) ** 2 + (z - p[2]) ** 2) / (2 * s * s))
    # A dense sharp-ish feature near the +x, +y corner for orientation.
    d += 1.0 * np.exp(-((x - 0.8) ** 2 + (y - 0.8) ** 2 + (z - 0.3) ** 2) / (2 * 0.06**2))
    return np.clip(d, 0.0, None).astype(np.float32)


def write_vol(path, grid, bbox=(0.0, 0.0, 0.0, 1.0, 1.0, 1.0)):
    """Mitsuba .vol v3: 'VOL' 3, encoding 1 (float32), xres yres zres,
    channels, bbox (6 f32: xmin ymin zmin xmax ymax zmax), then float32
    data[((z * yres + y) * xres + x) * channels + c]. `grid` is indexed
    [z, y, x] (one channel) or [z, y, x, c]."""
    if grid.ndim == 3:
        grid = grid[..., None]
    nz, ny, nx, nc = grid.shape
    with open(path, "wb") as f:
        f.write(b"VOL" + bytes([3]))
        f.write(struct.pack("<iiiii", 1, nx, ny, nz, nc))
        f.write(struct.pack("<6f", *bbox))
        f.write(np.ascontiguousarray(grid, dtype="<f4").tobytes())


# ---------------------------------------------------------------- scenes

CAMERA = dict(origin=[1.7, 1.35, 3.0], target=[0.5, 0.45, 0.5], up=[0.0, 1.0, 0.0], fov=34.0)

SCENES = {
    # (a) heterogeneous grid under a constant environment, isotropic phase
    "env": dict(
        scale=10.0,
        albedo=[0.95, 0.85, 0.7],
        g=0.0,
        # Exactly representable in few bits: Mitsuba's film sums samples in
        # f32, so e.g. 0.9 comes out a few ULP off in pixels that only see
        # the background (zero variance there, so the z-test would call it
        # an exact mismatch); 1, 0.75, 0.5 sum exactly.
        lights=[dict(type="constant", radiance=[1.0, 0.75, 0.5])],
    ),
    # (b) the same grid lit by a point light, Henyey-Greenstein g = 0.7;
    # the light is behind and above the cloud, so forward scattering
    # brightens it (a sign error in g would change the image a lot).
    "point": dict(
        scale=10.0,
        albedo=[0.95, 0.85, 0.7],
        g=0.7,
        lights=[dict(type="point", position=[0.1, 1.9, -1.2], intensity=[8.0, 8.0, 8.0])],
    ),
}


def setup_mitsuba(args):
    """Imports Mitsuba in `args.variant` on `args.threads` threads and writes
    the test grid to `<args.out>/grid.vol`; returns (mi, out, vol, grid)
    with `out` the absolute output folder."""
    # Dr.Jit's LLVM backend needs a newer LLVM than Debian 12's default 14
    # (`Cannot select: fminimum`); Debian's libllvm19 works. Set before import.
    llvm19 = "/usr/lib/x86_64-linux-gnu/libLLVM-19.so"
    if "DRJIT_LIBLLVM_PATH" not in os.environ and os.path.exists(llvm19):
        os.environ["DRJIT_LIBLLVM_PATH"] = llvm19
    import drjit as dr
    import mitsuba as mi

    mi.set_variant(args.variant)
    dr.set_thread_count(args.threads)
    os.makedirs(args.out, exist_ok=True)
    out = os.path.abspath(args.out)
    vol = os.path.join(out, "grid.vol")
    grid = make_grid()
    write_vol(vol, grid)
    return mi, out, vol, grid


def fogbank_toml(scene, vol_path, width, height, spp, seed, estimator="ratio_tracking",
                 preset=None, extra=None, medium_extra=None):
    s = SCENES[scene]
    cam = CAMERA
    lines = [
        "[camera]",
        f"from = {cam['origin']}",
        f"to = {cam['target']}",
        f"up = {cam['up']}",
        f"fov = {cam['fov']}",
        'fov_axis = "x"',
        f"width = {width}",
        f"height = {height}",
        "",
        "[[media]]",
        f'density = {{ vol = "{vol_path}" }}',
        f"sigma_t_scale = {s['scale']}",
        f"albedo = {s['albedo']}",
        (f'phase = {{ type = "hg", g = {s["g"]} }}' if s["g"] != 0.0
         else 'phase = { type = "isotropic" }'),
        'filter = "trilinear"',
        'precision = "f32"',
    ]
    for k, v in (medium_extra or {}).items():
        lines.append(f"{k} = {json.dumps(v)}")
    lines.append("")
    for l in s["lights"]:
        lines.append("[[lights]]")
        lines.append(f'type = "{l["type"]}"')
        for k, v in l.items():
            if k != "type":
                lines.append(f"{k} = {v}")
        lines.append("")
    lines += [
        "[integrator]",
        'type = "volpath"',
        f'estimator = "{estimator}"',
        f"max_depth = {BIG_DEPTH}",
        "rr_depth = 3",
    ]
    if preset:
        lines.append(f'preset = "{preset}"')
    for k, v in (extra or {}).items():
        lines.append(f"{k} = {json.dumps(v)}")
    lines += ["", "[render]", f"spp = {spp}", f"seed = {seed}", "pixel_jitter = true", ""]
    return "\n".join(lines)


def mitsuba_dict(mi, scene, vol_path, width, height, spp):
    s = SCENES[scene]
    T = mi.ScalarTransform4f
    cam = CAMERA
    d = {
        "type": "scene",
        "integrator": {"type": "volpath", "max_depth": -1, "rr_depth": 3},
        "sensor": {
            "type": "perspective",
            "fov": cam["fov"],
            "fov_axis": "x",
            "to_world": T().look_at(origin=cam["origin"], target=cam["target"], up=cam["up"]),
            "film": {
                "type": "hdrfilm",
                "width": width,
                "height": height,
                "rfilter": {"type": "box"},
                "pixel_format": "rgb",
                "sample_border": False,
            },
            "sampler": {"type": "independent", "sample_count": spp},
        },
        "medium_box": {
            "type": "cube",
            "to_world": T().translate([0.5, 0.5, 0.5]) @ T().scale(0.5),
            "bsdf": {"type": "null"},
            "interior": {
                "type": "heterogeneous",
                "sigma_t": {
                    "type": "gridvolume",
                    "filename": vol_path,
                    "filter_type": "trilinear",
                },
                "scale": s["scale"],
                "albedo": {"type": "rgb", "value": s["albedo"]},
                "phase": {"type": "hg", "g": s["g"]},
            },
        },
    }
    for i, l in enumerate(s["lights"]):
        if l["type"] == "constant":
            d[f"light{i}"] = {"type": "constant",
                              "radiance": {"type": "rgb", "value": l["radiance"]}}
        elif l["type"] == "point":
            d[f"light{i}"] = {"type": "point", "position": l["position"],
                              "intensity": {"type": "rgb", "value": l["intensity"]}}
        else:
            raise ValueError(l["type"])
    return d


def check_grid_convention(mi, vol_path, grid):
    """Mitsuba's gridvolume at random points must equal the cell-centred,
    border-clamped trilinear interpolant fogbank uses."""
    import drjit as dr

    vol = mi.load_dict({"type": "gridvolume", "filename": vol_path, "filter_type": "trilinear"})
    rng = np.random.default_rng(1)
    res = np.array(grid.shape[::-1])  # (nx, ny, nz)
    worst = 0.0
    for p in rng.uniform(0.0, 1.0, (200, 3)):
        q = p * res - 0.5
        f = np.floor(q).astype(int)
        w = q - f
        v = 0.0
        for dz in (0, 1):
            for dy in (0, 1):
                for dx in (0, 1):
                    ix = np.clip(f + [dx, dy, dz], 0, res - 1)
                    wt = ((w[0] if dx else 1 - w[0]) * (w[1] if dy else 1 - w[1])
                          * (w[2] if dz else 1 - w[2]))
                    v += wt * grid[ix[2], ix[1], ix[0]]
        it = dr.zeros(mi.Interaction3f)
        it.p = mi.Point3f(*p)
        worst = max(worst, abs(float(vol.eval_1(it)) - v))
    return worst


def mse_at(c, t):
    """c: [(time, mse)] by increasing time; log-log interpolation of the
    MSE at time t, 1/t extrapolation outside the measured range."""
    if t <= c[0][0]:
        return c[0][1] * c[0][0] / t
    if t >= c[-1][0]:
        return c[-1][1] * c[-1][0] / t
    for (t0, e0), (t1, e1) in zip(c, c[1:]):
        if t0 <= t <= t1:
            if t1 == t0 or e0 <= 0 or e1 <= 0:
                return e0
            a = math.log(t / t0) / math.log(t1 / t0)
            return math.exp(math.log(e0) + a * (math.log(e1) - math.log(e0)))
    return None


# ---------------------------------------------------------------- running

def run_fogbank(fogbank, toml_path, out_exr, threads, spp=None, seed=None, stats=None,
                device="cpu"):
    """Runs `fogbank render`; returns (wall seconds, CPU seconds of the child,
    stats dict or None)."""
    cmd = [fogbank, "render", toml_path, "-o", out_exr, "--threads", str(threads), "--quiet",
           "--device", device]
    if spp is not None:
        cmd += ["--spp", str(spp)]
    if seed is not None:
        cmd += ["--seed", str(seed)]
    if stats:
        cmd += ["--stats", stats]
    r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    subprocess.run(cmd, check=True)
    wall = time.perf_counter() - t0
    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime)
    st = None
    if stats:
        with open(stats) as f:
            st = json.load(f)
    return wall, cpu, st


def read_exr(mi, path):
    """Returns (rgb, variance or None) as float64 arrays (h, w, 3)."""
    import drjit as dr

    # Bitmap's EXR reader deadlocks with a one-thread Dr.Jit pool
    # (mitsuba 3.9.1 / drjit 1.5.0): read with a larger pool, then restore.
    n = dr.thread_count()
    dr.set_thread_count(max(n, 4))
    try:
        bmp = mi.Bitmap(path)
    finally:
        dr.set_thread_count(n)
    names = list(bmp.struct_()) if hasattr(bmp, "struct_") else None
    arr = np.array(bmp, dtype=np.float64)
    chans = [f.name for f in bmp.struct_()] if names is not None else ["R", "G", "B"]
    idx = {n: i for i, n in enumerate(chans)}
    rgb = arr[..., [idx["R"], idx["G"], idx["B"]]]
    var = None
    if "variance.R" in idx:
        var = arr[..., [idx["variance.R"], idx["variance.G"], idx["variance.B"]]]
    return rgb, var


def write_exr(mi, path, rgb, var=None):
    """EXR with R, G, B and (optionally) variance.R/G/B, as fogbank writes."""
    chans = ["R", "G", "B"]
    data = [rgb]
    if var is not None:
        chans += ["variance.R", "variance.G", "variance.B"]
        data.append(var)
    arr = np.ascontiguousarray(np.concatenate(data, axis=2).astype(np.float32))
    import drjit as dr

    bmp = mi.Bitmap(arr, mi.Bitmap.PixelFormat.MultiChannel, chans)
    n = dr.thread_count()
    dr.set_thread_count(max(n, 4))  # see read_exr
    try:
        bmp.write(path)
    finally:
        dr.set_thread_count(n)


def versions(fogbank):
    import drjit as dr
    import mitsuba as mi

    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    try:
        commit = subprocess.run(["git", "-C", root, "rev-parse", "--short", "HEAD"],
                                capture_output=True, text=True).stdout.strip()
    except OSError:
        commit = "?"
    cpu = "?"
    try:
        for line in open("/proc/cpuinfo"):
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    return dict(mitsuba=mi.__version__, drjit=dr.__version__, fogbank_commit=commit,
                cpu=cpu, cores=os.cpu_count())
