"""Benchmark (on demand): vtkSurfaceVectorFieldDecomposition on the bunny
Loop-subdivided twice (603k points, 1.2M triangles; genus 0: the stream
function integrated) and the eight five times (325k points; genus 2: the
stream function solved), a point field made from the coordinates, split
over 1, 2 and 4 ranks of pvbatch (RedistributeDataSet): wall time of the
filter, the conjugate gradients' iterations (both systems; the 1-rank run is
the serial code path, which solves the points' system on its multigrid and
factorizes the edges'), the largest share of the triangles a rank's piece
holds, and the largest difference from the serial potential over the points
(relative to its range).  One thread per rank: 2 ranks use the 2 cores of the CI
machines, 4 ranks are oversubscribed (2 per core).
Run:  source build/beltrami-env.sh && /usr/bin/python3 Testing/Benchmarks/benchmark_distributed_vector_fields.py
(it starts `mpirun ... pvbatch` itself; a worker prints one JSON line)."""
import json
import os
import subprocess
import sys
import tempfile
import time

HERE = os.path.abspath(__file__)
sys.path.insert(0, os.path.dirname(HERE))
WIND = "(coordsY - 0.1)*iHat - (coordsX + 0.02)*jHat + 10*exp(-200*((coordsX + 0.03)^2 + (coordsY - 0.1)^2))*kHat"


def worker(mesh_file):
    from paraview.simple import Calculator, ProgrammableFilter
    from paraview import servermanager, simple
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from benchmark_distributed_fairing import split_mesh
    ranks, split = split_mesh(mesh_file)
    wind = Calculator(Input=split, ResultArrayName="Wind", Function=WIND)
    wind.UpdatePipeline()
    decomposition = simple.SurfaceVectorFieldDecomposition(Input=wind, NumberOfThreads=1)
    decomposition.VectorField = ["POINTS", "Wind"]
    start = time.perf_counter()
    decomposition.UpdatePipeline()
    seconds = time.perf_counter() - start
    counts = ProgrammableFilter(Input=decomposition, OutputDataSetType="vtkPolyData")
    counts.Script = """
from vtkmodules.vtkCommonCore import vtkDoubleArray, vtkPoints
data = self.GetInput()
out = self.GetOutput()
p = vtkPoints()
p.InsertNextPoint(0.0, 0.0, 0.0)
out.SetPoints(p)
for name, value in (("Triangles", data.GetNumberOfCells()),
                    ("Iterations", data.GetFieldData().GetArray("SolverIterations").GetValue(0))):
    a = vtkDoubleArray()
    a.SetName(name)
    a.InsertNextValue(value)
    out.GetPointData().AddArray(a)
"""
    pd = servermanager.Fetch(counts).GetPointData()
    column = {n: vtk_to_numpy(pd.GetArray(n)).tolist() for n in ("Triangles", "Iterations")}
    # The potential at every point of every piece, for the comparison.
    potential = servermanager.Fetch(decomposition)
    points = vtk_to_numpy(potential.GetPoints().GetData()).tolist()
    values = vtk_to_numpy(potential.GetPointData().GetArray("Potential")).tolist()
    with open(mesh_file + ".%d.json" % ranks, "w") as f:
        json.dump(dict(points=points, values=values), f)
    print("RESULT " + json.dumps(dict(ranks=ranks, seconds=seconds, **column)), flush=True)


def driver():
    from beltrami.pipelines import write_vtp
    from benchmark_vector_fields import subdivided
    for name, levels in (("bunny00", 2), ("eight", 5)):
        mesh = subdivided(name, levels)
        print("%s Loop x%d: %d points, %d triangles; one thread per rank"
              % (name, levels, mesh.GetNumberOfPoints(), mesh.GetNumberOfCells()))
        results, potentials = [], {}
        with tempfile.TemporaryDirectory() as tmp:
            mesh_file = os.path.join(tmp, "mesh.vtp")
            write_vtp(mesh, mesh_file)
            for ranks in (1, 2, 4):
                out = subprocess.run(["mpirun", "--allow-run-as-root", "--oversubscribe", "-np", str(ranks),
                                      "pvbatch", HERE, "--worker", mesh_file], capture_output=True, text=True,
                                     timeout=3000).stdout
                results += [json.loads(line[7:]) for line in out.splitlines() if line.startswith("RESULT ")]
                with open(mesh_file + ".%d.json" % ranks) as f:
                    d = json.load(f)
                potentials[ranks] = {tuple(x): v for x, v in zip(d["points"], d["values"])}
        serial = potentials[1]
        span = max(serial.values()) - min(serial.values())
        print("%5s %9s %8s %10s %14s %12s" % ("ranks", "seconds", "speedup", "iterations", "triangles/rank",
                                              "potential"))
        base = next(r["seconds"] for r in results if r["ranks"] == 1)
        for r in results:
            difference = max(abs(v - serial[x]) for x, v in potentials[r["ranks"]].items()) / span
            print("%5d %9.2f %7.2fx %10d %13.1f%% %12.1e" % (
                r["ranks"], r["seconds"], base / r["seconds"], max(r["Iterations"]),
                100.0 * max(r["Triangles"]) / mesh.GetNumberOfCells(), difference))


if __name__ == "__main__":
    if "--worker" in sys.argv:
        worker(sys.argv[sys.argv.index("--worker") + 1])
    else:
        driver()
