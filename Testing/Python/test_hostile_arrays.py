"""The arrays a filter reads (importance, constraints, data, vectors) with
NaN, infinite, huge, negative or all-NaN values on a sphere: no crash,
finite output points, and wherever a value is NaN or infinite (or the
result overflows) a warning or an error that says so: never silently
dropped or silently non-finite numbers."""
import sys
import unittest

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonDataModel import vtkDataObject
from vtkmodules.vtkFiltersSources import vtkSphereSource

import beltrami as b
import inputs


def sphere():
    s = vtkSphereSource()
    s.SetThetaResolution(24)
    s.SetPhiResolution(16)
    s.Update()
    return s.GetOutput()


POINTS = sphere().GetNumberOfPoints()


def variants(components):
    """name -> values of a point array: a few hostile values among valid
    ones in [0, 1), or all NaN."""
    shape = (POINTS,) if components == 1 else (POINTS, components)
    good = np.random.default_rng(0).random(shape)
    out = {}
    for name, value in (("nan", np.nan), ("inf", np.inf), ("-inf", -np.inf), ("huge", 1e300), ("negative", -5.0)):
        v = good.copy()
        v.flat[7] = v.flat[30] = value
        out[name] = v
    out["all-nan"] = np.full(shape, np.nan)
    return out


def chosen(index):
    return lambda f: f.SetInputArrayToProcess(index, 0, 0, vtkDataObject.FIELD_ASSOCIATION_POINTS, "A")


def remesher(importance):
    def setup(f):
        f.SetNumberOfVertices(300)
        f.SetImportance(b.vtkSurfaceRemeshing.POINT_ARRAY)
        importance(f)
    return setup


# (name, filter, components, set-up, the variants that must be reported:
# NaN and infinite values, and where the numbers overflow, "huge").
CASES = [
    ("remeshing importance", b.vtkSurfaceRemeshing, 1, remesher(chosen(0)), ("nan", "inf", "-inf", "all-nan")),
    ("fairing fixed points", b.vtkImplicitFairing, 1, chosen(0), ("nan", "all-nan")),
    ("fairing weights", b.vtkImplicitFairing, 1, chosen(1), ("nan", "inf", "-inf", "huge", "negative", "all-nan")),
    ("fairing axes", b.vtkImplicitFairing, 3, chosen(2), ("nan", "inf", "-inf", "all-nan")),
    ("fairing planes", b.vtkImplicitFairing, 3, chosen(3), ("nan", "inf", "-inf", "all-nan")),
    ("surface data denoising", b.vtkSurfaceDataDenoising, 1, chosen(0), ("nan", "inf", "-inf", "all-nan")),
    ("graph operators", b.vtkBeltramiOperators, 1, chosen(0), ("nan", "inf", "-inf", "huge", "all-nan")),
    ("vector fields", b.vtkSurfaceVectorFieldDecomposition, 3, chosen(0), ("nan", "inf", "-inf", "huge", "all-nan")),
]


class HostileArrays(unittest.TestCase):
    def test_reported_never_silent(self):
        for name, make, components, setup, reported in CASES:
            for variant, values in variants(components).items():
                with self.subTest(case=name, values=variant):
                    data = sphere()
                    array = numpy_to_vtk(np.ascontiguousarray(values))
                    array.SetName("A")
                    data.GetPointData().AddArray(array)
                    f = make()
                    setup(f)
                    said = inputs.Messages(f, f.GetExecutive())
                    f.SetInputData(data)
                    f.Update()
                    out = f.GetOutputDataObject(0)
                    if out.GetNumberOfPoints():
                        self.assertTrue(np.all(np.isfinite(vtk_to_numpy(out.GetPoints().GetData()))))
                    if variant in reported:
                        self.assertTrue(said.errors or said.warnings, "nothing said")
        print("hostile arrays test passed")
        sys.stdout.flush()


if __name__ == "__main__":
    unittest.main()
