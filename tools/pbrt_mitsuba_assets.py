#!/usr/bin/env python3
"""Volume data shared by the pbrt-v4 scenes of scenes/pbrt/ and their
hand-written Mitsuba 3 twins in scenes/pbrt/mitsuba/.

Writes, from the same float32 arrays (fixed formulas, no randomness):

    scenes/pbrt/data/blob.nvdb          a 20^3 density for pbrt's `nanovdb`
                                        medium: written as OpenVDB by
                                        python3-openvdb (pyopenvdb), turned into
                                        NanoVDB by Debian's `nanovdb_convert`
    scenes/pbrt/mitsuba/data/blob.vol   the same voxels as a Mitsuba gridvolume
    scenes/pbrt/mitsuba/data/ugrid.vol  the 12 x 10 x 8 density inlined in
                                        scenes/pbrt/uniformgrid_area.pbrt
    scenes/pbrt/mitsuba/data/rgb_sigma_t.vol  the rgbgrid's sigma_a + sigma_s
    scenes/pbrt/data/sky_oct.exr        a 128^2 equal-area octahedral sky for
                                        pbrt's image `infinite` light
    scenes/pbrt/mitsuba/data/sky_latlong.exr  the same sky as a 512 x 256
                                        lat-long map in Mitsuba's envmap layout
    scenes/pbrt/mitsuba/data/cloud.vol  pbrt's `cloud` density at the centres
                                        of the 32^3 voxels fogbank bakes it into

The sky's lat-long map is made here independently of fogbank: each texel
averages (by solid angle) 4 x 4 directions, each taking the octahedral
pixel it falls in, as pbrt's ImageInfiniteLight::ImageLe looks up
(LookupNearest), through the light's transform of the scene (Rotate -90 1 0 0:
the square's centre, light +z, is world +y). The cloud density is pbrt-v4's
CloudMedium::Density with its Perlin Noise and DNoise (pbrt's util/noise.cpp),
ported to numpy from pbrt's source, not from fogbank's.

Placement. pbrt's `nanovdb` medium samples voxel (i, j, k) at index point
(i, j, k); a Mitsuba gridvolume puts its N cells' centres at
(i + 0.5)/N of its box, so the Mitsuba box spans index -0.5 .. N - 0.5.
pbrt's `uniformgrid` is cell-centred over p0..p1, as Mitsuba's gridvolume
over its box. Every grid has a zero outer layer, so pbrt's interpolation
towards zero outside and Mitsuba's clamping to the edge agree.

Needs pyopenvdb (Debian's python3-openvdb), numpy and mitsuba (for EXR
writing); Debian's python3 sees the venv's packages through PYTHONPATH:
    PYTHONPATH=/path/to/venv/lib/python3.11/site-packages \
        /usr/bin/python3 tools/pbrt_mitsuba_assets.py
"""

import os
import subprocess
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from mitsuba_common import write_vol  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
PBRT = os.path.join(ROOT, "scenes", "pbrt")
MI_DATA = os.path.join(PBRT, "mitsuba", "data")

BLOB_N = 20
BLOB_VOXEL = 0.1


def blob():
    """[z, y, x] density: two overlapping smooth bumps, zero outer layer."""
    n = BLOB_N
    z, y, x = np.meshgrid(*(np.arange(n, dtype=np.float64),) * 3, indexing="ij")
    c = (n - 1) / 2.0

    def bump(cx, cy, cz, r):
        q = ((x - cx) ** 2 + (y - cy) ** 2 + (z - cz) ** 2) / r**2
        return np.clip(1.0 - q, 0.0, None) ** 2

    d = bump(c - 2, c, c, 8.0) + 0.8 * bump(c + 3.5, c + 2, c - 1, 5.0)
    d[[0, -1], :, :] = 0
    d[:, [0, -1], :] = 0
    d[:, :, [0, -1]] = 0
    return d.astype(np.float32)


def ugrid():
    """[z, y, x] 8 x 10 x 12 density for the uniformgrid: a ramp times a
    bump, zero outer layer."""
    nz, ny, nx = 8, 10, 12
    z, y, x = np.meshgrid(np.arange(nz), np.arange(ny), np.arange(nx), indexing="ij")
    u = (x + 0.5) / nx
    q = ((x - 5.5) / 5) ** 2 + ((y - 4.5) / 4.5) ** 2 + ((z - 3.5) / 3.5) ** 2
    d = np.clip(1.0 - q, 0.0, None) * (0.4 + 1.2 * u)
    d[[0, -1], :, :] = 0
    d[:, [0, -1], :] = 0
    d[:, :, [0, -1]] = 0
    return d.astype(np.float32)


RGB_ALBEDO = np.array([0.9, 0.7, 0.8])


def rgb_grids():
    """[z, y, x, c] sigma_a and sigma_s of the rgbgrid (6 x 6 x 6, zero
    outer layer): sigma_t chromatic, redder towards +x and bluer towards -x,
    the albedo the same in every voxel (pbrt interpolates sigma_s and
    sigma_t, Mitsuba and fogbank the albedo: alike only for a constant
    albedo)."""
    n = 6
    z, y, x = np.meshgrid(*(np.arange(n),) * 3, indexing="ij")
    inner = ((x > 0) & (x < n - 1) & (y > 0) & (y < n - 1) & (z > 0) & (z < n - 1))
    u = x / (n - 1.0)
    bump = 1.0 - 0.5 * ((y - 2.5) ** 2 + (z - 2.5) ** 2) / 6.25
    t = np.stack([0.6 + 1.4 * u, 1.0 + 0.0 * u, 2.0 - 1.4 * u], axis=-1) * (bump * inner)[..., None]
    # Written as text with 6 significant digits: round sigma_t first so
    # that sigma_a + sigma_s is it.
    s = (t * RGB_ALBEDO).astype(np.float32)
    a = (t * (1 - RGB_ALBEDO)).astype(np.float32)
    return a, s


# ---------------------------------------------------------------- the sky

def square_to_sphere(u, v):
    """pbrt's EqualAreaSquareToSphere for arrays of [0, 1]^2 points."""
    u, v = 2 * u - 1, 2 * v - 1
    up, vp = np.abs(u), np.abs(v)
    sd = 1 - (up + vp)
    r = 1 - np.abs(sd)
    phi = np.where(r == 0, 1.0, (vp - up) / np.where(r == 0, 1, r) + 1) * np.pi / 4
    z = np.copysign(1 - r * r, sd)
    s = r * np.sqrt(np.clip(2 - r * r, 0, None))
    return np.copysign(np.cos(phi), u) * s, np.copysign(np.sin(phi), v) * s, z


def sphere_to_square(x, y, z):
    """pbrt's EqualAreaSphereToSquare (with an exact arctangent)."""
    ax, ay, az = np.abs(x), np.abs(y), np.abs(z)
    r = np.sqrt(np.clip(1 - az, 0, None))
    a, b = np.maximum(ax, ay), np.minimum(ax, ay)
    b = np.where(a == 0, 0, b / np.where(a == 0, 1, a))
    phi = np.arctan(b) * 2 / np.pi
    phi = np.where(ax < ay, 1 - phi, phi)
    v = phi * r
    u = r - v
    neg = z < 0
    u, v = np.where(neg, 1 - v, u), np.where(neg, 1 - u, v)
    u, v = np.copysign(u, x), np.copysign(v, y)
    return (u + 1) / 2, (v + 1) / 2


def sky_radiance(x, y, z):
    """Smooth sky in the light's frame (+z up): a blue gradient, a warm
    ground and a broad sun lobe."""
    up = np.clip(z, 0, None)
    sun = np.array([0.45, 0.3, 0.84])
    sun /= np.linalg.norm(sun)
    lobe = np.clip(x * sun[0] + y * sun[1] + z * sun[2], 0, None) ** 3
    rgb = [0.25 + 0.35 * up + 3.0 * lobe, 0.35 + 0.4 * up + 2.6 * lobe, 0.55 + 0.5 * up + 2.0 * lobe]
    ground = z < 0
    g = [0.3, 0.25, 0.2]
    return np.stack([np.where(ground, g[c] * (0.7 + 0.3 * (1 + z)), rgb[c]) for c in range(3)], -1)


SKY_N = 128


def sky_octahedral():
    n = SKY_N
    c = (np.arange(n) + 0.5) / n
    v, u = np.meshgrid(c, c, indexing="ij")  # row = v (from the top), column = u
    return sky_radiance(*square_to_sphere(u, v)).astype(np.float32)


def sky_latlong(oct_img, h=256, ss=4):
    """Mitsuba's envmap layout: column u = phi / 2pi with direction
    (sin t sin phi, cos t, -sin t cos phi), row v = t / pi from the top."""
    n = oct_img.shape[0]
    w = 2 * h
    acc = np.zeros((h, w, 3))
    wsum = np.zeros((h, 1, 1))
    for a in range(ss):
        for b in range(ss):
            t = (np.arange(h)[:, None] + (a + 0.5) / ss) * np.pi / h
            p = (np.arange(w)[None, :] + (b + 0.5) / ss) * 2 * np.pi / w
            st = np.sin(t)
            wx, wy, wz = st * np.sin(p), np.cos(t) * np.ones_like(p), -st * np.cos(p)
            # world = Rotate(-90 about x) light: light = (wx, -wz, wy)
            su, sv = sphere_to_square(wx, -wz, wy)
            col = np.clip((su * n).astype(int), 0, n - 1)
            row = np.clip((sv * n).astype(int), 0, n - 1)
            acc += oct_img[row, col] * st[..., None]
            wsum += st[..., None]
    return (acc / wsum).astype(np.float32)


# -------------------------------------------------------------- the cloud

PERM = [
    151, 160, 137, 91, 90, 15, 131, 13, 201, 95, 96, 53, 194, 233, 7, 225, 140, 36, 103, 30, 69,
    142, 8, 99, 37, 240, 21, 10, 23, 190, 6, 148, 247, 120, 234, 75, 0, 26, 197, 62, 94, 252, 219,
    203, 117, 35, 11, 32, 57, 177, 33, 88, 237, 149, 56, 87, 174, 20, 125, 136, 171, 168, 68, 175,
    74, 165, 71, 134, 139, 48, 27, 166, 77, 146, 158, 231, 83, 111, 229, 122, 60, 211, 133, 230,
    220, 105, 92, 41, 55, 46, 245, 40, 244, 102, 143, 54, 65, 25, 63, 161, 1, 216, 80, 73, 209, 76,
    132, 187, 208, 89, 18, 169, 200, 196, 135, 130, 116, 188, 159, 86, 164, 100, 109, 198, 173,
    186, 3, 64, 52, 217, 226, 250, 124, 123, 5, 202, 38, 147, 118, 126, 255, 82, 85, 212, 207, 206,
    59, 227, 47, 16, 58, 17, 182, 189, 28, 42, 223, 183, 170, 213, 119, 248, 152, 2, 44, 154, 163,
    70, 221, 153, 101, 155, 167, 43, 172, 9, 129, 22, 39, 253, 19, 98, 108, 110, 79, 113, 224, 232,
    178, 185, 112, 104, 218, 246, 97, 228, 251, 34, 242, 193, 238, 210, 144, 12, 191, 179, 162,
    241, 81, 51, 145, 235, 249, 14, 239, 107, 49, 192, 214, 31, 181, 199, 106, 157, 184, 84, 204,
    176, 115, 121, 50, 45, 127, 4, 150, 254, 138, 236, 205, 93, 222, 114, 67, 29, 24, 72, 243, 141,
    128, 195, 78, 66, 215, 61, 156, 180]
NOISE_PERM = np.array(PERM + PERM)


def _grad(x, y, z, dx, dy, dz):
    h = NOISE_PERM[NOISE_PERM[NOISE_PERM[x] + y] + z] & 15
    u = np.where((h < 8) | (h == 12) | (h == 13), dx, dy)
    v = np.where((h < 4) | (h == 12) | (h == 13), dy, dz)
    return np.where(h & 1, -u, u) + np.where(h & 2, -v, v)


def _weight(t):
    return 6 * t**5 - 15 * t**4 + 10 * t**3


def noise(x, y, z):
    """pbrt's Noise(x, y, z)."""
    x, y, z = (np.fmod(c, float(1 << 30)) for c in (x, y, z))
    fx, fy, fz = np.floor(x), np.floor(y), np.floor(z)
    dx, dy, dz = x - fx, y - fy, z - fz
    ix, iy, iz = (f.astype(np.int64) & 255 for f in (fx, fy, fz))
    w = {}
    for a in (0, 1):
        for b in (0, 1):
            for c in (0, 1):
                w[a, b, c] = _grad(ix + a, iy + b, iz + c, dx - a, dy - b, dz - c)
    wx, wy, wz = _weight(dx), _weight(dy), _weight(dz)
    lerp = lambda t, a, b: (1 - t) * a + t * b  # noqa: E731
    x00, x10 = lerp(wx, w[0, 0, 0], w[1, 0, 0]), lerp(wx, w[0, 1, 0], w[1, 1, 0])
    x01, x11 = lerp(wx, w[0, 0, 1], w[1, 0, 1]), lerp(wx, w[0, 1, 1], w[1, 1, 1])
    return lerp(wz, lerp(wy, x00, x10), lerp(wy, x01, x11))


def dnoise(x, y, z):
    """pbrt's DNoise: forward differences with delta 0.01."""
    d = 0.01
    n = noise(x, y, z)
    return ((noise(x + d, y, z) - n) / d, (noise(x, y + d, z) - n) / d, (noise(x, y, z + d) - n) / d)


def cloud_density(x, y, z, density, wispiness, frequency):
    """pbrt's CloudMedium::Density at medium-space points."""
    px, py, pz = frequency * x, frequency * y, frequency * z
    if wispiness > 0:
        vomega, vlambda = 0.05 * wispiness, 10.0
        for _ in range(2):
            gx, gy, gz = dnoise(vlambda * px, vlambda * py, vlambda * pz)
            px, py, pz = px + vomega * gx, py + vomega * gy, pz + vomega * gz
            vomega *= 0.5
            vlambda *= 1.99
    d = np.zeros_like(px)
    omega, lam = 0.5, 1.0
    for _ in range(5):
        d += omega * noise(lam * px, lam * py, lam * pz)
        omega *= 0.5
        lam *= 1.99
    d = np.clip((1 - y) * 4.5 * density * d, 0, 1)
    d += 2 * np.maximum(0, 0.5 - y)
    return np.clip(d, 0, 1)


CLOUD = dict(density=1.2, wispiness=0.6, frequency=2.0)
CLOUD_N = 32  # fogbank's resolution: ceil(16 * frequency * extent) for the box [0, 1]^3


def cloud_grid():
    c = (np.arange(CLOUD_N) + 0.5) / CLOUD_N
    z, y, x = np.meshgrid(c, c, c, indexing="ij")
    return cloud_density(x, y, z, **CLOUD).astype(np.float32)


def pbrt_floats(a):
    """x fastest, as pbrt's grids (and the [z, y, x] arrays' C order)."""
    return " ".join(f"{v:.6g}" for v in np.asarray(a, dtype=np.float32).ravel())


def write_nvdb(path, d):
    import pyopenvdb as vdb

    g = vdb.FloatGrid()
    g.copyFromArray(np.ascontiguousarray(np.transpose(d, (2, 1, 0))))  # [x, y, z]
    g.transform = vdb.createLinearTransform(voxelSize=BLOB_VOXEL)
    g.name = "density"
    g.gridClass = vdb.GridClass.FOG_VOLUME
    with tempfile.TemporaryDirectory() as tmp:
        src = os.path.join(tmp, "blob.vdb")
        vdb.write(src, grids=[g])
        subprocess.run(["nanovdb_convert", "-f", "-z", src, path], check=True)


def main():
    os.makedirs(MI_DATA, exist_ok=True)
    os.makedirs(os.path.join(PBRT, "data"), exist_ok=True)
    d = blob()
    try:
        write_nvdb(os.path.join(PBRT, "data", "blob.nvdb"), d)
    except ImportError:
        print("no pyopenvdb: data/blob.nvdb not written")
    lo, hi = -0.5 * BLOB_VOXEL, (BLOB_N - 0.5) * BLOB_VOXEL
    write_vol(os.path.join(MI_DATA, "blob.vol"), d, (lo, lo, lo, hi, hi, hi))
    u = ugrid()
    write_vol(os.path.join(MI_DATA, "ugrid.vol"), u, (0, 0, 0, 1, 1, 1))
    with open(os.path.join(PBRT, "data", "ugrid_density.txt"), "w") as f:
        f.write(pbrt_floats(u) + "\n")
    a, s = rgb_grids()
    write_vol(os.path.join(MI_DATA, "rgb_sigma_t.vol"), a + s, (0, 0, 0, 1, 1, 1))
    with open(os.path.join(PBRT, "data", "rgb_sigma_a.txt"), "w") as f:
        f.write(pbrt_floats(a) + "\n")
    with open(os.path.join(PBRT, "data", "rgb_sigma_s.txt"), "w") as f:
        f.write(pbrt_floats(s) + "\n")
    try:
        import mitsuba as mi

        mi.set_variant("scalar_rgb")
        oct_img = sky_octahedral()
        mi.Bitmap(oct_img).write(os.path.join(PBRT, "data", "sky_oct.exr"))
        latlong = mi.Bitmap(sky_latlong(oct_img)).convert(component_format=mi.Struct.Type.Float16)
        latlong.write(os.path.join(MI_DATA, "sky_latlong.exr"))
    except ImportError:
        print("no mitsuba: the sky's EXRs not written")
    # The cloud's world box: medium [0, 1]^3 under Translate -1 -0.6 -1, Scale 2.
    write_vol(os.path.join(MI_DATA, "cloud.vol"), cloud_grid(), (-1, -0.6, -1, 1, 1.4, 1))
    print("assets written under", PBRT)


if __name__ == "__main__":
    sys.exit(main())
