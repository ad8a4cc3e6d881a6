#!/usr/bin/env python3
"""Denoise one HDR image with Intel Open Image Denoise (the "RT" filter).

fogbank's experiments call this as an external denoiser (Lerzer and Dachsbacher 2025, Fig. 6):
stdin carries WIDTH*HEIGHT*3 little-endian f32 (rows top to bottom, RGB),
stdout gets the denoised pixels in the same layout, and the last line of
stderr is `execute_ms <float>`: the filter's execution time, without the
process start and the device set-up, which is what a renderer that keeps the
denoiser resident pays per frame.

Usage: denoise.py WIDTH HEIGHT

OIDN comes from the `oidn` wheel on PyPI (`pip install numpy oidn`), which
bundles Intel's libOpenImageDenoise 1.4.3 and TBB. Its Python binding cannot
set the filter's `hdr` flag and its library does not find the bundled TBB,
so this script loads both libraries itself and calls OIDN's C API.
Colour only: fogbank writes no albedo/normal feature images yet.
"""
import ctypes
import os
import sys
import time

import numpy as np

OIDN_FORMAT_FLOAT3 = 3


def load_oidn():
    import importlib.util

    spec = importlib.util.find_spec("oidn")
    if spec is None or spec.origin is None:
        sys.exit("denoise.py: the `oidn` package is missing (pip install numpy oidn)")
    libs = os.path.join(os.path.dirname(spec.origin), "lib.linux.x64")
    names = sorted(os.listdir(libs))
    tbb = next((n for n in names if n.startswith("libtbb.so")), None)
    core = next((n for n in names if n.startswith("libOpenImageDenoise.so")), None)
    if core is None:
        sys.exit(f"denoise.py: no libOpenImageDenoise in {libs}")
    if tbb is not None:
        ctypes.CDLL(os.path.join(libs, tbb), mode=ctypes.RTLD_GLOBAL)
    lib = ctypes.CDLL(os.path.join(libs, core))
    p, s = ctypes.c_void_p, ctypes.c_char_p
    sz = ctypes.c_size_t
    sig = {
        "oidnNewDevice": ([ctypes.c_int], p),
        "oidnCommitDevice": ([p], None),
        "oidnGetDeviceError": ([p, ctypes.POINTER(s)], ctypes.c_int),
        "oidnNewFilter": ([p, s], p),
        "oidnSetSharedFilterImage": ([p, s, p, ctypes.c_int, sz, sz, sz, sz, sz], None),
        "oidnSetFilter1b": ([p, s, ctypes.c_bool], None),
        "oidnCommitFilter": ([p], None),
        "oidnExecuteFilter": ([p], None),
        "oidnReleaseFilter": ([p], None),
        "oidnReleaseDevice": ([p], None),
    }
    for name, (args, res) in sig.items():
        f = getattr(lib, name)
        f.argtypes, f.restype = args, res
    return lib


def check(lib, device, what):
    msg = ctypes.c_char_p()
    code = lib.oidnGetDeviceError(device, ctypes.byref(msg))
    if code != 0:
        text = msg.value.decode() if msg.value else "unknown error"
        sys.exit(f"denoise.py: OIDN {what}: {text} (code {code})")


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    width, height = int(sys.argv[1]), int(sys.argv[2])
    n = width * height * 3
    raw = sys.stdin.buffer.read()
    if len(raw) != 4 * n:
        sys.exit(f"denoise.py: expected {4 * n} bytes on stdin for {width}x{height}, got {len(raw)}")
    color = np.frombuffer(raw, dtype="<f4").astype(np.float32).reshape(height, width, 3).copy()
    output = np.zeros_like(color)

    lib = load_oidn()
    device = lib.oidnNewDevice(0)
    lib.oidnCommitDevice(device)
    check(lib, device, "device")
    filt = lib.oidnNewFilter(device, b"RT")
    for name, img in ((b"color", color), (b"output", output)):
        lib.oidnSetSharedFilterImage(
            filt, name, img.ctypes.data, OIDN_FORMAT_FLOAT3, width, height, 0, 0, 0
        )
    lib.oidnSetFilter1b(filt, b"hdr", True)
    lib.oidnCommitFilter(filt)
    check(lib, device, "filter set-up")
    start = time.perf_counter()
    lib.oidnExecuteFilter(filt)
    ms = 1e3 * (time.perf_counter() - start)
    check(lib, device, "execute")
    lib.oidnReleaseFilter(filt)
    lib.oidnReleaseDevice(device)

    sys.stdout.buffer.write(output.astype("<f4").tobytes())
    sys.stdout.flush()
    print(f"execute_ms {ms:.3f}", file=sys.stderr)


if __name__ == "__main__":
    main()
