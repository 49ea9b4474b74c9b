"""Benchmark (on demand): vtkImplicitFairing's default step on the noisy
1.2M-triangle bunny (bunny00 Loop-subdivided twice, Gaussian noise of 0.3%
and of 0.075% of the diagonal along the normals) split over 1, 2 and 4 ranks
of pvbatch (RedistributeDataSet), with the Jacobi preconditioner and (on the
lighter noise only: on the heavier one a serial multigrid step takes over 10
minutes) the multigrid one; and vtkSurfaceDataDenoising at
its defaults on point data over the same mesh (f = sin(40 x) cos(30 y) plus
Gaussian noise of 0.15; noise estimated, least-risk stop), and two fairing
options that run split (anisotropic smoothing with its
feature curves; ten Taubin lambda|mu steps), on the lighter noise:
wall time of the filter, solver iterations, the largest share of points and
triangles a rank holds, and the values each rank sends per ghost update.
One thread per rank, so 2 ranks use the 2 cores of the CI machines and 4
ranks are oversubscribed (2 per core): read the 4-rank times as such.  The
1-rank run is the serial code path (the data are whole on one rank).
Run:  source build/beltrami-env.sh && /usr/bin/python3 Testing/Benchmarks/benchmark_distributed_fairing.py
(it starts `mpirun ... pvbatch` itself; a worker prints one JSON line per case).
`--only denoising` (or `fairing`, or `options`) runs one group of cases
(without --only: all but `options`)."""
import json
import os
import subprocess
import sys
import tempfile
import time

HERE = os.path.abspath(__file__)
# Per noise: (case, the fairing's settings; None: data denoising).
NOISES = {0.003: (("Jacobi", {"Preconditioner": 0}), ("data denoising", None)),
          0.00075: (("Jacobi", {"Preconditioner": 0}), ("multigrid", {"Preconditioner": 1}),
                    ("anisotropic", {"Anisotropic": 1, "SmoothFeatureCurves": 1}),
                    ("Taubin x10", {"Integration": 2, "Operator": 0, "NumberOfIterations": 10}))}
GROUPS = {"data denoising": "denoising", "anisotropic": "options", "Taubin x10": "options"}
ONLY = sys.argv[sys.argv.index("--only") + 1] if "--only" in sys.argv else None


def wanted(case):
    group = GROUPS.get(case, "fairing")
    return group == ONLY if ONLY else group != "options"


def split_mesh(mesh_file):
    """A pvbatch worker's start: the plugin loaded, the number of ranks, and
    the mesh file read on rank 0 and cut into one piece per rank (whole on
    one rank: the serial code path), updated."""
    from paraview.simple import XMLPolyDataReader, RedistributeDataSet, ExtractSurface
    from paraview import servermanager, simple
    if not hasattr(simple, "ImplicitFairing"):  # (loaded at start where PV_PLUGIN_PATH names its folder)
        simple.LoadPlugin(os.environ["BELTRAMI_PLUGIN"])
    ranks = servermanager.ActiveConnection.GetNumberOfDataPartitions()
    source = XMLPolyDataReader(FileName=[mesh_file])
    split = ExtractSurface(Input=RedistributeDataSet(Input=source)) if ranks > 1 else source
    split.UpdatePipeline()
    return ranks, split


def worker(mesh_file, noise):
    from paraview.simple import ProgrammableFilter
    from paraview import servermanager, simple
    from vtkmodules.util.numpy_support import vtk_to_numpy
    ranks, split = split_mesh(mesh_file)
    for name, settings in NOISES[noise]:
        if not wanted(name):
            continue
        if settings is None:
            faired = simple.SurfaceDataDenoising(Input=split, NumberOfThreads=1)
            faired.ArrayToSmooth = ["POINTS", "f"]
        else:
            faired = simple.ImplicitFairing(Input=split, NumberOfThreads=1, **settings)
        start = time.perf_counter()
        faired.UpdatePipeline()
        seconds = time.perf_counter() - start
        counts = ProgrammableFilter(Input=faired, OutputDataSetType="vtkPolyData")
        counts.Script = """
from vtkmodules.vtkCommonCore import vtkIdTypeArray, vtkPoints
d = self.GetInput().GetFieldData().GetArray("FairingDistribution")
i = self.GetInput().GetFieldData().GetArray("FairingIterations") or self.GetInput().GetFieldData().GetArray("FlowSolverIterations")
out = self.GetOutput()
p = vtkPoints()
p.InsertNextPoint(0.0, 0.0, 0.0)
out.SetPoints(p)
values = [d.GetValue(k) for k in range(4)] if d else [self.GetInput().GetNumberOfPoints(), 0,
          self.GetInput().GetNumberOfCells(), 0]
for k, name in enumerate(("Owned", "Ghosts", "Triangles", "Sent")):
    a = vtkIdTypeArray()
    a.SetName(name)
    a.InsertNextValue(values[k])
    out.GetPointData().AddArray(a)
a = vtkIdTypeArray()
a.SetName("Iterations")
total = 0  # (not sum(): the programmable filter's namespace has numpy_interface's)
for k in range(i.GetNumberOfTuples() if i else 0):
    total += i.GetValue(k)
a.InsertNextValue(total)
out.GetPointData().AddArray(a)
"""
        pd = servermanager.Fetch(counts).GetPointData()
        column = {n: vtk_to_numpy(pd.GetArray(n)).tolist() for n in ("Owned", "Ghosts", "Triangles", "Sent",
                                                                     "Iterations")}
        print("RESULT " + json.dumps(dict(ranks=ranks, case=name, noise=noise, seconds=seconds, **column)),
              flush=True)


def loop_bunny(levels=2):
    """bunny00 Loop-subdivided `levels` times (2: 603k points, 1.2M triangles)."""
    from vtkmodules.vtkFiltersModeling import vtkLoopSubdivisionFilter
    from beltrami import vtkOFFReader
    reader = vtkOFFReader()
    reader.SetFileName(os.path.join(os.path.dirname(HERE), "..", "Data", "bunny00.off"))
    loop = vtkLoopSubdivisionFilter()
    loop.SetInputConnection(reader.GetOutputPort())
    loop.SetNumberOfSubdivisions(levels)
    loop.Update()
    return loop.GetOutput()


def driver():
    import numpy as np
    from beltrami.pipelines import noisy_along_normals, write_vtp
    from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
    mesh = loop_bunny()
    p = vtk_to_numpy(mesh.GetPoints().GetData())
    print("Bunny: %d points, %d triangles; default step (order 2, 4 h^4), one thread per rank"
          % (mesh.GetNumberOfPoints(), mesh.GetNumberOfCells()))
    results = []
    with tempfile.TemporaryDirectory() as tmp:
        for noise in [n for n, cases in NOISES.items() if any(wanted(c) for c, _ in cases)]:
            noisy = noisy_along_normals(mesh, noise * float(np.linalg.norm(p.max(0) - p.min(0))), seed=1)
            f = numpy_to_vtk(np.sin(40 * p[:, 0]) * np.cos(30 * p[:, 1])
                             + np.random.default_rng(3).normal(0.0, 0.15, len(p)), deep=1)
            f.SetName("f")
            noisy.GetPointData().AddArray(f)
            mesh_file = os.path.join(tmp, "noisy.vtp")
            write_vtp(noisy, mesh_file)
            for ranks in (1, 2, 4):
                out = subprocess.run(["mpirun", "--allow-run-as-root", "--oversubscribe", "-np", str(ranks),
                                      "pvbatch", HERE, "--worker", mesh_file, repr(noise)]
                                     + (["--only", ONLY] if ONLY else []),
                                     capture_output=True, text=True, timeout=3000).stdout
                results += [json.loads(line[7:]) for line in out.splitlines() if line.startswith("RESULT ")]
    print("%-7s %-14s %5s %9s %8s %10s %13s %13s %11s" % ("noise", "solver", "ranks", "seconds", "speedup",
                                                            "iterations", "points/rank", "triangles/rk",
                                                            "sent/update"))
    for noise, cases in NOISES.items():
        for name, _ in [c for c in cases if wanted(c[0])]:
            runs = [r for r in results if r["case"] == name and r["noise"] == noise]
            base = next(r["seconds"] for r in runs if r["ranks"] == 1)
            for r in runs:
                held = max(o + g for o, g in zip(r["Owned"], r["Ghosts"]))
                print("%-7s %-14s %5d %9.2f %7.2fx %10d %12.1f%% %12.1f%% %11d" % (
                    "%g%%" % (100 * noise), name, r["ranks"], r["seconds"], base / r["seconds"],
                    max(r["Iterations"]), 100.0 * held / sum(r["Owned"]),
                    100.0 * max(r["Triangles"]) / mesh.GetNumberOfCells(), max(r["Sent"])))


if __name__ == "__main__":
    if "--worker" in sys.argv:
        worker(sys.argv[sys.argv.index("--worker") + 1], float(sys.argv[sys.argv.index("--worker") + 2]))
    else:
        driver()
