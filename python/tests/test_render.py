"""The same image through every door: `fogbank.render` of a scene equals
`fogbank render` of the same file, seed and spp bit for bit (mean and
variance) on the CPU, whatever the thread count; on a GPU (lavapipe in CI)
it passes the per-pixel z-test against the CPU."""

import numpy as np
import pytest

import fogbank
from conftest import assert_same_image, scene_path, skip_unless_required

# The default scene, a medium over a ground plane, and a Mitsuba scene
# (dielectric boundaries around media) as Mitsuba users write them.
PEERS = [None, "cloud_ground.toml", "mitsuba/dielectric_media.xml"]


def load(name, **over):
    return fogbank.default_scene(**over) if name is None else fogbank.load(scene_path(name), **over)


@pytest.mark.parametrize("name", PEERS)
def test_render_equals_the_command_bit_for_bit(cli, tmp_path, name, small):
    out = tmp_path / "cli.exr"
    sets = [a for k, v in small.items() for a in ("--set", f"{k}={v}")]
    scene_arg = [] if name is None else [scene_path(name)]
    cli("render", *scene_arg, "--spp", 4, "--seed", 3, "--quiet", "-o", out, *sets)
    img = fogbank.render(load(name, **small), spp=4, seed=3, progress=False)
    assert_same_image(img, fogbank.read_image(out), f"{name}")
    assert img.spp == 4 and img.stats["spp"] == 4 and img.stats["seed"] == 3


def test_threads_and_progress_do_not_change_the_image(small):
    s = fogbank.default_scene(**small)
    a = fogbank.render(s, spp=3, threads=1, progress=False)
    seen = []
    b = fogbank.render(s, spp=3, threads=2, progress=seen.append)
    assert_same_image(a, b)
    assert seen and seen[-1] == 3 * s.width * s.height


def test_saved_files_are_the_commands(cli, tmp_path, small):
    s = fogbank.default_scene(**small)
    img = fogbank.render(s, spp=2, progress=False)
    img.save(tmp_path / "py.exr")
    img.save(tmp_path / "py.png")
    cli("render", "--spp", 2, "--quiet", "-o", tmp_path / "cli.png", "--set", "camera.width=32",
        "--set", "camera.height=24")
    assert (tmp_path / "py.png").read_bytes() == (tmp_path / "cli.png").read_bytes()
    assert_same_image(fogbank.read_image(tmp_path / "py.exr"), img)
    assert img._repr_png_() == (tmp_path / "py.png").read_bytes()
    assert np.asarray(img) is img.mean
    assert "spp" in repr(img)


def test_shards_merge_into_the_whole_render(tmp_path, small):
    s = fogbank.default_scene(**small)
    whole = fogbank.render(s, spp=4, progress=False)
    parts = [fogbank.render(s, spp=4, shard=f"{i}/2", progress=False) for i in range(2)]
    assert_same_image(fogbank.merge(parts), whole, "merged images")
    for i, p in enumerate(parts):
        p.save(tmp_path / f"p{i}.fbpart")
    assert_same_image(fogbank.merge([tmp_path / "p0.fbpart", tmp_path / "p1.fbpart"]), whole)
    with pytest.raises(ValueError, match="missing"):
        fogbank.merge(parts[:1])
    tiles = [fogbank.render(s, spp=4, shard=f"{i}/3", shard_mode="tiles", progress=False) for i in range(3)]
    assert_same_image(fogbank.merge(tiles), whole, "tiles")


def test_frames_carry_restir_reuse_as_the_command_does(cli, tmp_path):
    over = {"camera.width": 24, "camera.height": 16}
    s = fogbank.load(scene_path("restir_plume.toml"), **over)
    frames = list(fogbank.render_frames(s, range(0, 3), spp=1, progress=False))
    assert [f.frame for f in frames] == [0, 1, 2]
    cli("render", scene_path("restir_plume.toml"), "--frames", "0..3", "--spp", 1, "--quiet",
        "-o", tmp_path / "f_{frame:04}.exr", "--set", "camera.width=24", "--set", "camera.height=16")
    for f in frames:
        ref = fogbank.read_image(tmp_path / f"f_{f.frame:04}.exr")
        assert np.array_equal(f.mean, ref.mean), f"frame {f.frame}"


def test_gpu_passes_the_z_test_against_the_cpu():
    s = fogbank.load(scene_path("transmittance.toml"), **{"camera.width": 48, "camera.height": 36})
    try:
        gpu = fogbank.render(s, spp=64, device="gpu", progress=False)
    except RuntimeError as e:
        skip_unless_required("GPU", f"no GPU adapter: {e}")
    cpu = fogbank.render(s, spp=64, progress=False)
    z = fogbank.compare(cpu, gpu, "ztest")
    assert z["pass"], z
    assert gpu.stats["device"].startswith("gpu")


def test_time_budget_and_bad_arguments():
    s = fogbank.default_scene(**{"camera.width": 16, "camera.height": 12})
    img = fogbank.render(s, time_budget=0.2, progress=False)
    assert img.spp >= 1
    for kwargs, match in [({"device": "tpu"}, "device"), ({"threads": 0}, "threads"),
                          ({"time_budget": -1.0}, "time_budget"), ({"shard": "2/2"}, "shard"),
                          ({"spp": 0}, "spp")]:
        with pytest.raises(ValueError, match=match):
            fogbank.render(s, progress=False, **kwargs)
