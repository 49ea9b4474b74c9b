"""vtkSurfaceVectorFieldDecomposition through the Python wrapping: point data
on a latitude-longitude sphere against the analytic parts, divergence and
curl; cell data on a torus (the harmonic rotation field) and on quads;
the parts summing to the tangent field and orthogonal; open surfaces under
both boundary conditions; an ill-conditioned locally refined surface; the
errors and warnings of bad input."""
import os
import sys
import unittest

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkFiltersSources import vtkPlaneSource, vtkSphereSource

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import inputs  # noqa: E402
from beltrami import vtkSurfaceVectorFieldDecomposition  # noqa: E402

PARTS = ("TangentField", "CurlFreePart", "DivergenceFreePart", "HarmonicPart")


def decompose(mesh, name, association=0, **settings):
    f = inputs.filter_with(vtkSurfaceVectorFieldDecomposition, **settings)()
    said = inputs.Messages(f, f.GetExecutive())
    f.SetInputData(mesh)
    f.SetInputArrayToProcess(0, 0, 0, association, name)
    f.Update()
    return f.GetOutput(), said


def add(mesh, name, values, cells=False):
    array = numpy_to_vtk(np.ascontiguousarray(values, dtype=float), deep=True)
    array.SetName(name)
    (mesh.GetCellData() if cells else mesh.GetPointData()).AddArray(array)
    return mesh


def arrays(out, cells=False):
    data = out.GetCellData() if cells else out.GetPointData()
    return {k: vtk_to_numpy(data.GetArray(k)) for k in PARTS}


def field_data(out, name):
    return out.GetFieldData().GetArray(name).GetValue(0)


def relative(a, b):
    return np.linalg.norm(a - b) / np.linalg.norm(b)


class Sphere(unittest.TestCase):
    """u = x y, v = 5 z^3 - 3 z on the unit sphere: X = grad u + n x grad v at
    the points; Laplace u = -6 u, Laplace v = -12 v."""

    @classmethod
    def setUpClass(cls):
        s = vtkSphereSource()
        s.SetThetaResolution(240)
        s.SetPhiResolution(120)
        s.SetRadius(1.0)
        s.Update()
        mesh = s.GetOutput()
        p = vtk_to_numpy(mesh.GetPoints().GetData()).astype(float)
        p /= np.linalg.norm(p, axis=1)[:, None]
        cls.p = p

        def tangent(g):
            return g - (g * p).sum(1)[:, None] * p
        cls.gradient = tangent(np.stack([p[:, 1], p[:, 0], 0 * p[:, 0]], 1))
        cls.rotated = np.cross(p, tangent(np.stack([0 * p[:, 0], 0 * p[:, 0], 15 * p[:, 2] ** 2 - 3], 1)))
        # A normal component too: removed and reported.
        add(mesh, "X", cls.gradient + cls.rotated + 0.5 * p)
        mesh.GetPointData().SetActiveVectors("X")
        cls.mesh = mesh
        cls.out, cls.said = decompose(mesh, "X")

    def test_parts_against_the_analytic_ones(self):
        a = arrays(self.out)
        self.assertFalse(self.said.errors or self.said.warnings, self.said.errors + self.said.warnings)
        self.assertLess(relative(a["CurlFreePart"], self.gradient), 0.01)
        self.assertLess(relative(a["DivergenceFreePart"], self.rotated), 0.01)
        self.assertLess(np.linalg.norm(a["HarmonicPart"]), 1e-6 * np.linalg.norm(a["TangentField"]))
        normal = vtk_to_numpy(self.out.GetPointData().GetArray("NormalComponent"))
        self.assertLess(np.abs(normal - 0.5).max(), 0.01)

    def test_divergence_curl_and_potentials(self):
        pd = self.out.GetPointData()
        u = self.p[:, 0] * self.p[:, 1]
        v = 5 * self.p[:, 2] ** 3 - 3 * self.p[:, 2]
        self.assertLess(relative(vtk_to_numpy(pd.GetArray("Divergence")), -6 * u), 0.01)
        self.assertLess(relative(vtk_to_numpy(pd.GetArray("Curl")), -12 * v), 0.01)
        potential = vtk_to_numpy(pd.GetArray("Potential"))
        stream = vtk_to_numpy(pd.GetArray("StreamFunction"))
        self.assertLess(relative(potential - potential.mean(), u - u.mean()), 0.01)
        self.assertLess(relative(stream - stream.mean(), v - v.mean()), 0.02)

    def test_parts_sum_and_are_orthogonal(self):
        a = arrays(self.out)
        total = a["CurlFreePart"] + a["DivergenceFreePart"] + a["HarmonicPart"]
        self.assertLess(np.abs(total - a["TangentField"]).max(), 1e-10 * np.abs(a["TangentField"]).max())
        energy = field_data(self.out, "TangentEnergy")
        for name in ("CurlFreeDivergenceFreeInnerProduct", "CurlFreeHarmonicInnerProduct",
                     "DivergenceFreeHarmonicInnerProduct"):
            self.assertLess(abs(field_data(self.out, name)), 1e-8 * energy, name)
        self.assertAlmostEqual(field_data(self.out, "CurlFreeEnergy") + field_data(self.out, "DivergenceFreeEnergy")
                               + field_data(self.out, "HarmonicEnergy"), energy, delta=1e-9 * energy)
        self.assertEqual(field_data(self.out, "ExcludedTriangles"), 0)


class TorusCells(unittest.TestCase):
    def test_the_rotation_field_is_harmonic(self):
        p, t = inputs.torus(n=160, m=64, major=1.0, minor=0.4)
        mesh = inputs.polydata(p, t)
        c = p[t].mean(axis=1)
        rho2 = c[:, 0] ** 2 + c[:, 1] ** 2
        add(mesh, "Flow", np.stack([-c[:, 1], c[:, 0], 0 * c[:, 0]], 1) / rho2[:, None], cells=True)
        out, said = decompose(mesh, "Flow", association=1)
        self.assertFalse(said.errors or said.warnings)
        a = arrays(out, cells=True)
        self.assertEqual(len(a["HarmonicPart"]), len(t))
        energy = field_data(out, "TangentEnergy")
        self.assertGreater(field_data(out, "HarmonicEnergy"), 0.999 * energy)
        self.assertLess(relative(a["HarmonicPart"], a["TangentField"]), 0.02)


class LatitudeLongitudeGrid(unittest.TestCase):
    """A global grid as climate data come: the seam at 0 and 360
    degrees and the poles' copies computed with sines and cosines (apart by
    round-off): welded, then decomposed as the sphere it is."""

    def test_the_seam_and_poles_are_welded(self):
        nlon, nlat = 144, 73  # 2.5 degrees
        lon, lat = np.meshgrid(np.radians(np.linspace(0, 360, nlon + 1)), np.radians(np.linspace(-90, 90, nlat)),
                               indexing="ij")
        p = np.stack([np.cos(lat) * np.cos(lon), np.cos(lat) * np.sin(lon), np.sin(lat)], -1).reshape(-1, 3)
        i, j = np.meshgrid(np.arange(nlon), np.arange(nlat - 1), indexing="ij")
        a, b, c, d = i * nlat + j, (i + 1) * nlat + j, (i + 1) * nlat + j + 1, i * nlat + j + 1
        mesh = inputs.polydata(p, np.concatenate([np.stack([a, b, c], -1), np.stack([a, c, d], -1)]).reshape(-1, 3))
        east = np.stack([-np.sin(lon), np.cos(lon), 0 * lon], -1).reshape(-1, 3)
        gradient = np.stack([p[:, 1], p[:, 0], 0 * p[:, 0]], 1)
        gradient -= (gradient * p).sum(1)[:, None] * p
        rotation = np.cos(lat).reshape(-1)[:, None] * east  # solid rotation: the stream function of z
        add(mesh, "wind", gradient + rotation)
        out, said = decompose(mesh, "wind")
        self.assertTrue(any("merged" in w for w in said.warnings), said.warnings)
        a = arrays(out)
        self.assertLess(relative(a["CurlFreePart"], gradient), 0.02)
        self.assertLess(relative(a["DivergenceFreePart"], rotation), 0.02)
        self.assertLess(np.linalg.norm(a["HarmonicPart"]), 1e-8 * np.linalg.norm(a["TangentField"]))
        curl = vtk_to_numpy(out.GetPointData().GetArray("Curl"))
        self.assertLess(relative(curl, 2 * p[:, 2]), 0.01)


class TimeSteps(unittest.TestCase):
    """Fields on a fixed mesh, one after the other (time steps): from the
    third run on the factorized systems are reused, with the numbers of a
    filter that decomposes each field from scratch; a changed mesh or
    setting prepares anew."""

    def test_prepared_systems_are_reused_with_the_same_numbers(self):
        p, t = inputs.torus(n=60, m=24, major=1.0, minor=0.4)  # genus 1: both systems factorized
        mesh = inputs.polydata(p, t)
        f = vtkSurfaceVectorFieldDecomposition()
        reused = []
        for step in range(4):
            add(mesh, "w", np.cross([0.0, 0.0, 1.0], p) * (1 + step) + step * p[:, [1, 2, 0]])
            f.SetInputData(mesh)
            f.SetInputArrayToProcess(0, 0, 0, 0, "w")
            f.Modified()
            f.Update()
            fresh, _ = decompose(mesh, "w")
            for name in PARTS:
                self.assertTrue(np.array_equal(arrays(f.GetOutput())[name], arrays(fresh)[name]), name)
            reused.append(field_data(f.GetOutput(), "PreparedSystemsReused"))
        self.assertEqual(reused, [0, 0, 1, 1])
        f.SetBoundaryCondition(1)  # (closed: the same numbers, but prepared anew)
        f.Update()
        self.assertEqual(field_data(f.GetOutput(), "PreparedSystemsReused"), 0)


class OpenSurfaces(unittest.TestCase):
    def plane(self):
        s = vtkPlaneSource()  # quads: triangulated inside, parts per quad
        s.SetResolution(30, 20)
        s.Update()
        mesh = s.GetOutput()
        c = np.array([mesh.GetCell(k).GetBounds() for k in range(mesh.GetNumberOfCells())])
        x, y = (c[:, 0] + c[:, 1]) / 2, (c[:, 2] + c[:, 3]) / 2
        return add(mesh, "V", np.stack([np.sin(3 * y) + x, np.cos(2 * x) - y * x, 0 * x], 1), cells=True)

    def test_both_boundary_conditions(self):
        mesh = self.plane()
        for condition in (0, 1):
            out, said = decompose(mesh, "V", association=1, BoundaryCondition=condition)
            self.assertFalse(said.errors or said.warnings)
            a = arrays(out, cells=True)
            self.assertEqual(len(a["CurlFreePart"]), mesh.GetNumberOfCells())
            self.assertLess(np.abs(a["CurlFreePart"] + a["DivergenceFreePart"] + a["HarmonicPart"]
                                   - a["TangentField"]).max(), 1e-10)
            energy = field_data(out, "TangentEnergy")
            for name in ("CurlFreeDivergenceFreeInnerProduct", "CurlFreeHarmonicInnerProduct",
                         "DivergenceFreeHarmonicInnerProduct"):
                self.assertLess(abs(field_data(out, name)), 1e-8 * energy)
            # (Harmonic fields with these conditions: 2g + boundary loops - 1, none on a disk.)
            self.assertLess(field_data(out, "HarmonicEnergy"), 1e-12 * energy, "a disk has no harmonic fields")
            if condition == 1:
                p = vtk_to_numpy(out.GetPoints().GetData())
                edge = (np.abs(np.abs(p[:, 0]) - 0.5) < 1e-9) | (np.abs(np.abs(p[:, 1]) - 0.5) < 1e-9)
                self.assertLess(np.abs(vtk_to_numpy(out.GetPointData().GetArray("Potential"))[edge]).max(), 1e-12)


class LocallyRefined(unittest.TestCase):
    @unittest.skipUnless(os.path.exists(os.path.join(inputs.SHARED_MESHES, "cylinder_locally_refined.off")),
                         "the shared corpus is not here")
    def test_the_edges_factorization_is_refined_to_the_tolerance(self):
        """cylinder_locally_refined after two Loop subdivisions (131k points,
        open): its edges' system is so ill-conditioned that the factorization's
        triangular solves alone miss the 1e-10 residual; refined, no iterative
        fallback is needed (which took 305 iterations and 14 s): only the
        points' multigrid iterates."""
        from vtkmodules.vtkFiltersCore import vtkTriangleFilter
        from vtkmodules.vtkFiltersModeling import vtkLoopSubdivisionFilter
        triangles = vtkTriangleFilter()
        triangles.SetInputData(inputs.read_off(os.path.join(inputs.SHARED_MESHES, "cylinder_locally_refined.off")))
        loop = vtkLoopSubdivisionFilter()
        loop.SetInputConnection(triangles.GetOutputPort())
        loop.SetNumberOfSubdivisions(2)
        loop.Update()
        out, said = decompose(inputs.with_vectors(loop.GetOutput()), "Vectors")
        self.assertFalse(said.errors or said.warnings)
        self.assertLessEqual(field_data(out, "SolverResidual"), 1e-10)
        self.assertLess(field_data(out, "SolverIterations"), 100)
        energy = field_data(out, "TangentEnergy")
        self.assertLess(abs(field_data(out, "CurlFreeDivergenceFreeInnerProduct")), 1e-8 * energy)


class BadInput(unittest.TestCase):
    def test_no_vector_array_is_an_error(self):
        p, t = inputs.sphere(12)
        mesh = inputs.with_scalars(inputs.polydata(p, t))
        for name in (None, "Scalars"):
            f = vtkSurfaceVectorFieldDecomposition()
            said = inputs.Messages(f, f.GetExecutive())
            f.SetInputData(mesh)
            if name:
                f.SetInputArrayToProcess(0, 0, 0, 0, name)
            f.Update()
            self.assertTrue(said.errors and "3 components" in said.errors[0], said.errors)

    def test_non_manifold_triangles_are_left_out(self):
        p, t = inputs.sphere(16)
        fin = len(p)
        p = np.vstack([p, [[0.0, 0.0, 3.0]]])
        t = np.vstack([t, [[t[0][0], t[0][1], fin]]])  # a third triangle on an edge
        mesh = inputs.with_vectors(inputs.polydata(p, t))
        out, said = decompose(mesh, "Vectors")
        self.assertTrue(any("left out" in w for w in said.warnings), said.warnings)
        excluded = field_data(out, "ExcludedTriangles")
        self.assertGreater(excluded, 0)
        self.assertLess(excluded, 50)  # the triangles at the edge's two points (one a pole)
        parts = arrays(out)["HarmonicPart"]
        self.assertTrue(np.isnan(parts[fin]).all())
        self.assertGreater(np.isfinite(parts[:, 0]).sum(), len(p) - 20)

    def test_triangles_left_out_keep_the_parts_orthogonal(self):
        # Triangles of zero area are left out.  Their rims bound what is
        # decomposed, and each boundary condition holds there too: the parts
        # were 0.15 of the energy from orthogonal on ParaView's Bohemian dome
        # (Sources > Parametric Surfaces), whose 158 such triangles along its
        # singular lines are now gone with the 79 edges of zero length they
        # stood on (collapsed by the repairs).  A sphere with three triangles
        # whose three corners coincide: one edge of each collapsed, the other
        # left, and its two triangles of zero area left out.
        dome = inputs.with_vectors(inputs.parametric_surface("BohemianDome"))
        p, t = inputs.sphere(24)
        p = p.copy()
        for k in (100, 400, 700):
            p[t[k, 1]] = p[t[k, 2]] = p[t[k, 0]]
        pinched = inputs.with_vectors(inputs.polydata(p, t))
        for surface, said_of_it in ((dome, "79 edges of zero length were collapsed"),
                                    (pinched, "6 triangles have zero area")):
            for boundary in (0, 1):
                out, said = decompose(surface, "Vectors", BoundaryCondition=boundary)
                self.assert_orthogonal(out, said, said_of_it)

    def test_solves_that_fail_on_folds_say_the_parts_are_wrong(self):
        # A hundredth of a sphere's triangles flattened (a corner moved onto
        # its opposite edge, the triangles beside it folded): the Poisson
        # solves stop at their iteration limit, and the parts' energies sum to
        # 4.8e10 times the field's.  Said so, not that the parts are
        # approximate.
        p, t = inputs.sphere(24)
        folded = inputs.with_vectors(inputs.polydata(inputs.flattened(p, t, 0.01), t))
        out, said = decompose(folded, "Vectors")
        self.assertTrue(any("the parts are wrong" in w for w in said.warnings), said.warnings)
        energy = [field_data(out, k + "Energy") for k in ("Tangent", "CurlFree", "DivergenceFree", "Harmonic")]
        self.assertGreater(sum(energy[1:]) / energy[0], 1.01)

    def assert_orthogonal(self, out, said, said_of_it):
        """The parts of `out` orthogonal and their energies summing to the
        field's; a warning holding `said_of_it`."""
        self.assertTrue(any(said_of_it in w for w in said.warnings), said.warnings)
        energy = [field_data(out, k + "Energy") for k in ("Tangent", "CurlFree", "DivergenceFree", "Harmonic")]
        for name in ("CurlFreeDivergenceFreeInnerProduct", "CurlFreeHarmonicInnerProduct",
                     "DivergenceFreeHarmonicInnerProduct"):
            self.assertLess(abs(field_data(out, name)), 1e-9 * energy[0], name)
        self.assertAlmostEqual(sum(energy[1:]) / energy[0], 1.0, delta=1e-9)

    def test_nan_vectors_count_as_zero(self):
        p, t = inputs.sphere(16)
        mesh = inputs.with_vectors(inputs.polydata(p, t))
        vtk_to_numpy(mesh.GetPointData().GetArray("Vectors"))[5] = np.nan
        out, said = decompose(mesh, "Vectors")
        self.assertFalse(said.errors)
        self.assertTrue(np.isfinite(arrays(out)["CurlFreePart"]).all())


if __name__ == "__main__":
    result = unittest.main(exit=False, verbosity=2).result
    sys.exit(0 if result.wasSuccessful() else 1)
