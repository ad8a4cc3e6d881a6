"""Scenes from files, dicts and the built-in default, changed with the
command line's dotted keys; errors name the key or file."""

import sys

import numpy as np
import pytest

import fogbank
from conftest import assert_same_image, scene_path


def test_load_set_get_and_copy():
    s = fogbank.load(scene_path("transmittance.toml"), **{"camera.width": 20, "camera.height": 10})
    assert (s.width, s.height) == (20, 10)
    assert s.integrator == "transmittance"
    c = s.copy()
    assert s.set("media.0.sigma_t_scale", 40) is s
    assert s.get("media.0.sigma_t_scale") == 40.0
    assert c.get("media.0.sigma_t_scale") == 8.0
    s.set("integrator.estimator", "jackknife")
    assert s.estimator == "jackknife"
    s.set("camera.from", np.array([0.0, 0.1, 2.5]))
    assert s.get("camera.from") == pytest.approx([0.0, 0.1, 2.5])
    with pytest.raises(KeyError, match="camera.nope"):
        s.get("camera.nope")


@pytest.mark.skipif(sys.version_info < (3, 11), reason="tomllib is Python 3.11's")
def test_to_toml_round_trips():
    import tomllib

    s = fogbank.load(scene_path("cloud_ground.toml"), **{"camera.width": 16, "camera.height": 12})
    again = fogbank.load_dict(tomllib.loads(s.to_toml()), base=str(scene_path("")))
    assert again.to_toml() == s.to_toml()
    assert_same_image(fogbank.render(s, spp=2, progress=False), fogbank.render(again, spp=2, progress=False))
    assert fogbank.load_dict(s.to_dict(), base=str(scene_path(""))).to_toml() == s.to_toml()


def test_mitsuba_parameters_and_overrides():
    s = fogbank.load(scene_path("mitsuba/users_clip_fog.xml"), **{"camera.width": 16, "camera.height": 12})
    assert (s.width, s.height) == (16, 12)
    with pytest.raises(ValueError):
        fogbank.load(scene_path("mitsuba/users_clip_fog.xml"), **{"camera.widht": 16})


def test_errors_name_the_key_or_file(tmp_path):
    s = fogbank.default_scene()
    before = s.to_toml()
    with pytest.raises(ValueError, match="sigma_t_scal"):
        s.set("media.0.sigma_t_scal", 40)
    assert s.to_toml() == before, "a refused set leaves the scene as it was"
    with pytest.raises(ValueError, match="out of range"):
        s.set("media.7.sigma_t_scale", 1)
    with pytest.raises(TypeError, match="None"):
        s.set("render.spp", None)
    with pytest.raises(FileNotFoundError, match="nope.toml"):
        fogbank.load(tmp_path / "nope.toml")
    bad = tmp_path / "bad.toml"
    bad.write_text("[camera]\nwidth = \n")
    with pytest.raises(ValueError, match="line 2"):
        fogbank.load(bad)
    missing_vol = tmp_path / "m.toml"
    missing_vol.write_text('[[media]]\ndensity = { vol = "gone.vol" }\n')
    with pytest.raises(FileNotFoundError, match="gone.vol"):
        fogbank.load(missing_vol)
    with pytest.raises(ValueError, match="estimator"):
        s.set("integrator.estimator", "jackknif")
    with pytest.raises(TypeError, match="dict keys"):
        fogbank.load_dict({"camera": {1: 2}})


def test_default_scene_and_media():
    s = fogbank.default_scene()
    assert len(s.media) == 1
    m = s.media[0]
    lo, hi = m.bounds
    assert all(a < b for a, b in zip(lo, hi))
    assert "fogbank.Scene" in repr(s) and "fogbank.Medium" in repr(m)
