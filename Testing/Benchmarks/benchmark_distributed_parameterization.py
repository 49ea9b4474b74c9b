"""Benchmark (on demand): vtkIntrinsicParameterization at its
defaults (DCP, circle boundary) on a height-field disk of n x n points,
on 1 rank (the serial path: one sparse direct factorization of the whole
system) and split over 2 and 4 ranks of pvbatch (each rank keeps its piece;
multigrid-preconditioned CG over the ranks).  The disk is made per rank by
a programmable source that honours piece requests (each rank makes its own
rows), so that at no point does one rank hold the whole mesh.  Prints the
wall time of the filter (the source already updated), the CG iterations,
each rank's peak memory (VmHWM, the source's piece included) and the
largest share of the points a rank holds.  2 ranks use the 2 cores of the
CI machines; 4 ranks are oversubscribed (2 per core): read those times as
such.
Run:  source build/beltrami-env.sh && /usr/bin/python3 Testing/Benchmarks/benchmark_distributed_parameterization.py [n ...]
(default sizes n = 346, 1000, 2237: 120k, 1M and 5M points)."""
import json
import os
import subprocess
import sys
import time

HERE = os.path.abspath(__file__)

DISK = """
import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, numpy_to_vtkIdTypeArray
from vtkmodules.vtkCommonCore import vtkPoints
from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkPolyData
from vtkmodules.vtkCommonExecutionModel import vtkStreamingDemandDrivenPipeline as sddp
info = self.GetOutputInformation(0)
piece, pieces = info.Get(sddp.UPDATE_PIECE_NUMBER()), info.Get(sddp.UPDATE_NUMBER_OF_PIECES())
n = %d
r0, r1 = (n - 1) * piece // pieces, (n - 1) * (piece + 1) // pieces  # rows of quads [r0, r1)
u, v = np.meshgrid(np.linspace(0.0, 1.0, n), np.linspace(0.0, 1.0, n)[r0:r1 + 1])
z = 0.1 * np.sin(6.0 * u) * np.cos(5.0 * v) + 0.02 * np.sin(37.0 * u * v)
pts = vtkPoints()
pts.SetData(numpy_to_vtk(np.column_stack([u.ravel(), v.ravel(), z.ravel()]), deep=1))
a = (np.arange(r1 - r0)[:, None] * n + np.arange(n - 1)[None, :]).ravel()
tri = np.concatenate([np.column_stack([a, a + 1, a + n + 1]), np.column_stack([a, a + n + 1, a + n])])
cells = vtkCellArray()
cells.SetData(3, numpy_to_vtkIdTypeArray(tri.ravel().astype(np.int64), deep=1))
out = vtkPolyData()
if r1 > r0:
    out.SetPoints(pts)
    out.SetPolys(cells)
self.GetOutput().ShallowCopy(out)
"""

PEAK = """
out = self.GetOutput()
out.ShallowCopy(self.GetInput())
from vtkmodules.vtkCommonCore import vtkDoubleArray
a = vtkDoubleArray()
a.SetName("PeakMemory")
for line in open("/proc/self/status"):
    if line.startswith("VmHWM"):
        a.InsertNextValue(float(line.split()[1]))
out.GetFieldData().AddArray(a)
"""


def worker(n):
    from paraview import servermanager, simple
    sys.path.insert(0, os.path.join(os.path.dirname(HERE), "..", "Python"))
    from configure import rank_rows
    simple.LoadPlugin(os.environ["BELTRAMI_PLUGIN"])
    ranks = servermanager.ActiveConnection.GetNumberOfDataPartitions()
    disk = simple.ProgrammableSource(OutputDataSetType="vtkPolyData")
    disk.ScriptRequestInformation = """
from vtkmodules.vtkCommonExecutionModel import vtkAlgorithm
self.GetOutputInformation(0).Set(vtkAlgorithm.CAN_HANDLE_PIECE_REQUEST(), 1)
"""
    disk.Script = DISK % n
    disk.UpdatePipeline()
    mapped = simple.IntrinsicParameterization(Input=disk)
    start = time.perf_counter()
    mapped.UpdatePipeline()
    seconds = time.perf_counter() - start
    peak = simple.ProgrammableFilter(Input=mapped)
    peak.Script = PEAK
    kb, = rank_rows(peak, "PeakMemory", ("kB",))
    record = {"points": n * n, "ranks": ranks, "seconds": round(seconds, 2), "peak_GB": [round(k / 2 ** 20, 2) for k in kb],
              "angle_distortion": mapped.FieldData["MeanAngleDistortion"].GetRange()[0]}
    if ranks > 1:
        owned, ghosts = rank_rows(mapped, "ParameterizationDistribution", ("Owned", "Ghosts"))
        record["iterations"] = mapped.FieldData["ParameterizationIterations"].GetRange()[0]
        record["largest_share"] = round(float((owned + ghosts).max()) / (n * n), 3)
    print("RESULT " + json.dumps(record), flush=True)


def main():
    sizes = [int(a) for a in sys.argv[1:]] or [346, 1000, 2237]
    mpirun = ["mpirun", "--allow-run-as-root", "--oversubscribe"] if os.geteuid() == 0 else ["mpirun", "--oversubscribe"]
    env = dict(os.environ, BELTRAMI_BENCHMARK_WORKER="1", OMP_NUM_THREADS="1")
    for n in sizes:
        results = {}
        for ranks in (1, 2, 4):
            run = subprocess.run(mpirun + ["-np", str(ranks), "pvbatch", HERE, str(n)], env=env,
                                 capture_output=True, text=True)
            lines = [line[7:] for line in run.stdout.splitlines() if line.startswith("RESULT ")]
            if not lines:
                print("n = %d on %d ranks: no result (exit %d)\n%s" % (n, ranks, run.returncode, run.stderr[-2000:]))
                continue
            results[ranks] = json.loads(lines[-1])
            print(json.dumps(results[ranks]), flush=True)
        if 1 in results:
            for ranks in (2, 4):
                if ranks in results:
                    print("  %d points: %d ranks %.2fx the serial direct solve's speed, largest rank peak %.2fx its memory"
                          % (n * n, ranks, results[1]["seconds"] / results[ranks]["seconds"],
                             max(results[ranks]["peak_GB"]) / results[1]["peak_GB"][0]))


if __name__ == "__main__":
    if os.environ.get("BELTRAMI_BENCHMARK_WORKER"):
        worker(int(sys.argv[1]))
    else:
        main()
