#!/usr/bin/env python3
"""Writes crates/render/src/world/surfaces/conductor_table.rs: the RGB complex
index of refraction (eta, k) that Mitsuba 3's RGB variants give each named
conductor `material` (Mitsuba integrates its measured spectra, the
`data/ior/*.spd` files of its package, against the CIE curves without D65
and without clamping: `complex_ior_from_file`). Read back from Mitsuba
itself with `mi.traverse`.

Usage (needs `pip install mitsuba==3.9.1`; never part of CI):

    python3 tools/mitsuba_conductors.py
"""

import glob
import os

import mitsuba as mi

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
OUT = os.path.join(ROOT, "crates", "render", "src", "world", "surfaces", "conductor_table.rs")


def main():
    mi.set_variant("scalar_rgb")
    data = os.path.join(os.path.dirname(mi.__file__), "data", "ior")
    names = sorted({os.path.basename(p)[: -len(".eta.spd")] for p in glob.glob(os.path.join(data, "*.eta.spd"))})
    rows = []
    for name in names:
        xml = (f'<scene version="3.0.0"><shape type="rectangle"><bsdf type="conductor">'
               f'<string name="material" value="{name}"/></bsdf></shape></scene>')
        p = mi.traverse(mi.load_string(xml))
        eta = [float(x) for x in p[[k for k in p.keys() if k.endswith("bsdf.eta.value")][0]]]
        k = [float(x) for x in p[[k for k in p.keys() if k.endswith("bsdf.k.value")][0]]]
        rows.append((name, eta, k))
    with open(OUT, "w") as f:
        f.write("//! Named conductors (`material = \"Au\"`, see `conductors`):\n")
        f.write("//! the RGB complex IOR (η, k) Mitsuba 3's RGB variants derive from their\n")
        f.write("//! measured spectra. Written by `tools/mitsuba_conductors.py` from Mitsuba\n")
        f.write(f"//! {mi.__version__} `scalar_rgb`; do not edit by hand.\n\n")
        f.write("/// (name, η, k) for every material Mitsuba knows.\n")
        f.write("#[rustfmt::skip]\n")
        f.write(f"pub const CONDUCTORS: [(&str, [f32; 3], [f32; 3]); {len(rows)}] = [\n")
        for name, eta, k in rows:
            f.write(f'    ("{name}", [{eta[0]:.6}, {eta[1]:.6}, {eta[2]:.6}], [{k[0]:.6}, {k[1]:.6}, {k[2]:.6}]),\n')
        f.write("];\n")
    print("wrote", OUT, len(rows), "materials")


if __name__ == "__main__":
    main()
