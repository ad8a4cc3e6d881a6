#!/usr/bin/env python3
"""fogbank on Mitsuba 3's own test scenes, as a new user would try them: every
scene XML of a `mitsuba-data` checkout's `tests/scenes/` (with its
`include/` and `fragments/` files and the shared `common/` folder) rendered
by `fogbank render`; for each, whether fogbank reads it (or its refusal) and,
when a Mitsuba RGB reference of it is there, the ratio of the image means
and the relative L1 distance of the images.

    python3 tools/mitsuba_data_check.py MITSUBA_DATA [--fogbank target/release/fogbank] [--spp 1024]

Needs numpy and mitsuba (to read the EXR references); never part of CI.
"""

import argparse
import glob
import os
import subprocess
import sys
import tempfile

import numpy as np

TOOLS = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, TOOLS)
import mitsuba_common as mc  # noqa: E402


def reference(scene):
    """The Mitsuba RGB reference of `scene` in the data's naming, if any."""
    d, stem = os.path.dirname(scene), os.path.basename(scene)[:-4]
    base = stem
    for suffix in ("_volpathmis", "_volpath", "_path", "_direct", "_ptracer"):
        if base.endswith(suffix):
            base = base[: -len(suffix)]
    found = glob.glob(os.path.join(d, "refs", base + "_ref_rgb.exr"))
    found += glob.glob(os.path.join(d, base + "*scalar_rgb.exr"))
    return found[0] if found else None


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("data", help="a mitsuba-data checkout")
    ap.add_argument("--fogbank", default=os.path.join(os.path.dirname(TOOLS), "target", "release", "fogbank"))
    ap.add_argument("--spp", type=int, default=1024)
    args = ap.parse_args()
    fogbank = os.path.abspath(args.fogbank)
    import mitsuba as mi

    mi.set_variant("scalar_rgb")
    root = os.path.join(os.path.abspath(args.data), "tests", "scenes")
    scenes = sorted(p for p in glob.glob(os.path.join(root, "*", "*.xml")))
    out = tempfile.mkdtemp()
    read = 0
    for scene in scenes:
        name = os.path.relpath(scene, root)
        exr = os.path.join(out, name.replace("/", "_") + ".exr")
        r = subprocess.run([fogbank, "render", os.path.basename(scene), "--spp", str(args.spp), "--quiet",
                            "-o", exr], cwd=os.path.dirname(scene), capture_output=True, text=True)
        if r.returncode:
            print(f"{name}: refused: {r.stderr.strip().splitlines()[-1]}")
            continue
        read += 1
        ref = reference(scene)
        if ref is None:
            print(f"{name}: read (no RGB reference)")
            continue
        want, got = mc.read_exr(mi, ref)[0], mc.read_exr(mi, exr)[0]
        if want.shape != got.shape:
            print(f"{name}: read; reference {want.shape} against {got.shape}")
            continue
        ratio = got.mean(axis=(0, 1)) / np.maximum(want.mean(axis=(0, 1)), 1e-12)
        rel_l1 = np.abs(got - want).sum() / max(np.abs(want).sum(), 1e-12)
        print(f"{name}: mean ratio {np.round(ratio, 4).tolist()}, relative L1 {rel_l1:.4f}")
    print(f"{read} of {len(scenes)} scenes read")


if __name__ == "__main__":
    main()
