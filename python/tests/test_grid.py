"""Volumes from numpy: a scene whose density is a numpy array renders bit
for bit as the same scene reading the same voxels from a `.vol` file; any
float dtype and memory order reads the same values; bad arrays raise
naming the argument."""

import numpy as np
import pytest

import fogbank
from conftest import REPO, assert_same_image, write_vol

# Exact in float32, as a .vol file stores its box.
BBOX = ((-0.625, -0.375, -0.5), (0.625, 0.5, 0.4375))


def volume(shape=(20, 24, 28), seed=4):
    """A (z, y, x) field with structure in every axis and empty margins."""
    rng = np.random.default_rng(seed)
    z, y, x = np.meshgrid(*(np.linspace(-1, 1, n) for n in shape), indexing="ij")
    blob = np.exp(-3.0 * (x**2 + 1.7 * y**2 + 0.8 * z**2)) * (1.0 + 0.3 * np.sin(7 * x + 3 * y))
    return (blob * (rng.random(shape) > 0.1)).astype(np.float32)


def scene(density, **over):
    over.setdefault("camera.width", 40)
    over.setdefault("camera.height", 30)
    d = {"camera": {"from": [0.3, 0.4, 2.0], "to": [0, 0, 0], "fov": 40.0},
         "media": [{"density": density, "sigma_t_scale": 12.0, "albedo": [0.9, 0.8, 0.7]}],
         "lights": [{"type": "constant", "radiance": [0.5, 0.6, 0.9]},
                    {"type": "directional", "direction": [-0.4, -0.8, -0.3], "irradiance": [3.0, 3.0, 3.0]}],
         "integrator": {"type": "volpath", "max_depth": 6}}
    s = fogbank.load_dict(d)
    for k, v in over.items():
        s.set(k, v)
    return s


def test_numpy_density_equals_the_vol_file_bit_for_bit(tmp_path):
    a = volume()
    write_vol(tmp_path / "d.vol", a, BBOX)
    from_file = scene({"vol": str(tmp_path / "d.vol")})
    from_numpy = scene(fogbank.Grid(a, bbox=BBOX))
    assert_same_image(fogbank.render(from_numpy, spp=4, progress=False),
                      fogbank.render(from_file, spp=4, progress=False), "volpath")
    for e in ["ratio_tracking", "jackknife"]:
        t = {"integrator.type": "transmittance", "integrator.estimator": e}
        assert_same_image(fogbank.render(scene(fogbank.Grid(a, bbox=BBOX), **t), spp=2, progress=False),
                          fogbank.render(scene({"vol": str(tmp_path / "d.vol")}, **t), spp=2, progress=False), e)


def test_every_dtype_and_memory_order_reads_the_same_values():
    a = volume((9, 10, 11))
    ref = fogbank.render(scene(fogbank.Grid(a)), spp=2, progress=False)
    f16 = a.astype(np.float16)
    for variant, expect in [(np.asfortranarray(a), a), (a.astype(np.float64), a),
                            (a.astype(">f4"), a), (f16, f16.astype(np.float32)),
                            (np.ascontiguousarray(a[::-1])[::-1], a)]:
        g = fogbank.Grid(variant)
        assert np.array_equal(np.asarray(g.to_numpy(), dtype=np.float32), np.asarray(variant, dtype=np.float32))
        img = fogbank.render(scene(g), spp=2, progress=False)
        if expect is a:
            assert_same_image(img, ref, str(variant.dtype))
    g = fogbank.Grid(a)
    assert g.to_numpy() is a, "a numpy grid is read in place, not copied"
    assert g.shape == [9, 10, 11] and g.channels == 1


def test_grids_serve_albedo_emission_and_velocity():
    a = volume((8, 8, 8))
    rgb = np.stack([a, 0.5 * a, 0.25 * a], axis=-1)
    s = scene(fogbank.Grid(a))
    s.set("media.0.albedo_grid", fogbank.Grid(np.clip(rgb + 0.2, 0, 1)))
    s.set("media.0.emission", {"grid": fogbank.Grid(a), "scale": 2.0, "color": [1.0, 0.5, 0.2]})
    img = fogbank.render(s, spp=1, progress=False)
    assert np.isfinite(img.mean).all() and img.mean.max() > 0
    s.set("media.0.velocity", fogbank.Grid(rgb))
    with pytest.raises(ValueError, match="a velocity has 3"):
        s.set("media.0.velocity", fogbank.Grid(a))


def test_read_volume_gives_what_the_scene_reads(tmp_path):
    a = volume((6, 7, 8))
    write_vol(tmp_path / "v.vol", a, BBOX)
    g = fogbank.read_volume(tmp_path / "v.vol")
    assert np.array_equal(g.to_numpy(), a)
    xf = np.array(g.index_to_world)
    assert np.allclose(xf @ [0, 0, 0, 1], list(BBOX[0]) + [1]) and np.allclose(xf @ [8, 7, 6, 1], list(BBOX[1]) + [1])
    again = fogbank.Grid(g.to_numpy(), index_to_world=g.index_to_world)
    assert np.array_equal(np.array(again.index_to_world), xf)
    with pytest.raises(ValueError, match="index_to_world: give it alone"):
        fogbank.Grid(a, index_to_world=xf, bbox=BBOX)
    sphere = fogbank.read_volume(REPO / "data" / "sphere.vdb", grid="ls_sphere")
    assert sphere.to_numpy().max() <= 1.0 and sphere.to_numpy().min() >= 0.0
    with pytest.raises(ValueError, match="max_voxels"):
        fogbank.read_volume(tmp_path / "v.vol", max_voxels=100)
    with pytest.raises(FileNotFoundError, match="nope.vol"):
        fogbank.read_volume(tmp_path / "nope.vol")
    with pytest.raises(ValueError, match="unknown volume format"):
        fogbank.read_volume(tmp_path / "v.txt")


def test_bad_arrays_raise_naming_the_argument():
    with pytest.raises(ValueError, match=r"array: value NaN at \[1, 2, 3\]"):
        a = np.zeros((4, 4, 4), np.float32)
        a[1, 2, 3] = np.nan
        fogbank.Grid(a)
    with pytest.raises(ValueError, match="array: value inf"):
        fogbank.Grid(np.full((2, 2, 2), np.inf))
    with pytest.raises(ValueError, match=r"array: shape \[4, 4\]"):
        fogbank.Grid(np.zeros((4, 4), np.float32))
    with pytest.raises(ValueError, match=r"array: shape \[2, 2, 2, 2\]"):
        fogbank.Grid(np.zeros((2, 2, 2, 2), np.float32))
    with pytest.raises(TypeError, match="array: dtype int32"):
        fogbank.Grid(np.zeros((2, 2, 2), np.int32))
    with pytest.raises(TypeError, match="array: expected a numpy array"):
        fogbank.Grid([[[1.0]]])
    with pytest.raises(ValueError, match="bbox"):
        fogbank.Grid(np.zeros((2, 2, 2), np.float32), bbox=((0, 0, 0), (1, 0, 1)))
    with pytest.raises(ValueError, match="to_world: the last row"):
        fogbank.Grid(np.zeros((2, 2, 2), np.float32), to_world=np.ones((4, 4)))
    with pytest.raises(ValueError, match="array: grid dimensions"):
        fogbank.Grid(np.zeros((0, 2, 2), np.float32))


def test_a_grid_outlives_nothing_it_needs():
    s = scene(fogbank.Grid(volume((5, 5, 5))))
    import gc

    gc.collect()
    s.set("render.spp", 2)  # rebuilds from the grid the scene keeps
    assert fogbank.render(s, progress=False).spp == 2
