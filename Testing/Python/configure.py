"""The helpers the Python tests share: a VTK filter set up from keyword
settings, the way the tests and benchmarks describe their runs, and the
checks of the pvpython/pvbatch scripts."""
import sys


def configured(f, source=None, update=True, **settings):
    """f with Set<Key>(value) for every keyword, fed by source (a data
    object or an algorithm; None: left as it is), updated unless update is
    False.  Returns f."""
    if source is not None:
        if hasattr(source, "GetOutputPort"):
            f.SetInputConnection(source.GetOutputPort())
        else:
            f.SetInputData(source)
    for key, value in settings.items():
        getattr(f, "Set" + key)(value)
    if update:
        f.Update()
    return f


def check(condition, message, quiet=False):
    """A pvpython/pvbatch script's check: "FAILED: message" and exit 1 when
    `condition` fails (ctest's FAIL_REGULAR_EXPRESSION), else "ok: message"
    unless quiet."""
    if not condition:
        print("FAILED: " + message)
        sys.exit(1)
    if not quiet:
        print("ok: " + message)
