"""The `Image` a render returns: numpy arrays with what the command writes."""

from __future__ import annotations

import json
import os
from typing import Any, Optional

import numpy as np

from . import _native


class Image:
    """A rendered (or read) image.

    | attribute | meaning |
    |---|---|
    | `mean` | H×W×3 float32: the per-pixel mean, linear RGB (non-finite pixels as 0, as written to files) |
    | `variance` | H×W×3 float32: the variance of the mean (per pixel, per channel), or None below 2 spp |
    | `spp` | samples per pixel every pixel has |
    | `stats` | the `fogbank render --stats` record (dict), or {} |
    | `exposure`, `tonemap` | the scene's PNG tone mapping (`save` and the notebook display use it) |
    | `frame` | the animation frame (from `render_frames`), else None |
    | `part` | a shard's part (`render(..., shard="I/N")`), for `merge` and `save("x.fbpart")` |
    | `interrupted` | True when Ctrl-C or a time budget stopped it before its last pass |

    `numpy.asarray(image)` is `image.mean`; in a notebook the image shows
    tone-mapped.
    """

    def __init__(self, mean: np.ndarray, variance: Optional[np.ndarray] = None, spp: int = 0,
                 stats: Optional[dict] = None, exposure: float = 0.0, tonemap: str = "linear",
                 frame: Optional[int] = None, part: Any = None, interrupted: bool = False):
        self.mean = mean
        self.variance = variance
        self.spp = spp
        self.stats = stats if stats is not None else {}
        self.exposure = exposure
        self.tonemap = tonemap
        self.frame = frame
        self.part = part
        self.interrupted = interrupted

    @classmethod
    def _from_native(cls, d: dict) -> "Image":
        stats = d.get("stats")
        return cls(
            mean=d["mean"],
            variance=d.get("variance"),
            spp=d.get("spp", 0),
            stats=json.loads(stats) if isinstance(stats, str) else (stats or {}),
            exposure=d.get("exposure", 0.0),
            tonemap=d.get("tonemap", "linear"),
            frame=d.get("frame"),
            part=d.get("part"),
            interrupted=bool(d.get("interrupted", False)),
        )

    @property
    def width(self) -> int:
        return int(self.mean.shape[1])

    @property
    def height(self) -> int:
        return int(self.mean.shape[0])

    @property
    def shape(self) -> tuple:
        return self.mean.shape

    def save(self, path: "str | os.PathLike", exposure: Optional[float] = None,
             tonemap: Optional[str] = None) -> None:
        """Writes the image as `fogbank render -o` does: `.exr` (linear,
        with the variance as a `variance` layer), `.png` (tone-mapped with
        `exposure` stops and the `tonemap` curve, by default the scene's) or,
        for a shard's image, `.fbpart` (the partial result `merge` adds)."""
        p = os.fspath(path)
        if p.endswith(".fbpart"):
            if self.part is None:
                raise ValueError(f"{p}: only a shard's image (render(..., shard='I/N')) saves as .fbpart")
            self.part.save(p)
            return
        _native.write_image(p, self.mean, self.variance,
                            self.exposure if exposure is None else exposure,
                            self.tonemap if tonemap is None else tonemap)

    def __array__(self, dtype=None, copy=None):
        a = self.mean
        if dtype is not None:
            a = a.astype(dtype, copy=False)
        return a.copy() if copy else a

    def _repr_png_(self) -> bytes:
        return bytes(_native.png_bytes(self.mean, self.exposure, self.tonemap))

    def __repr__(self) -> str:
        extra = f", frame {self.frame}" if self.frame is not None else ""
        extra += ", interrupted" if self.interrupted else ""
        return f"fogbank.Image({self.width}×{self.height}, {self.spp} spp{extra})"
