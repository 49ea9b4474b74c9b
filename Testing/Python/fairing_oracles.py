"""The fairing at its defaults against oracles chosen with the clean mesh:
shared by the defaults' test (test_fairing_defaults.py) and the fairing
benchmark's table (benchmark_fairing.py --defaults).

A case is a mesh with Gaussian noise of a fraction of its bounding-box
diagonal along its normals (a fixed seed); every error is the RMS distance
of the points to the clean ones over the diagonal:
  defaults   vtkImplicitFairing with nothing set (the step and the operator
             chosen from the noise), with its estimated noise and error
  own best   the filter's best step for the curvature flow and for the
             umbrella (order 2, one step; steps a factor of 2 apart)
  sinc best  vtkWindowedSincPolyDataFilter (20 iterations, normalised
             coordinates) at its best pass band
"""
import time

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkFiltersCore import vtkTriangleFilter, vtkWindowedSincPolyDataFilter

from beltrami import vtkImplicitFairing, vtkOFFReader
from beltrami.pipelines import noisy_along_normals, noisy_isotropic

import inputs

CURVATURE_STEPS = [0.01 * 2.0 ** k for k in range(16)]  # h^4
UMBRELLA_STEPS = [0.16 * 2.0 ** k for k in range(16)]   # dimensionless
PASS_BANDS = (0.001, 0.003, 0.01, 0.03, 0.1, 0.2, 0.5, 1.0)


def read_triangles(path):
    reader = vtkOFFReader()
    reader.SetFileName(path)
    triangles = vtkTriangleFilter()
    triangles.SetInputConnection(reader.GetOutputPort())
    triangles.Update()
    return triangles.GetOutput()


def points_of(polydata):
    return vtk_to_numpy(polydata.GetPoints().GetData()).astype(float)


def error(polydata, clean, diagonal):
    return float(np.sqrt(np.mean(np.sum((points_of(polydata) - clean) ** 2, 1)))) / diagonal


def faired(noisy, warnings=None, **settings):
    """The output and seconds; the filter's warnings appended to `warnings`."""
    f = vtkImplicitFairing()
    said = inputs.Messages(f, f.GetExecutive())
    f.SetInputData(noisy)
    for name, value in settings.items():
        getattr(f, "Set" + name)(value)
    start = time.perf_counter()
    f.Update()
    if warnings is not None:
        warnings.extend(said.warnings)
    return f.GetOutput(), time.perf_counter() - start


def sinc_filter(noisy, pass_band):
    """vtkWindowedSincPolyDataFilter as the benchmarks run it (not updated)."""
    w = vtkWindowedSincPolyDataFilter()
    w.SetInputData(noisy)
    w.SetNumberOfIterations(20)
    w.SetPassBand(pass_band)
    w.NormalizeCoordinatesOn()
    w.NonManifoldSmoothingOn()
    return w


def windowed_sinc(noisy, pass_band):
    w = sinc_filter(noisy, pass_band)
    start = time.perf_counter()
    w.Update()
    return w.GetOutput(), time.perf_counter() - start


def field(polydata, name):
    a = polydata.GetFieldData().GetArray(name)
    return a.GetValue(0) if a else float("nan")


def case(mesh, level, seed=1, oracles=True, isotropic=False, own=True):
    """One mesh and noise level (along the normals, or isotropic): a dict of
    the errors (over the diagonal), the defaults' estimates and times; the
    oracles only when asked (the own best step's sweep unless own=False)."""
    clean = points_of(mesh)
    diagonal = float(np.linalg.norm(clean.max(0) - clean.min(0)))
    noise = noisy_isotropic if isotropic else noisy_along_normals
    noisy = noise(mesh, level * diagonal, seed=seed) if level > 0 else mesh
    warnings = []
    result, seconds = faired(noisy, warnings)
    row = {"warned": any("scale of its triangles" in w for w in warnings), "noise": level, "input": error(noisy, clean, diagonal), "defaults": error(result, clean, diagonal),
           "seconds": seconds, "estimated noise": field(result, "FairingNoise") / diagonal,
           "estimated error": field(result, "FairingEstimatedError") / diagonal,
           "tangential noise": field(result, "FairingTangentialNoise") / diagonal,
           "step": field(result, "FairingTimeStep"), "operator": field(result, "FairingOperator"),
           "moved": float(np.sqrt(np.mean(np.sum((points_of(result) - points_of(noisy)) ** 2, 1))))}
    if oracles and own:
        swept = [(error(faired(noisy, Operator=operator, TimeStep=step)[0], clean, diagonal), step, operator)
                 for operator, steps in ((vtkImplicitFairing.CURVATURE_FLOW, CURVATURE_STEPS),
                                         (vtkImplicitFairing.UMBRELLA, UMBRELLA_STEPS)) for step in steps]
        row["own best"], row["own best step"], row["own best operator"] = min(swept)
    if oracles:
        sinc = [(error(out, clean, diagonal), band, seconds) for band in PASS_BANDS
                for out, seconds in [windowed_sinc(noisy, band)]]
        row["sinc best"], row["sinc pass band"], row["sinc seconds"] = min(sinc)
    return row


def mean_edge_length(mesh):
    p = points_of(mesh)
    t = vtk_to_numpy(mesh.GetPolys().GetConnectivityArray()).reshape(-1, 3)
    return float(np.mean([np.linalg.norm(p[t[:, a]] - p[t[:, (a + 1) % 3]], axis=1).mean() for a in range(3)]))
