#!/usr/bin/env python3
"""Mitsuba 3 reference images for the scenes in scenes/mitsuba/.

Renders each scene XML with Mitsuba 3's `scalar_rgb` variant on one thread and
writes `scenes/mitsuba/refs/<name>.exr` with channels

    R, G, B                          per-pixel mean radiance (linear)
    variance.R, variance.G, variance.B   per-pixel variance OF THE MEAN

(the layout `fogbank render` writes and `fogbank compare --metric ztest` reads),
plus `refs/refs.json` with the Mitsuba version, spp, seeds, timings and the
references' own noise level (see `noise_stats`).

Per-pixel moments. Mitsuba's `moment` integrator records the second moment of
each sample's *XYZ* value (moment.cpp squares `srgb_to_xyz(rgb)`), from which
per-channel RGB variances cannot be recovered (they would need the RGB
covariances). The script therefore renders the scene `spp` times at 1 sample
per pixel (`mi.render(scene, seed=s_k, spp=1)`, k = 0..spp-1: Mitsuba's own
render loop, sampler, film and filter; the pass seeds s_k are distinct
pseudo-random values chosen so that no two pixels of any passes share a
Mitsuba seed, see `pass_seeds`), and accumulates each sample x and x^2 per
pixel and channel in float64:

    mean     = S1 / n
    variance = (S2 - n * mean^2) / (n - 1) / n      (variance of the mean)

With the box filter and sample_border off, a 1-spp pass returns exactly the
sample's value, so this is the per-sample estimate (n - 1 degrees of freedom),
and pixels that only see a constant background get variance exactly 0 and the
mean exactly the background's float32 value.

Usage (needs `pip install mitsuba numpy`; never part of CI):

    python3 tools/mitsuba_refs.py                     # all scenes, ~2.5e7 samples each
    python3 tools/mitsuba_refs.py cloud_ground chromatic
    python3 tools/mitsuba_refs.py --samples 2e6       # spp = round(2e6 / pixels)
    python3 tools/mitsuba_refs.py --quick             # 16 spp into /tmp/mitsuba_refs_quick
    python3 tools/mitsuba_refs.py --spp 64 --out DIR
    python3 tools/mitsuba_refs.py --make-assets       # regenerate meshes/ and textures/
    python3 tools/mitsuba_refs.py --pbrt              # the pbrt twins (see below)
    python3 tools/mitsuba_refs.py --scene-dir scenes/street window_street

`--pbrt` renders the hand-written Mitsuba twins of the pbrt-v4 scenes,
`scenes/pbrt/mitsuba/<name>.xml`, into `scenes/pbrt/refs/<name>.exr`,
mirrored left-right: pbrt's look-at builds a left-handed camera frame, so
its image of the same eye, target and up is Mitsuba's mirrored; the mirrored
reference is the image pbrt renders (and fogbank renders from the `.pbrt`
file).

The assets (meshes/*.obj|ply, textures/*.exr|vol) are generated
deterministically by `--make-assets` (fixed seeds) and kept in the repository.
"""

import argparse
import json
import os
import struct
import sys
import time

import numpy as np

TOOLS = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(TOOLS)
SCENE_DIR = os.path.join(ROOT, "scenes", "mitsuba")
sys.path.insert(0, TOOLS)
import mitsuba_common as mc  # noqa: E402  (write_exr / read_exr, thread-safe EXR I/O)

SCENES = [
    "null_mesh_medium",
    "dielectric_media",
    "thin_area",
    "light_in_medium",
    "surfaces_env_area",
    "chromatic",
    "cloud_ground",
    "fog_emitters",
    "spot_fog",
    "bitmap_textures",
    "analytic_shapes",
    "instances",
    "users_beckmann_conductor",
    "users_beckmann_dielectric",
    "users_beckmann_plastic",
    "users_clip_fog",
    "users_spectral_lights",
    "users_path_include",
]
PBRT_DIR = os.path.join(ROOT, "scenes", "pbrt", "mitsuba")
PBRT_SCENES = [
    "fog_room",
    "nanovdb_sun",
    "uniformgrid_area",
    "glass_fog",
    "rgbgrid_envmap",
    "cloud_distant",
]
TOTAL_SAMPLES = 25_000_000  # per image, default of --samples


# ------------------------------------------------------------------ assets

def icosphere(subdiv):
    """Unit icosphere: (vertices (n, 3) float64, faces (m, 3) int), faces
    counter-clockwise seen from outside (geometric normal points out)."""
    t = (1.0 + 5.0 ** 0.5) / 2.0
    v = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t),
         (0, -1, -t), (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    f = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4),
         (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8),
         (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    verts = [np.array(p, float) / np.linalg.norm(p) for p in v]
    for _ in range(subdiv):
        cache, nf = {}, []

        def mid(a, b):
            k = (min(a, b), max(a, b))
            if k not in cache:
                m = verts[a] + verts[b]
                verts.append(m / np.linalg.norm(m))
                cache[k] = len(verts) - 1
            return cache[k]

        for a, b, c in f:
            ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
            nf += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        f = nf
    V, F = np.array(verts), np.array(f)
    # Enforce outward winding.
    for i, (a, b, c) in enumerate(F):
        n = np.cross(V[b] - V[a], V[c] - V[a])
        if np.dot(n, V[a] + V[b] + V[c]) < 0:
            F[i] = (a, c, b)
    return V, F


def write_obj_flat(path, V, F, comment):
    """OBJ with shared positions and one normal per face (`f v//n`): flat
    shading whatever the loader does with normals."""
    with open(path, "w") as f:
        f.write(f"# {comment}\n")
        for p in V:
            f.write(f"v {p[0]:.7f} {p[1]:.7f} {p[2]:.7f}\n")
        for a, b, c in F:
            n = np.cross(V[b] - V[a], V[c] - V[a])
            n /= np.linalg.norm(n)
            f.write(f"vn {n[0]:.7f} {n[1]:.7f} {n[2]:.7f}\n")
        for i, (a, b, c) in enumerate(F):
            f.write(f"f {a + 1}//{i + 1} {b + 1}//{i + 1} {c + 1}//{i + 1}\n")


def write_ply(path, V, F):
    """Binary little-endian PLY, float x y z, `list uchar int vertex_indices`,
    no normals."""
    hdr = ("ply\nformat binary_little_endian 1.0\ncomment fogbank tools/mitsuba_refs.py\n"
           f"element vertex {len(V)}\nproperty float x\nproperty float y\nproperty float z\n"
           f"element face {len(F)}\nproperty list uchar int vertex_indices\nend_header\n")
    with open(path, "wb") as f:
        f.write(hdr.encode("ascii"))
        f.write(np.asarray(V, "<f4").tobytes())
        for a, b, c in F:
            f.write(struct.pack("<Biii", 3, int(a), int(b), int(c)))


def emitter_soup(n=300, seed=23):
    """n small triangles (own vertices each) scattered in [-2.4, 2.4]^3 away
    from the camera at (0, 0, 2.5); random orientation."""
    rng = np.random.default_rng(seed)
    V, F = [], []
    while len(F) < n:
        c = rng.uniform(-2.4, 2.4, 3)
        if np.linalg.norm(c - np.array([0.0, 0.0, 2.5])) < 1.0:
            continue
        size = rng.uniform(0.015, 0.04)
        for _ in range(3):
            V.append(c + size * rng.normal(size=3))
        F.append((len(V) - 3, len(V) - 2, len(V) - 1))
    return np.array(V), np.array(F)


def cloud_grid(nx=32, ny=16, nz=24, seed=7):
    """Cloud density in [0, ~1.2] on a 32 x 16 x 24 grid: a flattened union of
    Gaussian puffs, modulated by low-frequency sinusoidal noise, falling to 0
    towards the grid faces; asymmetric."""
    rng = np.random.default_rng(seed)
    z, y, x = np.meshgrid((np.arange(nz) + 0.5) / nz, (np.arange(ny) + 0.5) / ny,
                          (np.arange(nx) + 0.5) / nx, indexing="ij")
    d = np.zeros_like(x)
    for _ in range(9):
        p = np.array([rng.uniform(0.25, 0.75), rng.uniform(0.35, 0.55), rng.uniform(0.3, 0.7)])
        s = rng.uniform(0.08, 0.16)
        d += rng.uniform(0.6, 1.0) * np.exp(-(((x - p[0]) / s) ** 2 + ((y - p[1]) / (1.6 * s)) ** 2
                                              + ((z - p[2]) / (1.2 * s)) ** 2) / 2)
    noise = np.zeros_like(x)
    for _ in range(6):
        k = rng.normal(size=3) * 9.0
        noise += np.sin(k[0] * x + k[1] * y + k[2] * z + rng.uniform(0, 6.3))
    d = d * (1.0 + 0.25 * noise / 6 ** 0.5)
    d = np.clip(d - 0.12, 0.0, None)
    return (d * 1.2 / d.max()).astype(np.float32)


def chroma_grid(n=16, seed=11):
    """3-channel extinction on 16^3: each channel a different pair of blobs,
    so sigma_t's colour varies in space."""
    rng = np.random.default_rng(seed)
    c = (np.arange(n) + 0.5) / n
    z, y, x = np.meshgrid(c, c, c, indexing="ij")
    out = np.zeros((n, n, n, 3))
    for ch in range(3):
        d = 0.2 + 0.1 * np.sin(4 * x + 2 * ch) * np.cos(3 * y - ch)
        for _ in range(2):
            p = rng.uniform(0.25, 0.75, 3)
            s = rng.uniform(0.12, 0.2)
            d += rng.uniform(0.8, 1.6) * np.exp(-((x - p[0]) ** 2 + (y - p[1]) ** 2
                                                  + (z - p[2]) ** 2) / (2 * s * s))
        out[..., ch] = d
    return out.astype(np.float32)


def sky_envmap(w=32, h=16):
    """Lat-long sky (32 x 16 RGB): zenith-to-horizon gradient, a dim ground,
    a warm tint growing with phi (orientation cue) and a bright sun. Pixel
    (x, y) is the direction of Mitsuba 3.9's envmap lookup:
    phi = 2 pi (x + 0.5) / w (texel-centred), theta = pi y / (h - 1) (rows
    on the poles), d = (sin phi sin theta, cos theta, -cos phi sin theta)."""
    img = np.zeros((h, w, 3))
    sun = np.array([0.5, 0.6, 0.3])
    sun /= np.linalg.norm(sun)
    for yy in range(h):
        th = np.pi * yy / (h - 1)
        for xx in range(w):
            ph = 2 * np.pi * (xx + 0.5) / w
            d = np.array([np.sin(ph) * np.sin(th), np.cos(th), -np.cos(ph) * np.sin(th)])
            if d[1] >= 0:
                t = d[1]
                c = (1 - t) * np.array([1.0, 0.9, 0.75]) + t * np.array([0.25, 0.4, 0.9])
                c = c * (1.0 + 0.5 * np.sin(th) * ph / (2 * np.pi) * np.array([1.0, 0.3, -0.5]))
            else:
                c = np.array([0.3, 0.25, 0.2]) * (1 + 0.5 * d[1])
            c = c + 40.0 * np.exp((np.dot(d, sun) - 1.0) / 0.01)
            img[yy, xx] = c
    return img.astype(np.float32)


def bitmap_textures(mi, td):
    """The bitmaps of bitmap_textures.xml: 8-bit sRGB RGB, 8-bit grey and
    16-bit RGB PNGs, patterns without symmetry so a flipped axis shows."""
    x, y = np.meshgrid(np.arange(24), np.arange(16))
    tiles = np.stack([(x * 10 + 15) % 256, y * 15 + 10,
                      ((x // 4 + y // 4) % 2) * 200 + 30], axis=-1).astype(np.uint8)
    mi.Bitmap(tiles, mi.Bitmap.PixelFormat.RGB).write(os.path.join(td, "tiles_24x16.png"))
    x, y = np.meshgrid(np.arange(12), np.arange(10))
    grey = (40 + 180 * (x / 11) * np.where(y % 3 == 0, 1.0, 0.5)).astype(np.uint8)
    mi.Bitmap(grey[..., None], mi.Bitmap.PixelFormat.Y).write(os.path.join(td, "grey_12x10.png"))
    x, y = np.meshgrid(np.arange(8), np.arange(6))
    rgb16 = np.stack([x * 8000 + 2000, y * 11000 + 1000, (x * y * 1500) % 65536],
                     axis=-1).astype(np.uint16)
    mi.Bitmap(rgb16, mi.Bitmap.PixelFormat.RGB).write(os.path.join(td, "rgb16_8x6.png"))


def make_assets(mi):
    import drjit as dr

    md, td = os.path.join(SCENE_DIR, "meshes"), os.path.join(SCENE_DIR, "textures")
    os.makedirs(md, exist_ok=True)
    os.makedirs(td, exist_ok=True)
    V, F = icosphere(2)
    write_ply(os.path.join(md, "icosphere2.ply"), V, F)
    write_obj_flat(os.path.join(md, "icosphere2_flat.obj"), V, F,
                   "unit icosphere, 2 subdivisions (320 faces), outward CCW, flat normals")
    V1, F1 = icosphere(1)
    write_obj_flat(os.path.join(md, "icosphere1_flat.obj"), V1, F1,
                   "unit icosphere, 1 subdivision (80 faces), outward CCW, flat normals")
    V, F = emitter_soup()
    write_obj_flat(os.path.join(md, "emitters300.obj"), V, F,
                   "300 random triangles (fog_emitters), own vertices each, flat normals")
    mc.write_vol(os.path.join(td, "cloud_32x16x24.vol"), cloud_grid(),
              (-1.5, 0.5, -1.0, 1.5, 1.5, 1.0))
    mc.write_vol(os.path.join(td, "chroma_16_rgb.vol"), chroma_grid(), (0, 0, 0, 1, 1, 1))
    sky = sky_envmap()
    n = dr.thread_count()
    dr.set_thread_count(max(n, 4))  # Bitmap EXR I/O deadlocks on a 1-thread pool
    try:
        mi.Bitmap(sky, mi.Bitmap.PixelFormat.RGB).write(os.path.join(td, "sky_32x16.exr"))
    finally:
        dr.set_thread_count(n)
    bitmap_textures(mi, td)
    print(f"assets written under {SCENE_DIR}/meshes and /textures")


# ------------------------------------------------------------------ render

def load_scene(mi, name, scene_dir=SCENE_DIR):
    import drjit as dr

    n = dr.thread_count()
    dr.set_thread_count(max(n, 4))  # scene loading reads EXRs (see make_assets)
    try:
        return mi.load_file(os.path.join(scene_dir, f"{name}.xml"))
    finally:
        dr.set_thread_count(n)


def pass_seeds(w, h, spp, seed0):
    """The `seed` argument of each 1-spp pass: distinct pseudo-random values
    (numpy PCG64 seeded with `seed0`), multiples of `spacing`.

    Mitsuba's scalar render loop seeds pixel i of block b with
    `seed * w * h + b * 32^2 + i` (PCG32, one default stream), so a pass
    covers seeds [seed * w * h, seed * w * h + padded) with `padded` = the
    number of 32 x 32 blocks times 1024; multiples of `spacing` keep passes
    disjoint. Consecutive pass seeds (seed0 + k) are NOT used: the samples of
    one pixel in passes k, k + 1, ... are then slightly positively correlated
    (seeds differing by small multiples of w * h; measured on
    null_mesh_medium: the variance of a 128-pass mean was 1.12 times the
    per-sample variance / 128, 1.22 times at 488 passes, against 1.00 for
    Mitsuba's own 128-spp renders and for random pass seeds)."""
    pixels = w * h
    padded = -(-w // 32) * -(-h // 32) * 1024
    spacing = -(-padded // pixels)
    n_max = (2 ** 32 - padded) // (pixels * spacing)
    if spp > n_max:
        raise ValueError(f"at most {n_max} passes fit Mitsuba's 32-bit seed")
    rng = np.random.default_rng(seed0)
    return [int(u) * spacing for u in rng.choice(n_max, spp, replace=False)]


def render_moments(mi, scene, spp, seed0):
    """Per-pixel mean and variance of the mean from `spp` 1-spp passes."""
    film = scene.sensors()[0].film()
    w, h = (int(v) for v in film.crop_size())
    s1 = s2 = None
    bad = 0
    for sd in pass_seeds(w, h, spp, seed0):
        x = np.array(mi.render(scene, seed=sd, spp=1), dtype=np.float64)[..., :3]
        fin = np.isfinite(x)
        if not fin.all():
            bad += int((~fin).sum())
            x = np.where(fin, x, 0.0)
        if s1 is None:
            s1, s2 = np.zeros_like(x), np.zeros_like(x)
        s1 += x
        s2 += x * x
    mean = s1 / spp
    var = np.maximum(s2 - spp * mean * mean, 0.0) / (spp - 1) / spp
    return mean, var, bad


def noise_stats(mean, var, block=8):
    """The reference's own noise level, per channel (lists of 3):

    block_rel_l1: the expected relative L1 distance of the block x block
        block means from their expectations, from the variance of the mean:
        sum_b sqrt(2/pi) sqrt(sum_{p in b} var_p) / sum_b |sum_{p in b} mean_p|
        (E|N(0, s)| = sqrt(2/pi) s; the 8 x 8 criterion of fogbank's test
        sums the blocks, which gives the same ratio as their means).
        Scales as 1/sqrt(samples), so block_rel_l1 * sqrt(samples) is the
        per-image constant k: a test render of N samples with the same
        per-sample variance is expected at k * sqrt(1/samples + 1/N).
    mean_rel_se: the relative standard error of the image mean,
        sqrt(sum_p var_p) / |sum_p mean_p|."""
    h, w, _ = mean.shape
    num, den = np.zeros(3), np.zeros(3)
    for by in range(0, h, block):
        for bx in range(0, w, block):
            m = mean[by:by + block, bx:bx + block].reshape(-1, 3)
            v = var[by:by + block, bx:bx + block].reshape(-1, 3)
            num += np.sqrt(2.0 / np.pi) * np.sqrt(v.sum(axis=0))
            den += np.abs(m.sum(axis=0))
    tot = np.abs(mean.reshape(-1, 3).sum(axis=0))
    l1 = num / np.maximum(den, 1e-300)
    se = np.sqrt(var.reshape(-1, 3).sum(axis=0)) / np.maximum(tot, 1e-300)
    return l1, se


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("scenes", nargs="*", help=f"scene names (default: all of {SCENES})")
    ap.add_argument("--samples", type=float, default=TOTAL_SAMPLES,
                    help=f"total samples per image (default {TOTAL_SAMPLES:.1e}): "
                    "spp = round(samples / pixels)")
    ap.add_argument("--spp", type=int, help="samples per pixel (overrides --samples)")
    ap.add_argument("--quick", action="store_true", help="16 spp into /tmp/mitsuba_refs_quick")
    ap.add_argument("--out", help="output folder (default scenes/mitsuba/refs)")
    ap.add_argument("--seed", type=int, default=1,
                    help="seeds numpy's generator of the passes' Mitsuba seeds")
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--variant", default="scalar_rgb")
    ap.add_argument("--scene-dir", help="read the named scenes from this folder instead "
                    "(references then go to its refs/, e.g. scenes/street)")
    ap.add_argument("--pbrt", action="store_true",
                    help="the Mitsuba twins of scenes/pbrt/, mirrored, into scenes/pbrt/refs")
    ap.add_argument("--make-assets", action="store_true",
                    help="(re)generate meshes/ and textures/ and exit")
    args = ap.parse_args()

    import drjit as dr
    import mitsuba as mi

    mi.set_variant(args.variant)
    dr.set_thread_count(args.threads)
    if args.make_assets:
        make_assets(mi)
        return

    scene_dir = args.scene_dir or (PBRT_DIR if args.pbrt else SCENE_DIR)
    names = args.scenes or (PBRT_SCENES if args.pbrt else SCENES)
    for n in names:
        if not os.path.exists(os.path.join(scene_dir, f"{n}.xml")):
            sys.exit(f"no scene {n}.xml in {scene_dir}")
    refs = os.path.join(os.path.dirname(PBRT_DIR), "refs") if args.pbrt else os.path.join(scene_dir, "refs")
    out = args.out or ("/tmp/mitsuba_refs_quick" if args.quick else refs)
    os.makedirs(out, exist_ok=True)
    meta_path = os.path.join(out, "refs.json")
    meta = {}
    if os.path.exists(meta_path):
        with open(meta_path) as f:
            meta = json.load(f)
    meta.setdefault("scenes", {})
    meta.update(mitsuba=mi.__version__, drjit=dr.__version__, variant=args.variant,
                threads=args.threads, channels=["R", "G", "B", "variance.R", "variance.G",
                                                "variance.B"],
                variance="sample variance of the per-sample values (n - 1) divided by n: "
                         "the variance of the mean",
                method="n passes of mi.render(scene, seed=s_k, spp=1), s_k from "
                       "tools/mitsuba_refs.py pass_seeds(w, h, n, seed0); float64 moment "
                       "accumulation",
                noise="per channel R, G, B: block8_rel_l1_rgb = expected relative L1 of "
                      "the 8x8 block means from the reference's own noise, "
                      "sum_b sqrt(2/pi) sqrt(sum_{p in b} var_p) / sum_b |sum_{p in b} "
                      "mean_p|; block8_rel_l1_x_sqrt_samples_rgb = the same times "
                      "sqrt(samples) (a render of N samples with the same per-sample "
                      "variance: k sqrt(1/samples + 1/N) against this reference); "
                      "mean_rel_se_rgb = sqrt(sum_p var_p) / |sum_p mean_p|, the "
                      "relative standard error of the image mean")
    for name in names:
        t0 = time.perf_counter()
        scene = load_scene(mi, name, scene_dir)
        film = scene.sensors()[0].film()
        w, h = (int(v) for v in film.crop_size())
        spp = args.spp or (16 if args.quick else max(2, round(args.samples / (w * h))))
        mean, var, bad = render_moments(mi, scene, spp, args.seed)
        if args.pbrt:
            mean, var = mean[:, ::-1], var[:, ::-1]
        secs = time.perf_counter() - t0
        path = os.path.join(out, f"{name}.exr")
        mc.write_exr(mi, path, mean.astype(np.float32), var.astype(np.float32))
        l1, se = noise_stats(mean, var)
        samples = spp * w * h
        print(f"[{name}] {w}x{h}, {spp} spp ({samples} samples), {secs:.1f} s, "
              f"mean {np.round(mean.mean(axis=(0, 1)), 5).tolist()}, "
              f"8x8 block rel. L1 {np.round(l1, 5).tolist()}, "
              f"rel. std. error of the mean {np.round(se, 6).tolist()}"
              + (f", {bad} non-finite sample values zeroed" if bad else ""), flush=True)
        meta["scenes"][name] = dict(
            width=w, height=h, spp=spp, samples=samples, seed0=args.seed,
            seconds=round(secs, 1), nonfinite_samples=bad,
            mirrored=bool(args.pbrt),
            mean_rgb=mean.mean(axis=(0, 1)).tolist(),
            block8_rel_l1_rgb=l1.tolist(),
            block8_rel_l1_x_sqrt_samples_rgb=(l1 * np.sqrt(samples)).tolist(),
            mean_rel_se_rgb=se.tolist())
        with open(meta_path, "w") as f:
            json.dump(meta, f, indent=2)


if __name__ == "__main__":
    main()
