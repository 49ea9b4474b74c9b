"""Every filter on every hostile input, each case guarded: a child process
runs the cases one after another and says when each begins and ends, so a
crash or a hang is caught as that case's failure (the next child goes on
with the rest).  A case passes when the filter returns a defined output
(an output object; finite coordinates wherever the input's were finite)
and, where the input cannot be processed as it is, says so (an error or a
warning).  Prints one line a case and "N passed, M failed".

    test_hostile_inputs.py FILTER [FILTER ...]   (no name: every filter)
"""
import os
import queue
import subprocess
import sys
import threading

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

CASE_SECONDS = 90  # a hang is a case that takes longer (the slowest real case takes a few seconds)

# The inputs that no filter can process as they are: each must be refused
# or repaired with a word to the user (error or warning).
MUST_SPEAK = {"nan-coordinate", "inf-coordinate", "index-out-of-range", "image-nan-value", "image-inf-value",
              "grid-nan-point", "mobius"}
# The inputs every surface filter repairs (coincident points merged,
# repeated triangles dropped, triangles turned to one orientation) and then
# processes: each must say what it repaired, and none may refuse.
REPAIRED = {"half-flipped-sphere", "unwelded-soup", "repeated-triangles"}


def filters():
    """name -> (make(), the input kinds it takes)."""
    import beltrami as b
    import inputs
    return {
        "curvatures": (b.vtkDiscreteCurvatures, ("surface",)),
        "operators": (b.vtkBeltramiOperators, ("surface", "image", "grid")),
        "fairing": (b.vtkImplicitFairing, ("surface",)),
        "fairing-geometric-multigrid": (inputs.filter_with(b.vtkImplicitFairing, Preconditioner=2, TimeStep=4.0),
                                        ("surface",)),
        "surface-data-denoising": (b.vtkSurfaceDataDenoising, ("surface",)),
        "parameterization": (b.vtkIntrinsicParameterization, ("surface",)),
        "atlas": (b.vtkSurfaceAtlas, ("surface",)),
        "remeshing": (inputs.filter_with(b.vtkSurfaceRemeshing, NumberOfVertices=300), ("surface",)),
        "remeshing-anisotropic": (inputs.filter_with(b.vtkSurfaceRemeshing, NumberOfVertices=300, Anisotropy=1),
                                  ("surface",)),
        "remeshing-sharp-edges": (inputs.filter_with(b.vtkSurfaceRemeshing, NumberOfVertices=300, SplitAtFeatures=True),
                                  ("surface",)),
        "line-drawing": (inputs.filter_with(b.vtkSurfaceLineDrawing, Visibility=2), ("surface",)),
        "vector-fields": (b.vtkSurfaceVectorFieldDecomposition, ("surface-with-vectors",)),
        "tetgen": (b.vtkTetGenTetrahedralizer, ("surface",)),
        "image-denoising": (b.vtkImageBeltramiDenoising, ("image",)),
        "tetrahedral-denoising": (b.vtkTetrahedralBeltramiDenoising, ("grid", "image")),
        "off-reader": (b.vtkOFFReader, ("file",)),
    }


def hostile_files(folder):
    """name -> path of a broken OFF file."""
    texts = {
        "off-empty-file": "",
        "off-garbage": "this is not a mesh\n\x00\x01",
        "off-counts-too-large": "OFF\n100000000 100000000 0\n0 0 0\n",
        "off-negative-count": "OFF\n-3 1 0\n",
        "off-bad-index": "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n",
        "off-nan-coordinate": "OFF\n3 1 0\nnan 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
        "off-truncated": "OFF\n4 2 0\n0 0 0\n1 0 0\n",
        "off-huge-polygon": "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n1000000000 0 1 2\n",
    }
    os.makedirs(folder, exist_ok=True)
    paths = {}
    for name, text in texts.items():
        paths[name] = os.path.join(folder, name + ".off")
        with open(paths[name], "w", encoding="latin-1") as f:
            f.write(text)
    paths["off-missing-file"] = os.path.join(folder, "does-not-exist.off")
    return paths


def cases_for(kinds, folder):
    import inputs
    cases = {}
    if "surface" in kinds:
        cases.update(inputs.hostile_surfaces())
    if "surface-with-vectors" in kinds:
        cases.update({name: inputs.with_vectors(mesh) for name, mesh in inputs.hostile_surfaces().items()})
    if "image" in kinds:
        cases.update(inputs.hostile_images())
    if "grid" in kinds:
        cases.update(inputs.hostile_grids())
    if "file" in kinds:
        cases.update(hostile_files(folder))
    return cases


def input_has_nonfinite(data):
    from vtkmodules.util.numpy_support import vtk_to_numpy
    if isinstance(data, str) or not hasattr(data, "GetPoints") or data.GetPoints() is None:
        return False
    return not np.isfinite(vtk_to_numpy(data.GetPoints().GetData())).all()


def run_case(make, name, data):
    """(passed, what happened) of one filter on one input."""
    import inputs
    from vtkmodules.util.numpy_support import vtk_to_numpy
    f = make()
    said = inputs.Messages(f, f.GetExecutive())
    if isinstance(data, str):
        f.SetFileName(data)
    else:
        f.SetInputData(data)
    f.Update()
    out = f.GetOutputDataObject(0)
    spoke = bool(said.errors or said.warnings)
    summary = "%d error(s), %d warning(s)" % (len(said.errors), len(said.warnings))
    if said.errors or said.warnings:
        summary += ": " + (said.errors + said.warnings)[0].strip().replace("\n", " ")[:160]
    if out is None:
        return False, "no output object; " + summary
    points = out.GetPoints() if hasattr(out, "GetPoints") else None
    if points is not None and points.GetNumberOfPoints() > 0:
        finite = np.isfinite(vtk_to_numpy(points.GetData())).all()
        if not finite and not (input_has_nonfinite(data) and spoke):
            return False, "non-finite output coordinates; " + summary
    if name in MUST_SPEAK and not spoke:
        return False, "said nothing about an input it cannot process as it is"
    if name in REPAIRED and (said.errors or not any("was repaired" in w for w in said.warnings)):
        return False, "did not repair and process a repairable input; " + summary
    return True, summary


def child(filter_name, skip):
    """Runs the cases of one filter after the first `skip`, one line each."""
    make, kinds = filters()[filter_name]
    folder = os.path.join(os.environ.get("BELTRAMI_TEST_OUTPUT_DIR", "/tmp"), "hostile")
    cases = cases_for(kinds, folder)
    for k, (name, data) in enumerate(cases.items()):
        if k < skip:
            continue
        print("BEGIN %d %s" % (k, name), flush=True)
        try:
            passed, what = run_case(make, name, data)
        except Exception as error:  # a Python-side failure of the case, not of the harness
            passed, what = False, "exception: %r" % (error,)
        print("END %d %s %s %s" % (k, name, "ok" if passed else "FAILED", what), flush=True)
    print("DONE", flush=True)


def parent(filter_name):
    """Runs children until every case has ended, crashed or hung."""
    results, skip = [], 0
    while True:
        proc = subprocess.Popen([sys.executable, __file__, "--child", filter_name, str(skip)],
                                stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        lines = queue.Queue()
        threading.Thread(target=lambda: [lines.put(x) for x in proc.stdout] + [lines.put(None)], daemon=True).start()
        current, finished = None, False
        while True:
            try:
                line = lines.get(timeout=CASE_SECONDS)
            except queue.Empty:
                proc.kill()
                results.append((current or ("?", "?"), False, "hung (no end after %d s)" % CASE_SECONDS))
                break
            if line is None:
                proc.wait()
                if current is not None:
                    results.append((current, False, "crashed (exit %d)" % proc.returncode))
                break
            if line.startswith("BEGIN "):
                _, k, name = line.split(None, 2)
                current = (int(k), name.strip())
            elif line.startswith("END "):
                _, k, name, status, *what = line.rstrip("\n").split(" ", 4)
                results.append(((int(k), name), status == "ok", what[0] if what else ""))
                current = None
            elif line.startswith("DONE"):
                finished = True
        proc.wait()
        if finished or current is None and not results:
            break
        skip = results[-1][0][0] + 1 if results and results[-1][0] != ("?", "?") else skip + 1
    failed = 0
    for (k, name), passed, what in results:
        failed += not passed
        print("%-22s %-24s %s %s" % (filter_name, name, "ok    " if passed else "FAILED", what))
    return len(results) - failed, failed


def main(argv):
    if argv[:1] == ["--child"]:
        child(argv[1], int(argv[2]))
        return 0
    names = argv or list(filters())
    passed = failed = 0
    for name in names:
        p, f = parent(name)
        passed, failed = passed + p, failed + f
    print("%d passed, %d failed" % (passed, failed))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
