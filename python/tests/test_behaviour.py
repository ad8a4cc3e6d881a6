"""What a Python user expects of a native package: Ctrl-C raises
KeyboardInterrupt within a pass and keeps the accumulated image, two
renders in two threads run side by side and each equals its
single-threaded image, a panic is a RuntimeError, memory stays bounded
over many renders, and every public function documents itself."""

import gc
import inspect
import os
import signal
import threading
import time

import numpy as np
import pytest

import fogbank
from conftest import assert_same_image


def test_ctrl_c_raises_keyboard_interrupt_and_keeps_the_image():
    # A render that would take minutes, interrupted from a timer thread by
    # the signal Ctrl-C sends.
    # Python's own handler, whatever the launcher left: a process started in
    # the background by a non-interactive shell inherits SIGINT ignored, and
    # Python then installs no handler. The time budget turns a missed signal
    # into a failure instead of a hang.
    s = fogbank.default_scene(**{"camera.width": 64, "camera.height": 48})
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    timer = threading.Timer(0.5, lambda: os.kill(os.getpid(), signal.SIGINT))
    started = time.monotonic()
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt) as info:
            fogbank.render(s, spp=1_000_000, time_budget=120, progress=False)
    finally:
        timer.join()
        signal.signal(signal.SIGINT, previous)
    img = info.value.image
    assert img.interrupted and 0 < img.spp < 1_000_000
    assert np.isfinite(img.mean).all() and img.mean.max() > 0
    assert time.monotonic() - started < 60, "the render did not stop"


def test_two_threads_render_side_by_side():
    s = fogbank.default_scene(**{"camera.width": 48, "camera.height": 32})
    alone = [fogbank.render(s, spp=6, seed=k, threads=1, progress=False) for k in (1, 2)]
    out = {}

    def work(k):
        out[k] = fogbank.render(s, spp=6, seed=k, threads=1, progress=False)

    threads = [threading.Thread(target=work, args=(k,)) for k in (1, 2)]
    [t.start() for t in threads]
    [t.join() for t in threads]
    for k, a in zip((1, 2), alone):
        assert_same_image(out[k], a, f"seed {k}")


def test_a_panic_is_a_runtime_error_not_the_end():
    with pytest.raises(RuntimeError, match="internal error"):
        fogbank._native.panic_for_tests()
    assert fogbank.render(fogbank.default_scene(**{"camera.width": 8, "camera.height": 6}), spp=1,
                          progress=False).spp == 1


def rss_bytes():
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")


@pytest.mark.skipif(not os.path.exists("/proc/self/statm"), reason="RSS is read from /proc")
def test_200_renders_keep_memory_bounded():
    s = fogbank.default_scene(**{"camera.width": 32, "camera.height": 24})
    for _ in range(20):
        fogbank.render(s, spp=1, progress=False)
    gc.collect()
    before = rss_bytes()
    for _ in range(200):
        img = fogbank.render(s, spp=1, progress=False)
        img._repr_png_()
    gc.collect()
    grown = rss_bytes() - before
    # One render's film and images are ~0.1 MB; 200 leaked would be 20 MB.
    assert grown < 16 << 20, f"RSS grew by {grown / 2**20:.1f} MiB over 200 renders"


def test_every_public_function_documents_what_it_returns():
    for name in fogbank.__all__:
        obj = getattr(fogbank, name)
        assert inspect.getdoc(obj), f"fogbank.{name} has no docstring"
    assert "Image" in inspect.getdoc(fogbank.render)
    assert "returns" in inspect.getdoc(fogbank.transmittance).lower()
    here = os.path.dirname(fogbank.__file__)
    assert os.path.exists(os.path.join(here, "py.typed")) and os.path.exists(os.path.join(here, "_native.pyi"))
