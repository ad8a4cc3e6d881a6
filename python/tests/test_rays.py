"""Estimators on your own rays: on a scene's camera rays they are the
command's transmittance render, per pixel and bit for bit, for every
estimator; on an analytic medium the unbiased ones average to the exact
transmittance within a bound from their measured standard error."""

import numpy as np
import pytest

import fogbank
from conftest import scene_path

W, H = 16, 12


def transmittance_scene(estimator, **over):
    o = {"camera.width": W, "camera.height": H, "media.0.density.resolution": 32,
         "render.pixel_jitter": False, "integrator.estimator": estimator}
    o.update(over)
    return fogbank.load(scene_path("transmittance.toml"), **o)


@pytest.mark.parametrize("estimator", [e["name"] for e in fogbank.estimators()])
def test_estimates_are_the_commands_per_pixel(cli, tmp_path, estimator):
    out = tmp_path / "t.exr"
    cli("render", scene_path("transmittance.toml"), "--spp", 1, "--seed", 7, "--quiet", "-o", out,
        "--set", f"camera.width={W}", "--set", f"camera.height={H}", "--set", "media.0.density.resolution=32",
        "--set", "render.pixel_jitter=false", "--set", f"integrator.estimator={estimator}")
    s = transmittance_scene(estimator)
    o, d, t = s.camera_rays()
    est, lookups = fogbank.transmittance(s.media[0], o, d, t, estimator=estimator, seed=7)
    assert est.dtype == np.float64 and lookups.dtype == np.uint32 and est.shape == (W * H,)
    cli_mean = fogbank.read_image(out).mean[..., 0].ravel()
    assert np.array_equal(est.astype(np.float32), cli_mean), estimator


def analytic_rays(n=24, seed=2):
    rng = np.random.default_rng(seed)
    o = rng.uniform(-0.3, 0.3, (n, 3))
    o[:, 2] = -1.5
    d = np.column_stack([rng.uniform(-0.05, 0.05, n), rng.uniform(-0.05, 0.05, n), np.ones(n)])
    return o, d * 1.7  # not unit length: t is in units of d


def test_unbiased_estimators_average_to_the_exact_value():
    s = fogbank.load_dict({"media": [{"density": {"procedural": "sinusoid"}, "sigma_t_scale": 1.5}]})
    m = s.media[0]
    o, d = analytic_rays()
    exact, _ = fogbank.transmittance(m, o, d, np.inf, estimator="analytic_trilinear")
    assert np.all((exact > 0.02) & (exact < 0.98)), exact
    k = 4000
    for e in fogbank.estimators():
        est, _ = fogbank.transmittance(m, o, d, np.inf, estimator=e["name"], seed=11, per_ray=k)
        assert est.shape == (len(o), k) and np.isfinite(est).all()
        if e["biased"]:
            continue
        mean, se = est.mean(axis=1), est.std(axis=1, ddof=1) / np.sqrt(k)
        exact_rows = np.abs(mean - exact) <= np.maximum(5.0 * se, 1e-6)
        assert exact_rows.all(), f"{e['name']}: rays {np.nonzero(~exact_rows)[0]}: {mean} vs {exact}"
        z = (mean - exact).sum() / max(np.sqrt((se**2).sum()), 1e-12)
        assert abs(z) < 4.5 or np.abs(mean - exact).max() < 1e-6, f"{e['name']}: pooled z = {z}"


def test_results_do_not_depend_on_threads_and_grids_work_as_media():
    g = fogbank.Grid(np.full((8, 8, 8), 1.0, np.float32))
    o, _ = analytic_rays(8)
    d = np.tile([0.0, 0.0, 1.7], (len(o), 1))
    a = fogbank.transmittance(g, o, d, np.inf, estimator="ratio_tracking", per_ray=64, threads=1, sigma_t_scale=2.0)
    b = fogbank.transmittance(g, o, d, np.inf, estimator="ratio_tracking", per_ray=64, threads=2, sigma_t_scale=2.0)
    assert np.array_equal(a[0], b[0]) and np.array_equal(a[1], b[1])
    exact = fogbank.transmittance(g, o, d, np.inf, estimator="analytic_trilinear", sigma_t_scale=2.0)[0]
    # Every ray crosses the grid's centred box [-½, ½]³ along z: τ = 2 · 1.
    assert np.allclose(exact, np.exp(-2.0), rtol=1e-5)


def test_free_flights_escape_as_often_as_the_transmittance():
    s = fogbank.load_dict({"media": [{"density": {"procedural": "sinusoid"}, "sigma_t_scale": 1.5}]})
    o, d = analytic_rays(6)
    exact, _ = fogbank.transmittance(s.media[0], o, d, np.inf, estimator="analytic_trilinear")
    k = 20000
    for sampler in ["delta_tracking", "decomposition_tracking", "regular_tracking"]:
        t, w, n = fogbank.sample_distance(s.media[0], o, d, np.inf, sampler=sampler, per_ray=k, seed=3)
        escaped = np.isinf(t).mean(axis=1)
        se = np.sqrt(exact * (1 - exact) / k)
        assert np.all(np.abs(escaped - exact) < 5 * se), (sampler, escaped, exact)
        assert np.all(w == 1.0)
    t, w, _ = fogbank.sample_distance(s.media[0], o, d, np.inf, sampler="equiangular", light=(0, 1, 0), per_ray=8)
    assert np.isfinite(t).all() and np.all(w > 0)
    with pytest.raises(ValueError, match="light="):
        fogbank.sample_distance(s.media[0], o, d, np.inf, sampler="equiangular")
    with pytest.raises(ValueError, match="unknown sampler `delta`"):
        fogbank.sample_distance(s.media[0], o, d, np.inf, sampler="delta")
    with pytest.raises(ValueError, match="analytic"):
        fogbank.sample_distance(s.media[0], o, d, np.inf, sampler="analytic_trilinear")


def test_bad_rays_and_options_raise_naming_them():
    s = fogbank.default_scene()
    m = s.media[0]
    o = np.zeros((2, 3))
    with pytest.raises(ValueError, match="unknown estimator `jackknif`"):
        fogbank.transmittance(m, o, o + 1, 1.0, estimator="jackknif")
    with pytest.raises(ValueError, match="ray 1: direction is zero"):
        fogbank.transmittance(m, o, np.array([[0, 0, 1.0], [0, 0, 0]]), 1.0)
    with pytest.raises(ValueError, match="directions: expected an N×3"):
        fogbank.transmittance(m, o, np.ones((2, 2)), 1.0)
    with pytest.raises(ValueError, match="one entry per ray"):
        fogbank.transmittance(m, o, o + 1, np.ones(3))
    with pytest.raises(ValueError, match="roulete: not an option of ratio_tracking"):
        fogbank.transmittance(m, o, o + 1, 1.0, estimator="ratio_tracking", roulete=0.1)
    with pytest.raises(ValueError, match="sigma_t_scale"):
        fogbank.transmittance(m, o, o + 1, 1.0, sigma_t_scale=2.0)
    with pytest.raises(TypeError, match="medium"):
        fogbank.transmittance("cloud", o, o + 1, 1.0)
    names = {e["name"] for e in fogbank.estimators()}
    assert {"jackknife", "ratio_tracking", "track_length"} <= names
