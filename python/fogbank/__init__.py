"""fogbank: Monte Carlo rendering of heterogeneous participating media.

Scenes load from fogbank TOML or Mitsuba XML files (`load`), dicts
(`load_dict`) or the built-in default (`default_scene`) and change with the
command line's dotted keys (`scene.set("media.0.sigma_t_scale", 40)`).
Volumes come from numpy (`Grid`) or files (`read_volume`). `render` returns
an `Image` (numpy arrays); `transmittance` and `sample_distance` run the
estimators on your own rays; `stats`, `converge`, `compare` and
`experiment` are the command line's studies. Every call is the library the
`fogbank` command runs: the same scene, seed and spp give the same image
bit for bit on the CPU, whichever door it goes through.

Errors are exceptions carrying the command's message: bad input
`ValueError` (or `TypeError` for a wrong type, `KeyError` for a missing
key), a missing file `FileNotFoundError`, a device or I/O failure
`RuntimeError`. Rust work runs with the GIL released; Ctrl-C stops a render
within a pass and raises `KeyboardInterrupt` whose `.image` holds what was
accumulated.
"""

from __future__ import annotations

import json
import os
from typing import Any, Dict, Iterator, List, Optional, Sequence, Tuple, Union

import numpy as np

from . import _native
from ._image import Image
from ._native import Grid, Medium, Part, Scene, default_scene, load, load_dict, read_volume
from ._progress import Progress, reporter

__version__ = _native.__version__

__all__ = [
    "Grid", "Image", "Medium", "Part", "Scene", "compare", "converge", "default_scene",
    "estimators", "experiment", "load", "load_dict", "merge", "read_image", "read_volume",
    "render", "render_frames", "sample_distance", "stats", "transfer_function",
    "transmittance", "write_image",
]

PathLike = Union[str, "os.PathLike[str]"]


def _interrupted(image: Image) -> KeyboardInterrupt:
    e = KeyboardInterrupt(
        f"render interrupted: {image.spp} spp accumulated; the image is this exception's .image"
    )
    e.image = image  # type: ignore[attr-defined]
    return e


def render(scene: Scene, spp: Optional[int] = None, seed: Optional[int] = None, device: str = "cpu",
           threads: Optional[int] = None, time_budget: Optional[float] = None,
           progress: Progress = True, shard: Optional[str] = None,
           shard_mode: str = "samples") -> Image:
    """Renders `scene` and returns an `Image` (`.mean`, `.variance`, `.spp`,
    `.stats`, `.save(path)`).

    | parameter | default | meaning |
    |---|---|---|
    | `scene` | | a `Scene` (`load`, `load_dict`, `default_scene`) |
    | `spp` | the scene's `render.spp` | samples per pixel (with `time_budget`: at most) |
    | `seed` | the scene's `render.seed` | the seed; the image is a function of scene, seed and spp |
    | `device` | `"cpu"` | `"cpu"` (the reference) or `"gpu"` (wgpu; `RuntimeError` naming why when there is no adapter) |
    | `threads` | all cores | CPU worker threads; the image does not depend on them |
    | `time_budget` | None | stop starting passes after this many seconds |
    | `progress` | True | a bar on stderr (tqdm when installed); False silences it; a callable gets the samples done |
    | `shard` | None | `"I/N"`: render shard I of N; the image's `.part` merges with `merge` |
    | `shard_mode` | `"samples"` | how shards split the work: `samples` or `tiles` |

    Equals `fogbank render SCENE --spp N --seed S` bit for bit on the CPU
    (mean and variance). Ctrl-C stops within a pass and raises
    `KeyboardInterrupt`; its `.image` is what was accumulated.
    """
    total = None
    if time_budget is None:
        n = spp if spp is not None else scene.spp
        total = n * scene.width * scene.height
    report, bar = reporter(progress, total, "fogbank render")
    try:
        d = _native.render(scene, spp, seed, device, threads, time_budget, report, shard, shard_mode)
    finally:
        if bar is not None:
            bar.close()
    image = Image._from_native(d)
    if d.get("keyboard_interrupt"):
        raise _interrupted(image)
    return image


def render_frames(scene: Scene, frames: Union[range, str, int], spp: Optional[int] = None,
                  seed: Optional[int] = None, device: str = "cpu", threads: Optional[int] = None,
                  progress: Progress = True) -> Iterator[Image]:
    """Yields one `Image` per frame of an animated scene (its `[animation]`
    table), each with `.frame`; `restir` carries its reservoirs from frame
    to frame (temporal reuse), as `fogbank render --frames` does.

    `frames` is a `range` (step 1), `"A..B"`, `"A..=B"` or a count N
    (frames 0..N). Other parameters as for `render`.
    """
    if isinstance(frames, range):
        if frames.step != 1:
            raise ValueError(f"frames: {frames} must have step 1")
        text = f"{frames.start}..{frames.stop}"
    else:
        text = str(frames)
    n = spp if spp is not None else scene.spp
    report, bar = reporter(progress, n * scene.width * scene.height, "fogbank frame")
    try:
        for d in _native.render_frames(scene, text, spp, seed, device, threads, report):
            yield Image._from_native(d)
    finally:
        if bar is not None:
            bar.close()


def merge(parts: Sequence[Union[Image, Part, PathLike]], allow_partial: bool = False) -> Image:
    """Adds up shards' parts into the single render's image, bit for bit,
    as `fogbank merge` does. `parts`: shard images (`render(...,
    shard="I/N")`), their `.part`s, or `.fbpart` paths. Refuses parts of
    different renders and missing shards (unless `allow_partial`; the image's
    `.stats["missing"]` then lists them)."""
    native = []
    for p in parts:
        native.append(p.part if isinstance(p, Image) else (os.fspath(p) if isinstance(p, (str, os.PathLike)) else p))
    d = _native.merge(native, allow_partial)
    image = Image._from_native(d)
    image.stats = {"missing": d.get("missing", [])}
    return image


def transmittance(medium: Union[Medium, Grid], origins: Any, directions: Any, t_max: Any,
                  estimator: str = "jackknife", seed: int = 0, per_ray: int = 1,
                  threads: Optional[int] = None, **options: Any) -> Tuple[np.ndarray, np.ndarray]:
    """Transmittance estimates along your own rays: returns (estimates,
    lookups), float64 and uint32 arrays of N (or N×per_ray).

    | parameter | meaning |
    |---|---|
    | `medium` | a scene's medium (`scene.media[i]`: its transform, σ_t scale and filter) or a `Grid` (then `sigma_t_scale=`, `filter=` as a medium's keys) |
    | `origins`, `directions` | N×3 arrays; a ray is `o + t·d`, `d` of any length |
    | `t_max` | a number or N: where each segment ends, in units of its `d` (inf: through the medium) |
    | `estimator` | a name from `estimators()`; its options as keywords (`samples=8` for the jackknife's optical-depth samples, `roulette=0.1`) |
    | `seed`, `per_ray` | `per_ray` independent estimates per ray; estimate `j` of ray `i` uses the stream (seed, i, j): the transmittance integrator's stream of pixel `i`'s sample `j`, so on `scene.camera_rays()` with the scene's seed these are a transmittance render's per-pixel samples |
    """
    return _native.transmittance(medium, origins, directions, t_max, estimator, seed, per_ray,
                                 threads, **options)


def sample_distance(medium: Union[Medium, Grid], origins: Any, directions: Any, t_max: Any,
                    sampler: str = "delta_tracking", seed: int = 0, per_ray: int = 1,
                    threads: Optional[int] = None, light: Optional[Sequence[float]] = None,
                    **options: Any) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Free-flight distances along your own rays: returns (t, weight,
    lookups) arrays of N (or N×per_ray); `t` is inf when the ray escapes.

    | sampler | density of t | weight |
    |---|---|---|
    | `delta_tracking`, `decomposition_tracking`, `regular_tracking` | T(t)·σ_t(t), escape with probability T(t_max) | 1 |
    | `analytic_trilinear` | exact T·σ_t of the trilinear field (grids) | 1 |
    | `equiangular` | ∝ 1/(D² + (t − Δ)²) towards `light=(x, y, z)` over the medium's part of the segment | 1/pdf |

    Rays, seeds and the medium as for `transmittance`.
    """
    return _native.sample_distance(medium, origins, directions, t_max, sampler, seed, per_ray,
                                   threads, None if light is None else tuple(light), **options)


def estimators() -> List[Dict[str, Any]]:
    """The transmittance estimators, as `fogbank estimators` lists them: a
    dict per estimator with `name`, `biased`, `description`, `options`."""
    return _native.estimators()


class Stats:
    """What `stats` returns: per-pixel `mean`, `std` (of one frame) and
    `bias` (against the reference, or None) as H×W×3 float64 arrays, the
    finite frames per pixel `count` (H×W) and `summary`, the dict `fogbank
    stats` writes as summary.json."""

    def __init__(self, d: dict):
        self.mean: np.ndarray = d["mean"]
        self.std: np.ndarray = d["std"]
        self.bias: Optional[np.ndarray] = d["bias"]
        self.count: np.ndarray = d["count"]
        self.summary: Dict[str, Any] = json.loads(d["summary"])

    def __repr__(self) -> str:
        s = self.summary
        return f"fogbank.Stats({s['estimator']}, {s['runs']} runs, mean std {s['mean_std']:.4g})"


def stats(scene: Scene, estimator: Optional[str] = None, runs: int = 1024, seed: int = 1,
          reference_estimator: Optional[str] = None, reference: Optional[PathLike] = None,
          device: str = "cpu", threads: Optional[int] = None,
          out: Optional[PathLike] = None) -> Stats:
    """Per-pixel mean, single-frame std and bias of the scene's estimator
    (or `estimator`) over `runs` independent 1-spp frames, as `fogbank
    stats`; returns a `Stats`. `reference_estimator` (`analytic_trilinear`,
    `regular_tracking`) or `reference` (an image through pixel centres)
    gives the bias; `out` also writes the command's files there."""
    return Stats(_native.stats(scene, estimator, runs, seed, reference_estimator,
                               None if reference is None else os.fspath(reference), device, threads,
                               None if out is None else os.fspath(out)))


def converge(scene: Scene, estimators: Sequence[str], seconds: float = 10.0,
             reference_estimator: str = "analytic_trilinear", seed: int = 1, device: str = "cpu",
             threads: Optional[int] = None, out: Optional[PathLike] = None) -> Dict[str, Dict[str, list]]:
    """Equal-time MSE-versus-time curves of `estimators` on `scene` against
    an exact reference, measured in one run, as `fogbank converge`: returns
    {estimator: {"spp": [...], "seconds": [...], "mse": [...]}}; `out`
    also writes converge.csv and the plots."""
    return _native.converge(scene, list(estimators), seconds, reference_estimator, seed, device,
                            threads, None if out is None else os.fspath(out))


def _image_arg(x: Any) -> Any:
    if isinstance(x, Image):
        return (x.mean, x.variance)
    if isinstance(x, (str, os.PathLike)):
        return os.fspath(x)
    if isinstance(x, tuple):
        return x
    return (np.asarray(x), None)


def compare(reference: Any, test: Any, metric: Union[str, Sequence[str]] = "rmse",
            flip_mode: str = "auto", ppd: Optional[float] = None, tonemapper: str = "aces",
            alpha: Optional[float] = None) -> Any:
    """Compares `test` against `reference` (each an `Image`, an H×W×3
    array, a (mean, variance) pair or an EXR/PNG path) as `fogbank
    compare`: `metric` one of rmse, relmse, smape, flip, ztest (a float for
    the first three, a dict for flip and ztest), or a list of them or
    "all" (a dict by metric). The z-test needs a variance (an `Image` of at
    least 2 spp or an EXR fogbank wrote)."""
    names = [metric] if isinstance(metric, str) else list(metric)
    out = _native.compare(_image_arg(reference), _image_arg(test), names, flip_mode, ppd, tonemapper,
                          alpha)
    out = {k: (json.loads(v) if isinstance(v, str) else v) for k, v in out.items()}
    if isinstance(metric, str) and metric.lower() != "all":
        return out[metric.lower()]
    return out


def experiment(name: str, out: Optional[PathLike] = None, trials: Optional[int] = None) -> Dict[str, Any]:
    """Runs one of the papers' experiments (`fogbank experiment NAME`) into
    `out` (default experiments/NAME); returns {"summary", "files",
    "seconds"}."""
    summary, files, seconds = _native.experiment(name, None if out is None else os.fspath(out), trials)
    return {"summary": summary, "files": [os.fspath(f) for f in files], "seconds": seconds}


def read_image(path: PathLike) -> Image:
    """Reads an EXR (with its `variance` layer, if any) or PNG."""
    d = _native.read_image(os.fspath(path))
    return Image(d["mean"], d["variance"])


def write_image(path: PathLike, image: Any, variance: Optional[np.ndarray] = None,
                exposure: float = 0.0, tonemap: str = "linear") -> None:
    """Writes an `Image` or an H×W×3 array as `fogbank render -o` writes
    images: `.exr` (linear, `variance` as a layer) or `.png` (tone-mapped)."""
    if isinstance(image, Image):
        image.save(path, exposure, tonemap)
        return
    _native.write_image(os.fspath(path), np.asarray(image), variance, exposure, tonemap)


def transfer_function(opacity: Any = None, color: Any = None, lut: Any = None,
                      range: Tuple[float, float] = (0.0, 1.0), emission: Any = None,
                      mode: Optional[str] = None) -> Dict[str, Any]:
    """A medium's `transfer` table from numpy, for `scene.set("media.0.
    transfer", fogbank.transfer_function(...))`.

    Either control points — `opacity` N×2 (value, opacity), `color` N×4
    (value, r, g, b), `emission` N×4 — or `lut`, an N×4 RGBA table spread
    evenly over `range` (values in the grid's units). `mode`: the medium's
    transfer mode (`pre` or `post` classification).
    """
    t: Dict[str, Any] = {}
    if lut is not None:
        if opacity is not None or color is not None:
            raise ValueError("transfer_function: give lut or opacity/color points, not both")
        lut = np.asarray(lut, dtype=np.float64)
        if lut.ndim != 2 or lut.shape[1] != 4 or lut.shape[0] < 2:
            raise ValueError(f"lut: expected an N×4 RGBA array with N ≥ 2, got shape {lut.shape}")
        lo, hi = float(range[0]), float(range[1])
        if not hi > lo:
            raise ValueError(f"range: ({lo}, {hi}) must increase")
        x = np.linspace(lo, hi, lut.shape[0])
        opacity = np.column_stack([x, lut[:, 3]])
        color = np.column_stack([x, lut[:, :3]])
    for key, pts, width in (("opacity", opacity, 2), ("color", color, 4), ("emission", emission, 4)):
        if pts is None:
            continue
        a = np.asarray(pts, dtype=np.float64)
        if a.ndim != 2 or a.shape[1] != width:
            raise ValueError(f"{key}: expected an N×{width} array, got shape {a.shape}")
        if not np.all(np.isfinite(a)):
            raise ValueError(f"{key}: values must be finite")
        t[key] = a.tolist()
    if mode is not None:
        t["mode"] = mode
    return t
