"""Shared fixtures of the Python suite. `cargo test` runs it
(`crates/cli/tests/suite/python.rs`), which sets FOGBANK_CLI to the
`fogbank` binary of the same build and FOGBANK_REPO to the checkout; run by
hand, both are found from this file's place."""

import os
import pathlib
import shutil
import subprocess

import numpy as np
import pytest

import fogbank

REPO = pathlib.Path(os.environ.get("FOGBANK_REPO", pathlib.Path(__file__).resolve().parents[2]))


def required(name: str) -> bool:
    return os.environ.get(f"FOGBANK_REQUIRE_{name}") == "1"


def skip_unless_required(name: str, why: str):
    """Skips (saying why), or fails when FOGBANK_REQUIRE_<name>=1."""
    if required(name):
        pytest.fail(f"{why} (FOGBANK_REQUIRE_{name}=1)")
    pytest.skip(why)


@pytest.fixture(scope="session")
def cli():
    """Runs the `fogbank` command; returns a function of its arguments."""
    exe = os.environ.get("FOGBANK_CLI") or shutil.which("fogbank")
    if not exe:
        exe = str(REPO / "target" / "release" / "fogbank")
        if not os.path.exists(exe):
            pytest.skip("no fogbank binary (set FOGBANK_CLI)")

    def run(*args, cwd=None):
        r = subprocess.run([exe, *map(str, args)], capture_output=True, text=True, cwd=cwd)
        assert r.returncode == 0, f"fogbank {' '.join(map(str, args))}: {r.stderr}"
        return r

    return run


@pytest.fixture
def small():
    """Overrides that make a scene cheap to render."""
    return {"camera.width": 32, "camera.height": 24}


def scene_path(name: str) -> pathlib.Path:
    return REPO / "scenes" / name


def assert_same_image(a, b, what=""):
    """Bit for bit: mean and variance."""
    assert a.mean.shape == b.mean.shape, what
    assert np.array_equal(a.mean, b.mean), f"{what}: means differ at {np.argwhere(a.mean != b.mean)[:5]}"
    if a.variance is None or b.variance is None:
        assert a.variance is None and b.variance is None, what
    else:
        assert np.array_equal(a.variance, b.variance), f"{what}: variances differ"


def write_vol(path, array, bbox):
    """A Mitsuba `.vol` (version 3, float32) of a (z, y, x) array, as
    Mitsuba's own `VolumeGrid.write` lays it out."""
    a = np.ascontiguousarray(array, dtype="<f4")
    channels = 1 if a.ndim == 3 else a.shape[3]
    nz, ny, nx = a.shape[:3]
    header = b"VOL" + bytes([3]) + np.array([1, nx, ny, nz, channels], "<i4").tobytes()
    header += np.array(list(bbox[0]) + list(bbox[1]), "<f4").tobytes()
    pathlib.Path(path).write_bytes(header + a.tobytes())


__all__ = ["REPO", "fogbank", "scene_path", "assert_same_image", "write_vol", "skip_unless_required"]
