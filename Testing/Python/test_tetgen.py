"""vtkTetGenTetrahedralizer from /usr/bin/python3: quality tetrahedral meshes of
closed surfaces (elephant, bunny) with the requested radius-edge ratio and volume
bound, the enclosed volume kept, point data extended exactly for linear fields,
the chain TetGen -> vtkTetrahedralBeltramiDenoising, and clear errors for open,
self-intersecting and NaN input."""
import os
import unittest

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkOutputWindow, vtkStringOutputWindow
from vtkmodules.vtkCommonDataModel import vtkPolyData
from vtkmodules.vtkFiltersCore import vtkAppendPolyData, vtkFeatureEdges
from vtkmodules.vtkFiltersSources import vtkSphereSource

from beltrami import vtkOFFReader, vtkTetGenTetrahedralizer, vtkTetrahedralBeltramiDenoising
from configure import configured

DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "Data")


def read(name):
    r = vtkOFFReader()
    r.SetFileName(os.path.join(DATA, name))
    r.Update()
    return r.GetOutput()


def triangles(pd):
    return vtk_to_numpy(pd.GetPolys().GetConnectivityArray()).reshape(-1, 3)


def enclosed_volume(pd):
    p = vtk_to_numpy(pd.GetPoints().GetData()).astype(float)
    t = triangles(pd)
    return abs(np.einsum("ij,ij->i", p[t[:, 0]], np.cross(p[t[:, 1]], p[t[:, 2]])).sum()) / 6


def tetrahedra(grid):
    p = vtk_to_numpy(grid.GetPoints().GetData()).astype(float)
    t = vtk_to_numpy(grid.GetCells().GetConnectivityArray()).reshape(-1, 4)
    a, b, c, d = (p[t[:, k]] for k in range(4))
    signed = np.einsum("ij,ij->i", b - a, np.cross(c - a, d - a)) / 6
    # Radius-edge ratio: circumradius over the shortest edge.
    e = [b - a, c - a, d - a]
    m = np.stack(e, axis=1)
    rhs = 0.5 * np.stack([np.einsum("ij,ij->i", v, v) for v in e], axis=1)
    centre = np.linalg.solve(m, rhs[..., None])[..., 0]
    radius = np.linalg.norm(centre, axis=1)
    edges = [b - a, c - a, d - a, c - b, d - b, d - c]
    shortest = np.min([np.linalg.norm(v, axis=1) for v in edges], axis=0)
    return signed, radius / shortest


def tetgen(pd, **settings):
    return configured(vtkTetGenTetrahedralizer(), pd, **settings).GetOutput()


class Quality(unittest.TestCase):
    def test_elephant_and_bunny(self):
        for name in ("elephant.off", "bunny00.off"):
            surface = read(name)
            p = vtk_to_numpy(surface.GetPoints().GetData()).astype(float)
            linear = numpy_to_vtk(p[:, 0] + 2 * p[:, 1] - p[:, 2], deep=1)
            linear.SetName("linear")
            surface.GetPointData().AddArray(linear)
            volume = enclosed_volume(surface)
            grid = tetgen(surface, RadiusEdgeRatio=2.0)
            signed, ratio = tetrahedra(grid)
            print("%s: %d surface points -> %d points, %d tetrahedra; radius-edge ratio: max %.2f, "
                  "99th percentile %.3f" % (name, surface.GetNumberOfPoints(), grid.GetNumberOfPoints(),
                                            grid.GetNumberOfCells(), ratio.max(), np.percentile(ratio, 99)))
            self.assertTrue(np.all(grid.GetCellTypesArray() is None or
                                   vtk_to_numpy(grid.GetCellTypesArray()) == 10))  # VTK_TETRA
            self.assertGreater(np.abs(signed).min(), 0.0)
            self.assertTrue(np.all(signed > 0) or np.all(signed < 0))  # consistently oriented
            self.assertAlmostEqual(np.abs(signed).sum() / volume, 1.0, delta=1e-9)
            self.assertLess(np.percentile(ratio, 99), 2.0 + 1e-6)
            # Input points first, unchanged; the linear field extended exactly.
            q = vtk_to_numpy(grid.GetPoints().GetData())
            self.assertTrue(np.array_equal(q[:len(p)], p))
            f = vtk_to_numpy(grid.GetPointData().GetArray("linear"))
            self.assertLess(np.abs(f - (q[:, 0] + 2 * q[:, 1] - q[:, 2])).max(), 1e-8)

    def test_maximum_volume_and_denoising_chain(self):
        surface = read("elephant.off")
        limit = enclosed_volume(surface) / 2000
        # (Surface kept as it is, tetrahedra at the boundary cannot always be split.)
        grid = tetgen(surface, RadiusEdgeRatio=1.5, MaximumVolume=limit, PreserveSurface=False)
        signed, _ = tetrahedra(grid)
        self.assertLessEqual(np.abs(signed).max(), limit * (1 + 1e-9))
        self.assertGreater(grid.GetNumberOfCells(), 2000)
        # A noisy field on the tetrahedra, smoothed by the volume flow.
        p = vtk_to_numpy(grid.GetPoints().GetData())
        clean = (p[:, 0] > np.median(p[:, 0])).astype(float)
        noisy = clean + np.random.default_rng(2).normal(0, 0.1, clean.shape)
        a = numpy_to_vtk(noisy, deep=1)
        a.SetName("f")
        grid.GetPointData().SetScalars(a)
        d = vtkTetrahedralBeltramiDenoising()
        d.SetInputData(grid)
        d.SetContrastScale(15.0)
        d.SetNoiseLevel(0.1)
        d.SetNumberOfIterations(100)
        d.Update()
        out = vtk_to_numpy(d.GetOutput().GetPointData().GetArray("f"))
        rms = lambda v: np.sqrt(np.mean((v - clean) ** 2))  # noqa: E731
        print("elephant field: RMS error noisy %.3f -> %.3f" % (rms(noisy), rms(out)))
        self.assertLess(rms(out), 0.7 * rms(noisy))

    def test_points_of_no_triangle_are_not_meshed(self):
        # A closed sphere with its feature edges as line cells on copies of
        # its points (an appended vtkFeatureEdges output): the copies were
        # passed to TetGen, which dropped them, and the run failed
        # ("malformed answer"). They come back unused at their places.
        s = vtkSphereSource()
        s.SetThetaResolution(16)
        s.SetPhiResolution(16)
        edges = vtkFeatureEdges()
        edges.SetInputConnection(s.GetOutputPort())
        edges.BoundaryEdgesOff()
        edges.SetFeatureAngle(5.0)
        both = vtkAppendPolyData()
        both.AddInputConnection(s.GetOutputPort())
        both.AddInputConnection(edges.GetOutputPort())
        both.Update()
        surface = both.GetOutput()
        n = surface.GetNumberOfPoints()
        self.assertGreater(surface.GetNumberOfLines(), 0)
        grid = tetgen(surface)
        signed, _ = tetrahedra(grid)
        s.Update()
        self.assertAlmostEqual(np.abs(signed).sum() / enclosed_volume(s.GetOutput()), 1.0, delta=1e-9)
        q = vtk_to_numpy(grid.GetPoints().GetData())
        self.assertTrue(np.array_equal(q[:n], vtk_to_numpy(surface.GetPoints().GetData())))
        used = np.unique(vtk_to_numpy(grid.GetCells().GetConnectivityArray()))
        self.assertFalse(np.isin(np.arange(s.GetOutput().GetNumberOfPoints(), n), used).any())


class BadInput(unittest.TestCase):
    def setUp(self):
        self.log = vtkStringOutputWindow()
        vtkOutputWindow.SetInstance(self.log)

    def check_error(self, pd, message):
        grid = tetgen(pd)
        self.assertIn(message, self.log.GetOutput())
        self.assertEqual(grid.GetNumberOfCells(), 0)

    def test_errors(self):
        s = vtkSphereSource()
        s.SetThetaResolution(16)
        s.SetPhiResolution(16)
        s.Update()
        open_sphere = vtkPolyData()
        open_sphere.DeepCopy(s.GetOutput())
        open_sphere.BuildLinks()
        open_sphere.DeleteCell(0)
        open_sphere.RemoveDeletedCells()
        self.check_error(open_sphere, "boundary edges")

        t = vtkSphereSource()
        t.SetCenter(0.3, 0, 0)
        t.SetThetaResolution(16)
        t.SetPhiResolution(16)
        both = vtkAppendPolyData()
        both.AddInputConnection(s.GetOutputPort())
        both.AddInputConnection(t.GetOutputPort())
        both.Update()
        self.check_error(both.GetOutput(), "intersects itself")

        nan = vtkPolyData()
        nan.DeepCopy(s.GetOutput())
        nan.GetPoints().SetPoint(3, float("nan"), 0, 0)
        self.check_error(nan, "NaN")

        empty = tetgen(vtkPolyData())
        self.assertEqual(empty.GetNumberOfCells(), 0)


if __name__ == "__main__":
    unittest.main()
