"""Progress reports for long calls: tqdm when it is installed, else one
line on stderr rewritten in place; `progress=False` silences them."""

from __future__ import annotations

import sys
import time
from typing import Callable, Optional, Union

Progress = Union[bool, Callable[[int], None], None]


class _Reporter:
    """Called with the samples done so far, every 100 ms of a render."""

    def __init__(self, total: Optional[int], what: str):
        self.total = total if total and total > 0 else None
        self.what = what
        self.started = time.monotonic()
        self.bar = None
        try:
            from tqdm.auto import tqdm  # type: ignore

            self.bar = tqdm(total=self.total, desc=what, unit="sample", unit_scale=True, leave=False)
        except Exception:
            self.bar = None
        self.last = 0

    def __call__(self, done: int) -> None:
        if self.bar is not None:
            self.bar.update(done - self.last)
            self.last = done
            return
        seconds = time.monotonic() - self.started
        if self.total:
            text = f"\r{self.what}: {100.0 * done / self.total:5.1f} % ({seconds:.1f} s)"
        else:
            text = f"\r{self.what}: {done} samples ({seconds:.1f} s)"
        sys.stderr.write(text)
        sys.stderr.flush()

    def close(self) -> None:
        if self.bar is not None:
            self.bar.close()
        elif time.monotonic() - self.started > 0.0:
            sys.stderr.write("\r" + " " * 60 + "\r")
            sys.stderr.flush()


def reporter(progress: Progress, total: Optional[int], what: str):
    """The callable a native call reports to (None: silent), and what to
    close afterwards."""
    if progress is False or progress is None:
        return None, None
    if callable(progress):
        return progress, None
    r = _Reporter(total, what)
    return r, r
