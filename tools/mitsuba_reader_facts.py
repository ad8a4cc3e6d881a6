#!/usr/bin/env python3
"""What Mitsuba 3 itself makes of the XML conventions fogbank's reader follows,
stored for fogbank's tests (crates/scene/tests/fixtures/mitsuba_reader_facts.json):

- `sensors`: for perspective sensors written several ways (no fov, i.e. the
  default 50 mm focal length; `focal_length`; `fov` with every `fov_axis`;
  near and far clip), the rays of `sensor.sample_ray` at the four corners and
  the centre of the film (position samples (0,0), (1,0), (0,1), (1,1),
  (0.5,0.5)): origin, unit direction and the ray's length (`maxt`).
- `spectra`: for `<spectrum>` values (wavelength:value lists and constants)
  on an emitter, a reflectance, an unbounded texture (a conductor's eta) and
  a medium's sigma_t and albedo, the RGB values Mitsuba's `scalar_rgb`
  variant stores (read back with `mi.traverse`).

Each case keeps the XML it was made from, so the tests read the same text.

Usage (needs `pip install mitsuba==3.9.1`; never part of CI):

    python3 tools/mitsuba_reader_facts.py
"""

import json
import os
import sys

import mitsuba as mi

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
OUT = os.path.join(ROOT, "crates", "scene", "tests", "fixtures", "mitsuba_reader_facts.json")

LOOKAT = '<transform name="to_world"><lookat origin="1, 2, 3" target="0, 0.5, 0" up="0, 1, 0"/></transform>'

SENSORS = [
    ("default focal length", "", 64, 48),
    ("focal_length 35mm", '<string name="focal_length" value="35mm"/>', 64, 48),
    ("focal_length 35mm portrait", '<string name="focal_length" value="35mm"/>', 48, 64),
    ("focal_length 85", '<string name="focal_length" value="85"/>', 40, 30),
    ("fov 40 x", '<float name="fov" value="40"/>', 64, 48),
    ("fov 40 y", '<float name="fov" value="40"/><string name="fov_axis" value="y"/>', 64, 48),
    ("fov 40 diagonal", '<float name="fov" value="40"/><string name="fov_axis" value="diagonal"/>', 64, 48),
    ("fov 40 smaller", '<float name="fov" value="40"/><string name="fov_axis" value="smaller"/>', 64, 48),
    ("fov 40 smaller portrait", '<float name="fov" value="40"/><string name="fov_axis" value="smaller"/>', 48, 64),
    ("fov 40 larger", '<float name="fov" value="40"/><string name="fov_axis" value="larger"/>', 64, 48),
    ("fov 40 larger portrait", '<float name="fov" value="40"/><string name="fov_axis" value="larger"/>', 48, 64),
    ("near and far clip", '<float name="fov" value="50"/><float name="near_clip" value="0.75"/>'
                          '<float name="far_clip" value="6"/>', 32, 32),
    ("default clip", '<float name="fov" value="50"/>', 16, 8),
]

CORNERS = [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0), (0.5, 0.5)]

# (context, the XML of a scene around `{v}`, the traversed parameter's suffix)
CONTEXTS = {
    "emitter": ('<shape type="rectangle"><emitter type="area"><spectrum name="radiance" value="{v}"/></emitter></shape>',
                "emitter.radiance.value"),
    "reflectance": ('<shape type="rectangle"><bsdf type="diffuse"><spectrum name="reflectance" value="{v}"/></bsdf></shape>',
                    "bsdf.reflectance.value"),
    "unbounded": ('<shape type="rectangle"><bsdf type="conductor"><spectrum name="eta" value="{v}"/></bsdf></shape>',
                  "bsdf.eta.value"),
    "sigma_t": ('<medium type="homogeneous" id="m"><spectrum name="sigma_t" value="{v}"/></medium>'
                '<shape type="sphere"><ref name="interior" id="m"/><bsdf type="null"/></shape>',
                "m.sigma_t.value.value"),
    "albedo": ('<medium type="homogeneous" id="m"><spectrum name="albedo" value="{v}"/></medium>'
               '<shape type="sphere"><ref name="interior" id="m"/><bsdf type="null"/></shape>',
               "m.albedo.value.value"),
    "constvolume": ('<medium type="heterogeneous" id="m"><volume type="constvolume" name="sigma_t">'
                    '<spectrum name="value" value="{v}"/>'
                    '<transform name="to_world"><scale value="2"/></transform></volume></medium>'
                    '<shape type="sphere"><ref name="interior" id="m"/><bsdf type="null"/></shape>',
                    "m.sigma_t.value.value"),
}

VALUES = [
    "400:0, 500:0.3, 600:0.8, 700:1.1",
    "400:0.1, 500:0.3, 600:0.8, 700:0.9",
    "380:0.9, 450:0.2, 520:0.05, 650:0.6, 780:0.4",
    "360:0.25, 830:0.25",
    "550:1, 560:1",
    "400:1, 700:3",
    "0.5",
    "2.0",
]


def vec(v):
    return [float(v[0]), float(v[1]), float(v[2])]


def sensor_cases():
    out = []
    for name, params, w, h in SENSORS:
        xml = (f'<sensor type="perspective">{params}{LOOKAT}<film type="hdrfilm">'
               f'<integer name="width" value="{w}"/><integer name="height" value="{h}"/>'
               f'<rfilter type="box"/></film></sensor>')
        sensor = mi.load_string(f'<scene version="3.0.0">{xml}</scene>').sensors()[0]
        rays = []
        for u, v in CORNERS:
            ray, _ = sensor.sample_ray(0.0, 0.5, mi.Point2f(u, v), mi.Point2f(0.5, 0.5))
            rays.append({"sample": [u, v], "o": vec(ray.o), "d": vec(ray.d), "maxt": float(ray.maxt)})
        out.append({"name": name, "xml": xml, "width": w, "height": h, "rays": rays})
    return out


def spectrum_cases():
    out = []
    for ctx, (template, suffix) in CONTEXTS.items():
        for value in VALUES:
            xml = template.format(v=value)
            params = mi.traverse(mi.load_string(f'<scene version="3.0.0">{xml}</scene>'))
            keys = [k for k in params.keys() if k.endswith(suffix)]
            assert len(keys) == 1, (xml, list(params.keys()))
            rgb = params[keys[0]]
            rgb = [float(rgb)] * 3 if isinstance(rgb, float) else vec(rgb)
            out.append({"context": ctx, "value": value, "xml": xml, "rgb": rgb})
    return out


def main():
    mi.set_variant("scalar_rgb")
    facts = {
        "generator": "tools/mitsuba_reader_facts.py",
        "mitsuba": mi.__version__,
        "variant": mi.variant(),
        "sensors": sensor_cases(),
        "spectra": spectrum_cases(),
    }
    with open(OUT, "w") as f:
        json.dump(facts, f, indent=1)
    print("wrote", OUT, file=sys.stderr)


if __name__ == "__main__":
    main()
