"""vtkBeltramiOperators (thesis section 2.8 as outputs) from
/usr/bin/python3: the operators of a Gaussian image against the analytic
graph, the same image in another plane, pieces equal to the whole image, the
automatic contrast scale on the real camera image, point data on a surface,
voxels of an unstructured grid equal to the 3D image path, and bad input."""
import os
import unittest

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkOutputWindow, vtkPoints, vtkStringOutputWindow
from vtkmodules.vtkCommonDataModel import VTK_VOXEL, vtkCellArray, vtkImageData, vtkPolyData, vtkUnstructuredGrid
from vtkmodules.vtkFiltersSources import vtkPlaneSource

from beltrami import pipelines, vtkBeltramiOperators
from configure import configured

DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "Data")


def image(values, dims, spacing=(1.0, 1.0, 1.0)):
    img = vtkImageData()
    img.SetDimensions(*dims)
    img.SetSpacing(*spacing)
    arr = numpy_to_vtk(np.ascontiguousarray(values.reshape(int(np.prod(dims)), -1)), deep=1)
    arr.SetName("f")
    img.GetPointData().SetScalars(arr)
    return img


def arrays(data):
    pd = data.GetPointData()
    return {pd.GetArrayName(i): vtk_to_numpy(pd.GetArray(i)) for i in range(pd.GetNumberOfArrays())}


def field(data, name):
    return data.GetFieldData().GetArray(name).GetValue(0)


def gaussian_graph(x, y, alpha):
    """u = alpha exp(-(x^2 + y^2) / 2): Delta_g f, mean curvature |div(grad u / W)| / 2,
    Gaussian curvature and 1/W of the graph (x, y, u)."""
    u = alpha * np.exp(-(x * x + y * y) / 2)
    ux, uy = -x * u, -y * u
    uxx, uyy, uxy = (x * x - 1) * u, (y * y - 1) * u, x * y * u
    w2 = 1 + ux * ux + uy * uy
    div = ((1 + uy * uy) * uxx + (1 + ux * ux) * uyy - 2 * ux * uy * uxy) / w2 ** 1.5
    return div / np.sqrt(w2) / alpha, np.abs(div) / 2, (uxx * uyy - uxy * uxy) / w2 ** 2, 1 / np.sqrt(w2)




class GraphOperatorsTest(unittest.TestCase):
    def setUp(self):
        self.log = vtkStringOutputWindow()
        vtkOutputWindow.SetInstance(self.log)

    def gaussian(self, n=129):
        h = 8.0 / (n - 1)
        y, x = np.mgrid[0:n, 0:n] * h - 4
        return np.exp(-(x * x + y * y) / 2), x, y, h

    def test_gaussian_image_matches_the_analytic_graph(self):
        f, x, y, h = self.gaussian()
        out = configured(vtkBeltramiOperators(), image(f, (129, 129, 1), (h, h, 1)), ContrastScale=2.0).GetOutput()
        a = arrays(out)
        beltrami, mean, gauss, indicator = gaussian_graph(x.ravel(), y.ravel(), 2.0)
        rel = lambda got, want: np.max(np.abs(got - want)) / np.max(np.abs(want))
        self.assertLess(rel(a["BeltramiOperator"], beltrami), 0.01)
        self.assertLess(rel(a["MeanCurvature"], mean), 0.01)
        self.assertLess(rel(a["GaussianCurvature"], gauss), 0.02)
        self.assertLess(np.max(np.abs(a["EdgeIndicator"] - indicator)), 3e-3)
        normal = a["MeanCurvatureNormal"]
        self.assertEqual(normal.shape, (129 * 129, 4))  # x, y, z, data
        np.testing.assert_allclose(normal[:, 3], -2.0 * a["BeltramiOperator"], atol=1e-12)
        self.assertEqual(np.abs(normal[:, 2]).max(), 0.0)
        self.assertEqual(field(out, "GraphContrastScale"), 2.0)
        # The same image in the XZ plane: the normal's base part on x and z.
        xz = configured(vtkBeltramiOperators(), image(f, (129, 1, 129), (h, 1, h)), ContrastScale=2.0).GetOutput()
        b = arrays(xz)
        np.testing.assert_allclose(b["GaussianCurvature"], a["GaussianCurvature"], atol=1e-12)
        np.testing.assert_allclose(b["MeanCurvatureNormal"][:, [0, 2, 3]], normal[:, [0, 1, 3]], atol=1e-12)
        self.assertEqual(np.abs(b["MeanCurvatureNormal"][:, 1]).max(), 0.0)

    def test_pieces_give_the_whole_image(self):
        # A given contrast scale: each piece with one ring of neighbours; the
        # automatic one: each piece reads the whole image for the noise estimate.
        rng = np.random.default_rng(4)
        f = rng.normal(0.0, 1.0, (40, 50)).cumsum(axis=1) * 0.05
        for settings in ({"ContrastScale": 3.0}, {}):
            whole = arrays(configured(vtkBeltramiOperators(), image(f, (50, 40, 1)), **settings).GetOutput())
            filt = configured(vtkBeltramiOperators(), image(f, (50, 40, 1)), update=False, **settings)
            for piece in range(4):
                filt.UpdatePiece(piece, 4, 0)
                out = filt.GetOutput()
                ext = out.GetExtent()
                ids = (np.arange(ext[2], ext[3] + 1)[:, None] * 50 + np.arange(ext[0], ext[1] + 1)[None, :]).ravel()
                got = arrays(out)
                self.assertLess(len(ids), 50 * 40)
                for name in ("MeanCurvatureNormal", "GaussianCurvature", "EdgeIndicator"):
                    np.testing.assert_allclose(got[name], whole[name][ids], rtol=0, atol=1e-12, err_msg=name)

    def test_automatic_contrast_on_the_camera_image(self):
        # The denoising filters' rule, alpha = 1.5 h / sigma with sigma
        # estimated, and an edge map that follows the clean image's edges.
        clean = pipelines.read_png(os.path.join(DATA, "camera.png"))[::-1].astype(float) / 255
        clean = clean[..., 0] if clean.ndim == 3 else clean
        noisy = clean + np.random.default_rng(1).normal(0.0, 0.05, clean.shape)
        h, w = clean.shape
        out = configured(vtkBeltramiOperators(), image(noisy, (w, h, 1), (0.5, 0.5, 1))).GetOutput()
        sigma = field(out, "EstimatedNoiseLevel")
        self.assertAlmostEqual(sigma, 0.05, delta=0.005)
        self.assertAlmostEqual(field(out, "GraphContrastScale"), 1.5 * 0.5 / sigma, delta=1e-9)
        indicator = arrays(out)["EdgeIndicator"].reshape(h, w)
        gy, gx = np.gradient(clean)
        g = np.hypot(gx, gy)
        strong, flat = g >= np.quantile(g, 0.9), g <= np.quantile(g, 0.5)
        self.assertLess(np.median(indicator[strong]), 0.7 * np.median(indicator[flat]))
        self.assertGreater(np.corrcoef(1 - indicator.ravel(), g.ravel())[0, 1], 0.4)

    def test_point_data_on_a_surface(self):
        # A flat mesh with the Gaussian as point data: the graph of the image
        # test on one diagonal; the mesh boundary is undefined (NaN).
        plane = configured(vtkPlaneSource(), Origin=(-4, -4, 0), Point1=(4, -4, 0), Point2=(-4, 4, 0),
                           XResolution=128, YResolution=128)
        surface = plane.GetOutput()
        pts = vtk_to_numpy(surface.GetPoints().GetData())
        f = numpy_to_vtk(np.exp(-(pts[:, 0] ** 2 + pts[:, 1] ** 2) / 2), deep=1)
        f.SetName("f")
        surface.GetPointData().SetScalars(f)
        out = configured(vtkBeltramiOperators(), surface, ContrastScale=2.0).GetOutput()
        a = arrays(out)
        beltrami, mean, gauss, indicator = gaussian_graph(pts[:, 0], pts[:, 1], 2.0)
        boundary = (np.abs(pts[:, 0]) > 3.99) | (np.abs(pts[:, 1]) > 3.99)
        self.assertTrue(np.all(np.isnan(a["GaussianCurvature"][boundary])))
        self.assertEqual(field(out, "GraphUndefinedPoints"), boundary.sum())
        # (NaN there by design, as documented: no warning that blames the data)
        self.assertNotIn("NaN or infinite", self.log.GetOutput())
        inner = ~boundary
        rel = lambda got, want: np.max(np.abs(got[inner] - want[inner])) / np.max(np.abs(want[inner]))
        self.assertLess(rel(a["BeltramiOperator"], beltrami), 0.01)
        self.assertLess(rel(a["GaussianCurvature"], gauss), 0.02)
        self.assertLess(np.max(np.abs(a["EdgeIndicator"][inner] - indicator[inner])), 5e-3)

    def test_voxels_equal_the_3d_image(self):
        # An unstructured grid of voxels (split into the Kuhn tetrahedra of the
        # 3D image path) with 2-component data: its interior points equal the
        # image's, its boundary points are undefined.
        n = 12
        rng = np.random.default_rng(2)
        f = rng.normal(0.0, 0.2, (n, n, n, 2)).cumsum(axis=0)
        img = image(f, (n, n, n), (1.0, 0.5, 2.0))
        volume = arrays(configured(vtkBeltramiOperators(), img, ContrastScale=1.0).GetOutput())
        self.assertNotIn("GaussianCurvature", volume)
        grid = vtkUnstructuredGrid()
        points = vtkPoints()
        points.SetData(numpy_to_vtk(np.array([img.GetPoint(i) for i in range(n ** 3)]), deep=1))
        grid.SetPoints(points)
        k, j, i = np.mgrid[0:n - 1, 0:n - 1, 0:n - 1]
        base = (i + n * (j + n * k)).ravel()
        corners = [base + dx + n * dy + n * n * dz for dz in (0, 1) for dy in (0, 1) for dx in (0, 1)]
        cells = vtkCellArray()
        for c in np.stack(corners, axis=1):
            cells.InsertNextCell(8, [int(v) for v in c])
        grid.SetCells(VTK_VOXEL, cells)
        grid.GetPointData().SetScalars(img.GetPointData().GetScalars())
        out = configured(vtkBeltramiOperators(), grid, ContrastScale=1.0).GetOutput()
        mesh = arrays(out)
        interior = np.isfinite(mesh["MeanCurvature"])
        self.assertEqual(interior.sum(), (n - 2) ** 3)
        self.assertEqual(field(out, "GraphUndefinedPoints"), n ** 3 - (n - 2) ** 3)
        np.testing.assert_allclose(mesh["MeanCurvatureNormal"][interior], volume["MeanCurvatureNormal"][interior],
                                   atol=1e-12)
        np.testing.assert_allclose(mesh["BeltramiOperator"][interior], volume["BeltramiOperator"][interior],
                                   atol=1e-12)

    def test_bad_input(self):
        f, _, _, h = self.gaussian(17)
        img = image(f, (17, 17, 1))
        # No array selected by name that exists: an error, the output is the input.
        filt = vtkBeltramiOperators()
        filt.SetInputArrayToProcess(0, 0, 0, 0, "missing")
        configured(filt, img)
        self.assertIn("No point array", self.log.GetOutput())
        self.assertNotIn("MeanCurvature", arrays(filt.GetOutput()))
        # Seven components: an error.
        seven = image(np.zeros((17 * 17, 7)), (17, 17, 1))
        out = configured(vtkBeltramiOperators(), seven).GetOutput()
        self.assertIn("7 components", self.log.GetOutput())
        self.assertNotIn("MeanCurvature", arrays(out))
        # NaN in the data: a warning, finite values away from it.
        g = f.copy()
        g[8, 8] = np.nan
        a = arrays(configured(vtkBeltramiOperators(), image(g, (17, 17, 1)), ContrastScale=1.0).GetOutput())
        self.assertIn("NaN or infinite", self.log.GetOutput())
        self.assertTrue(np.isfinite(a["MeanCurvature"].reshape(17, 17)[:4]).all())
        # Lines only, and an empty data set: a warning or nothing, never a crash.
        lines = vtkPolyData()
        lines.SetPoints(vtkPoints())
        configured(vtkBeltramiOperators(), lines)
        configured(vtkBeltramiOperators(), vtkUnstructuredGrid())
        configured(vtkBeltramiOperators(), vtkImageData())


if __name__ == "__main__":
    unittest.main()
