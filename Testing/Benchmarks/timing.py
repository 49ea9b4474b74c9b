"""The timing rule of the benchmarks: the best wall time of a few runs (the
same rule for every method: the first run of a process also pays for
faulting in fresh memory).

Importing this module also keeps freed memory in the process (glibc's
mallopt: no trimming of the heap, blocks up to 64 MiB from the heap instead
of their own mappings).  By default glibc hands every freed block of 128 KiB
or more back to the kernel, so a method that allocates temporaries per
iteration faults them in again each time; on machines where page faults are slow, of this
project a fresh page costs 1-3 ms per MiB, and scikit-image's TV on the
512 x 512 camera image took 0.44-0.51 s instead of 0.08-0.10 s, depending on
what the process had freed before.  Our filters keep their large buffers
themselves (Filters/Core/Support/LargeBuffer.h); this gives the peers the same."""
import ctypes
import time

_M_TRIM_THRESHOLD, _M_MMAP_THRESHOLD = -1, -3
try:
    _libc = ctypes.CDLL("libc.so.6")
    _libc.mallopt(_M_MMAP_THRESHOLD, 64 << 20)
    _libc.mallopt(_M_TRIM_THRESHOLD, 256 << 20)
except (OSError, AttributeError):  # not glibc: nothing to tune
    pass


def timed(f, repeats=3):
    """(result of the last run, best wall time in seconds) of `repeats` runs of f()."""
    best = None
    out = None
    for _ in range(repeats):
        t = time.perf_counter()
        out = f()
        t = time.perf_counter() - t
        best = t if best is None else min(best, t)
    return out, best
