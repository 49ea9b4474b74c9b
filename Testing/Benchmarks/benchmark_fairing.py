"""Benchmark (on demand): one implicit curvature-flow step of vtkImplicitFairing
against vtkWindowedSincPolyDataFilter (20 iterations) on bunny00 Loop-subdivided
to ~300k and ~1.2M triangles, and accuracy on the noisy bunny (Gaussian noise of
0.3% of the bounding-box diagonal along the normals; RMS vertex distance to the
clean mesh) against the windowed-sinc filter at its best pass band.
Run:  source build/beltrami-env.sh && /usr/bin/python3 Testing/Benchmarks/benchmark_fairing.py
(CGAL's smooth_shape is not compared here: libcgal-dev is not part of the stack yet.)"""
import os
import time

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkPoints
from vtkmodules.vtkCommonDataModel import vtkPolyData
from vtkmodules.vtkFiltersCore import vtkPolyDataNormals, vtkWindowedSincPolyDataFilter
from vtkmodules.vtkFiltersModeling import vtkLoopSubdivisionFilter

from beltrami import vtkImplicitFairing, vtkOFFReader

DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "Data")


def timed(f):
    t = time.perf_counter()
    f.Update()
    return time.perf_counter() - t


def sinc(mesh, passband):
    w = vtkWindowedSincPolyDataFilter()
    w.SetInputData(mesh)
    w.SetNumberOfIterations(20)
    w.SetPassBand(passband)
    w.NormalizeCoordinatesOn()
    w.NonManifoldSmoothingOn()
    return w


def fairing(mesh, threads, step=10.0, steps=1):
    f = vtkImplicitFairing()
    f.SetInputData(mesh)
    f.SetTimeStep(step)
    f.SetNumberOfSteps(steps)
    f.SetNumberOfThreads(threads)
    return f


reader = vtkOFFReader()
reader.SetFileName(os.path.join(DATA, "bunny00.off"))
reader.Update()
bunny = reader.GetOutput()
print("Speed: one implicit curvature-flow step (lambda*dt = 10 h^2) vs windowed sinc, 20 iterations")
for level in (1, 2):
    loop = vtkLoopSubdivisionFilter()
    loop.SetInputData(bunny)
    loop.SetNumberOfSubdivisions(level)
    loop.Update()
    mesh = loop.GetOutput()
    t_sinc = timed(sinc(mesh, 0.1))
    for threads in (1, 2):
        f = fairing(mesh, threads)
        t = timed(f)
        print(f"  {mesh.GetNumberOfPolys():9d} triangles, {threads} thread(s): ours {t:.3f} s "
              f"({f.GetIterations(0)} CG iterations), windowed sinc {t_sinc:.3f} s, ratio {t_sinc / t:.2f}")

print("\nAccuracy: noisy bunny (sigma = 0.3% of the diagonal), RMS distance / diagonal")
clean = vtk_to_numpy(bunny.GetPoints().GetData()).astype(float)
normals = vtkPolyDataNormals()
normals.SetInputData(bunny)
normals.SplittingOff()
normals.Update()
n = vtk_to_numpy(normals.GetOutput().GetPointData().GetNormals()).astype(float)
diag = np.linalg.norm(clean.max(0) - clean.min(0))
noisy_points = clean + (0.003 * diag * np.random.default_rng(1).standard_normal(len(clean)))[:, None] * n
noisy = vtkPolyData()
noisy.DeepCopy(bunny)
pts = vtkPoints()
pts.SetData(numpy_to_vtk(noisy_points, deep=1))
noisy.SetPoints(pts)


def rms(f):
    f.Update()
    x = vtk_to_numpy(f.GetOutput().GetPoints().GetData())
    return float(np.sqrt(np.mean(np.sum((x - clean) ** 2, 1)))) / diag


print(f"  noisy input                     {float(np.sqrt(np.mean(np.sum((noisy_points - clean) ** 2, 1)))) / diag:.5f}")
best = min((rms(sinc(noisy, pb)), pb) for pb in (0.001, 0.005, 0.01, 0.02, 0.05, 0.1, 0.2))
print(f"  windowed sinc, best pass band {best[1]:<5} {best[0]:.5f}")
for step, steps in ((0.25, 3), (0.5, 2), (2.0, 1)):
    print(f"  curvature flow {steps} x {step} h^2        {rms(fairing(noisy, 0, step, steps)):.5f}")
