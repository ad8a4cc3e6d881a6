"""The command line's studies and metrics from Python: `stats` gives the
arrays and summary `fogbank stats` writes, `compare` its metrics."""

import json

import numpy as np
import pytest

import fogbank
from conftest import scene_path

SMALL = {"camera.width": 12, "camera.height": 9, "media.0.density.resolution": 24}


def test_stats_equals_the_command(cli, tmp_path):
    s = fogbank.load(scene_path("transmittance.toml"), **SMALL)
    st = fogbank.stats(s, estimator="ratio_tracking", runs=32, reference_estimator="analytic_trilinear",
                       out=tmp_path / "py")
    sets = [a for k, v in SMALL.items() for a in ("--set", f"{k}={v}")]
    cli("stats", scene_path("transmittance.toml"), "--estimator", "ratio_tracking", "--runs", 32,
        "--reference-estimator", "analytic_trilinear", "--out", tmp_path / "cli", *sets)
    ref = json.loads((tmp_path / "cli" / "summary.json").read_text())
    for k in ["mean_abs_bias", "mean_std", "rmse", "runs", "covered_pixels"]:
        assert st.summary[k] == ref[k], k
    assert st.mean.shape == (9, 12, 3) and st.bias is not None
    assert (tmp_path / "py" / "stats.exr").exists()
    with pytest.raises(ValueError, match="runs"):
        fogbank.stats(s, runs=0)
    with pytest.raises(ValueError, match="must be exact"):
        fogbank.stats(s, runs=4, reference_estimator="jackknife")


def test_converge_gives_a_curve_per_estimator():
    s = fogbank.load(scene_path("transmittance.toml"), **SMALL)
    c = fogbank.converge(s, ["ratio_tracking", "track_length"], seconds=0.3)
    assert set(c) == {"ratio_tracking", "track_length"}
    assert all(len(v["mse"]) > 0 for v in c.values())


def test_compare_metrics_on_arrays_images_and_files(tmp_path):
    s = fogbank.default_scene(**{"camera.width": 24, "camera.height": 16})
    # The z-test's per-pixel variances need tens of samples to be trusted.
    a = fogbank.render(s, spp=64, seed=1, progress=False)
    b = fogbank.render(s, spp=64, seed=2, progress=False)
    assert fogbank.compare(a, a, "rmse") == 0.0
    assert fogbank.compare(a, b, "rmse") > 0.0
    assert fogbank.compare(a, b, "ztest")["pass"]
    a.save(tmp_path / "a.exr")
    assert fogbank.compare(tmp_path / "a.exr", b.mean, "smape") == pytest.approx(fogbank.compare(a, b, "smape"))
    all_ = fogbank.compare(a, b, "all")
    assert set(all_) == {"rmse", "relmse", "smape", "flip", "ztest"} and "mean" in all_["flip"]
    with pytest.raises(ValueError, match="unknown metric"):
        fogbank.compare(a, b, "psnr")
    with pytest.raises(ValueError, match="size"):
        fogbank.compare(a, np.zeros((3, 3, 3), np.float32), "rmse")
    with pytest.raises(FileNotFoundError, match="nope.exr"):
        fogbank.compare(tmp_path / "nope.exr", a, "rmse")


def test_images_read_and_write(tmp_path):
    x = np.random.default_rng(0).random((5, 7, 3)).astype(np.float32)
    fogbank.write_image(tmp_path / "x.exr", x, variance=x * 0.1)
    back = fogbank.read_image(tmp_path / "x.exr")
    assert np.array_equal(back.mean, x) and np.allclose(back.variance, x * 0.1)
    bad = x.copy()
    bad[0, 0, 0] = np.nan
    fogbank.write_image(tmp_path / "n.exr", bad)
    assert np.isfinite(fogbank.read_image(tmp_path / "n.exr").mean).all(), "no NaN pixel reaches a file"
    with pytest.raises(ValueError, match="must end in"):
        fogbank.write_image(tmp_path / "x.jpg", x)
    with pytest.raises(ValueError, match="H×W×3"):
        fogbank.write_image(tmp_path / "x.exr", np.zeros((4, 4)))


def test_transfer_function_from_a_lut():
    lut = np.array([[0, 0, 0, 0], [1, 0.5, 0.2, 0.3], [1, 1, 1, 1]], float)
    t = fogbank.transfer_function(lut=lut, range=(10, 30))
    assert t["opacity"] == [[10.0, 0.0], [20.0, 0.3], [30.0, 1.0]]
    assert t["color"][1] == [20.0, 1.0, 0.5, 0.2]
    with pytest.raises(ValueError, match="lut"):
        fogbank.transfer_function(lut=np.zeros((3, 3)))
