"""Runs the guide's examples (docs/examples/*.py) from the repository root,
each in a fresh namespace: the plain Python ones with this interpreter, the
*_pvpython.py ones when this is pvpython or pvbatch (--pvpython).  Prints
one line per example and 'N passed, N failed'; exits 1 on any failure."""
import glob
import os
import runpy
import sys
import time
import traceback

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)


def examples(pvpython):
    paths = sorted(glob.glob(os.path.join(HERE, "examples", "*.py")))
    return [p for p in paths if p.endswith("_pvpython.py") == pvpython]


def load_plugin():
    """In pvpython the plugin comes from PV_PLUGIN_PATH (build/beltrami-env.sh);
    where only BELTRAMI_PLUGIN names it (the test suite), it is loaded here."""
    import paraview.simple as simple
    if not hasattr(simple, "ImplicitFairing") and os.environ.get("BELTRAMI_PLUGIN"):
        simple.LoadPlugin(os.environ["BELTRAMI_PLUGIN"], ns=vars(simple))


def main(argv):
    pvpython = "--pvpython" in argv
    os.chdir(ROOT)
    if pvpython:
        load_plugin()
    passed, failed = 0, 0
    for path in examples(pvpython):
        start = time.perf_counter()
        try:
            runpy.run_path(path, run_name="__main__")
            passed += 1
            print(f"PASSED {os.path.basename(path)} ({time.perf_counter() - start:.1f} s)", flush=True)
        except BaseException:  # an example's SystemExit is a failure too
            failed += 1
            traceback.print_exc()
            print(f"FAILED {os.path.basename(path)}", flush=True)
    print(f"{passed} passed, {failed} failed")
    return 1 if failed or not passed else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
