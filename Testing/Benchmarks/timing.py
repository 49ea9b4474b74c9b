"""The timing rule of the benchmarks: the best wall time of a few runs (the
same rule for every method: the first run of a process also pays for
faulting in fresh memory)."""
import time


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
