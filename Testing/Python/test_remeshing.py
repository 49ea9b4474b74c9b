"""vtkSurfaceRemeshing (thesis chapter 4) from /usr/bin/python3: real meshes, generated hard shapes and
hostile inputs through the wrapping."""
import os
import re
import unittest

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkOutputWindow, vtkPoints, vtkStringOutputWindow
from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkPolyData

from beltrami import vtkOFFReader, vtkSurfaceRemeshing

DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "Data")


class RemeshingFromPython(unittest.TestCase):
    """vtkSurfaceRemeshing (thesis chapter 4) through the wrapping."""

    def remesher(self, name="mushroom.off"):
        reader = vtkOFFReader()
        reader.SetFileName(os.path.join(DATA, name))
        f = vtkSurfaceRemeshing()
        f.SetInputConnection(reader.GetOutputPort())
        return reader, f

    def remeshed(self, data, count, features=False, **settings):
        """(output, what VTK printed) of a remesh of `data` with `count`
        vertices at the defaults (but `settings`: name -> value)."""
        f = vtkSurfaceRemeshing()
        f.SetInputData(data)
        f.SetNumberOfVertices(count)
        f.SetSplitAtFeatures(features)
        for name, value in settings.items():
            getattr(f, "Set" + name)(value)
        log = vtkStringOutputWindow()
        vtkOutputWindow.SetInstance(log)
        self.assertEqual(f.GetExecutive().Update(), 1, log.GetOutput())
        self.last_control_map_dimensions = f.GetOutputDataObject(1).GetBlock(0).GetDimensions()
        return f.GetOutput(), log.GetOutput()

    def assert_topology_kept(self, surface, out):
        """The remesh `out` has the topology of `surface` (of its pinched
        points split, as the remesher splits them): Euler characteristic,
        components, boundary loops, manifold and oriented."""
        import inputs
        expected = inputs.topology(*inputs.arrays_of(surface))
        if not expected["manifold"]:
            expected = inputs.topology(*inputs.split_pinched(*inputs.arrays_of(surface)))
        got = inputs.topology(*inputs.arrays_of(out))
        for key in ("euler", "components", "loops", "manifold", "oriented"):
            self.assertEqual(got[key], expected[key], key)

    def test_exact_count_point_data_and_the_kept_atlas(self):
        reader, f = self.remesher()
        reader.Update()
        heights = numpy_to_vtk(vtk_to_numpy(reader.GetOutput().GetPoints().GetData())[:, 2].copy())
        heights.SetName("Height")
        reader.GetOutput().GetPointData().AddArray(heights)
        # A cell label (the side of x = 0 of the triangle's centre): each remesh triangle takes the nearest input cell's.
        xyz = vtk_to_numpy(reader.GetOutput().GetPoints().GetData())
        cells = vtk_to_numpy(reader.GetOutput().GetPolys().GetConnectivityArray()).reshape(-1, 3)
        side = numpy_to_vtk((xyz[cells].mean(axis=1)[:, 0] > 0).astype(np.int32))
        side.SetName("Side")
        reader.GetOutput().GetCellData().AddArray(side)
        f.SetInputData(reader.GetOutput())
        self.assertEqual((f.GetNumberOfVertices(), f.GetImportance(), f.GetIterations()), (10000, 0, 25))
        for count in (3000, 1234):
            f.SetNumberOfVertices(count)
            f.Update()
            out = f.GetOutput()
            self.assertEqual(out.GetNumberOfPoints(), count)
            # The interpolated height is the height of the new vertices (linear data, barycentric interpolation).
            z = vtk_to_numpy(out.GetPoints().GetData())[:, 2]
            np.testing.assert_allclose(vtk_to_numpy(out.GetPointData().GetArray("Height")), z, atol=1e-9)
            self.assertGreater(out.GetFieldData().GetArray("RemeshMeanMinimumAngle").GetValue(0), 49.0)
            centres = vtk_to_numpy(out.GetPoints().GetData())[
                vtk_to_numpy(out.GetPolys().GetConnectivityArray()).reshape(-1, 3)].mean(axis=1)[:, 0]
            labels = vtk_to_numpy(out.GetCellData().GetArray("Side"))
            clear = np.abs(centres) > 0.02 * np.ptp(xyz[:, 0])  # (the cells beside x = 0: either side)
            np.testing.assert_array_equal(labels[clear], (centres[clear] > 0).astype(np.int32))
        self.assertEqual(f.GetAtlasBuilds(), 1)  # only the sampling changed
        # The kept atlas, control-map rasters and chart locators give a fresh filter's remesh.
        fresh = vtkSurfaceRemeshing()
        fresh.SetInputData(reader.GetOutput())
        fresh.SetNumberOfVertices(1234)
        fresh.Update()
        np.testing.assert_array_equal(vtk_to_numpy(fresh.GetOutput().GetPoints().GetData()),
                                      vtk_to_numpy(f.GetOutput().GetPoints().GetData()))
        # Moved points: the kept surface and atlas are built again from them.
        xyz = vtk_to_numpy(reader.GetOutput().GetPoints().GetData())
        xyz *= 2.0
        reader.GetOutput().GetPoints().Modified()
        f.Update()
        self.assertEqual(f.GetAtlasBuilds(), 2)
        self.assertAlmostEqual(f.GetOutput().GetBounds()[5], reader.GetOutput().GetBounds()[5], delta=1e-3)
        control = f.GetOutputDataObject(1).GetBlock(0)
        halftone = vtk_to_numpy(control.GetPointData().GetArray("Halftone"))
        kinds = vtk_to_numpy(f.GetOutput().GetPointData().GetArray("SampleKind"))
        self.assertEqual(int(halftone.sum()), int((kinds == 0).sum()))

    def test_curvature_importance_concentrates_the_vertices(self):
        _, f = self.remesher("bunny00.off")
        f.SetNumberOfVertices(3000)
        f.SetImportance(vtkSurfaceRemeshing.MEAN_CURVATURE)
        f.Update()
        self.assertEqual(f.GetOutput().GetNumberOfPoints(), 3000)
        variation = f.GetOutput().GetFieldData().GetArray("RemeshEdgeLengthVariation").GetValue(0)
        f.SetImportance(vtkSurfaceRemeshing.UNIFORM)
        f.Update()
        uniform = f.GetOutput().GetFieldData().GetArray("RemeshEdgeLengthVariation").GetValue(0)
        self.assertGreater(variation, 2 * uniform)

    def test_curvature_importance_grows_the_triangles_gradually(self):
        # A curvature's importance jumps at creases (fandisk's mean
        # curvature, sharp edges kept): its spacing graded to grow by at
        # most a fifth of the distance by default, the triangles grow away
        # from them gradually.  As given, 42% of the triangles were below 30
        # degrees (the smallest 3.5) and 22% of the vertices of valence 6;
        # graded 2.4%, 19.4 and 65%.
        import inputs
        fandisk = inputs.read_off(os.path.join(DATA, "fandisk.off"))
        out, _ = self.remeshed(fandisk, 2000, features=True, Importance=vtkSurfaceRemeshing.MEAN_CURVATURE)
        field = out.GetFieldData()
        self.assertEqual(out.GetNumberOfPoints(), 2000)
        self.assertLessEqual(field.GetArray("RemeshFractionBelow30").GetValue(0), 0.05)
        self.assertGreaterEqual(field.GetArray("RemeshMinimumAngle").GetValue(0), 15.0)
        self.assertGreaterEqual(field.GetArray("RemeshFractionValence6").GetValue(0), 0.6)

    def test_a_crease_that_fades_out_is_followed(self):
        # fandisk has a crease whose bend falls from 65 degrees to 30 over
        # eight edges: with the sharp edges above 60 degrees only, its line
        # stopped after the first and the remesh at 10,000 vertices cut the
        # rest, its triangles 0.188% of the diagonal from the input (CGAL's
        # 0.154%).  Continued where it fades, to 30 degrees: 0.095%.
        import inputs
        fandisk = inputs.read_off(os.path.join(DATA, "fandisk.off"))
        out, _ = self.remeshed(fandisk, 10000, features=True)
        to_input, from_input = (out.GetFieldData().GetArray("RemeshDeviation").GetValue(k) for k in (0, 1))
        self.assertLessEqual(to_input, 0.0013)
        self.assertLessEqual(from_input, 0.00165)  # (CGAL's two-sided 0.165%)
        self.assert_topology_kept(fandisk, out)

    def test_transfer_function_and_gradation(self):
        # A flat transfer function makes every importance 1: the uniform
        # remesh, point for point.  A steep one adapts (its spacing graded
        # to grow by at most a fifth of the distance, as by default: its
        # edge lengths vary 1.94 times as much as the uniform remesh's), and
        # a gradation much wider than the bunny evens its importance out
        # again.
        _, f = self.remesher("bunny00.off")
        f.SetNumberOfVertices(2000)
        f.Update()
        uniform = vtk_to_numpy(f.GetOutput().GetPoints().GetData()).copy()

        def variation():
            f.Update()
            self.assertEqual(f.GetOutput().GetNumberOfPoints(), 2000)
            return f.GetOutput().GetFieldData().GetArray("RemeshEdgeLengthVariation").GetValue(0)
        flat = variation()
        f.SetImportance(vtkSurfaceRemeshing.MEAN_CURVATURE)
        f.AddTransferFunctionPoint(0.0, 1.0)
        f.AddTransferFunctionPoint(10.0, 1.0)
        self.assertEqual(f.GetNumberOfTransferFunctionPoints(), 2)
        f.Update()
        np.testing.assert_allclose(vtk_to_numpy(f.GetOutput().GetPoints().GetData()), uniform, atol=1e-12)
        f.RemoveAllTransferFunctionPoints()
        f.AddTransferFunctionPoint(3.0, 6.0)  # unsorted on purpose
        f.AddTransferFunctionPoint(0.0, 0.2)
        adapted = variation()
        f.SetGradation(10.0)
        graded = variation()
        self.assertGreater(adapted, 1.5 * flat)
        self.assertLess(graded, 1.2 * flat)
        self.assertEqual(f.GetAtlasBuilds(), 1)  # only the sampling changed

    def test_surface_sag_raises_the_density_where_the_surface_bends(self):
        # The bunny at 2000 vertices is curved tighter than their spacing in
        # many places: MaximumSurfaceSag (default 0.1) puts more vertices
        # there, so the edges vary more than in the plain uniform remesh.
        _, f = self.remesher("bunny00.off")
        self.assertEqual((f.GetMaximumSurfaceSag(), f.GetMaximumLineSag()), (0.1, 0.05))
        f.SetNumberOfVertices(2000)

        def variation():
            f.Update()
            self.assertEqual(f.GetOutput().GetNumberOfPoints(), 2000)
            return f.GetOutput().GetFieldData().GetArray("RemeshEdgeLengthVariation").GetValue(0)
        raised = variation()
        f.SetMaximumSurfaceSag(0.0)
        plain = variation()
        self.assertGreater(raised, 1.15 * plain)
        self.assertLess(raised, 0.15)
        self.assertEqual(f.GetAtlasBuilds(), 1)

    def test_a_scan_with_small_holes_remeshes_at_every_count(self):
        # bunny00 with 60 small holes punched into it (jagged rims, most
        # smaller than the spacing): where two rims or a rim and a seam run
        # closer than the chords between their samples depart from them,
        # the chords crossed in the chart's plane and the remesh failed
        # ("two boundary segments cross": at 2000 vertices here, without
        # the samples that SeparateCrossingChords adds).  Every count keeps
        # the holes.
        import inputs
        scan = inputs.read_off(os.path.join(DATA, "bunny00.off"))
        points, triangles = inputs.punched(*inputs.arrays_of(scan))
        before = inputs.topology(points, triangles)
        self.assertGreater(before["loops"], 40)
        f = vtkSurfaceRemeshing()
        f.SetInputData(inputs.polydata(points, triangles))
        for count in (2000, 3000, 5000):
            f.SetNumberOfVertices(count)
            log = vtkStringOutputWindow()
            vtkOutputWindow.SetInstance(log)
            self.assertEqual(f.GetExecutive().Update(), 1, log.GetOutput())
            out = inputs.arrays_of(f.GetOutput())
            self.assertEqual(len(out[0]), count)
            after = inputs.topology(*out)
            self.assertEqual((after["euler"], after["loops"], after["components"]),
                             (before["euler"], before["loops"], before["components"]), count)
            self.assertTrue(after["manifold"] and after["oriented"], count)

    def test_a_noisy_scan_is_laid_out_on_a_smoothed_copy(self):
        # bunny00 with noise of 0.3% of its diagonal along its normals (as
        # large as its edges, 11.7% of its edges folded): its own charts'
        # boundaries need more samples than the count at 2,000; at 10,000
        # they remesh, poorly (1.7% of the diagonal from the input, 8.7% of
        # the triangles below 30 degrees: measured).  Folded that much, the
        # remesh is laid out on a smoothed copy first (not after its own
        # charts: 3.3 s -> 0.6 s at 10,000), with a warning, and lies on
        # the noisy input.
        # With isotropic noise of 0.6% (the triangles folded in their
        # planes) the first smoothed copy's charts do not join at 2,000
        # vertices, a copy smoothed more does; moved onto the input, its
        # triangles are shaped there (CGAL on the same input: 12% below 30
        # degrees, the smallest 0.5; ours 0.8% and 20 degrees, 12% and 1.3
        # without the shaping on the input).
        import inputs
        from beltrami.pipelines import noisy_along_normals, noisy_isotropic
        scan = inputs.read_off(os.path.join(DATA, "bunny00.off"))
        points, triangles = inputs.arrays_of(scan)
        diagonal = inputs.diagonal(points)
        along = noisy_along_normals(inputs.polydata(points, triangles), 0.003 * diagonal, seed=1)
        isotropic = noisy_isotropic(inputs.polydata(points, triangles), 0.006 * diagonal, seed=1)
        for noisy, count, smallest, below30 in ((along, 2000, 15.0, 0.005), (along, 10000, 15.0, 0.005),
                                                (isotropic, 2000, 10.0, 0.02)):
            out, said = self.remeshed(noisy, count)
            self.assertIn("laid out on a smoothed copy of the input", said)
            self.assertIn("noise larger than its edges", said)
            self.assertEqual(out.GetNumberOfPoints(), count)
            p = vtk_to_numpy(out.GetPoints().GetData())
            self.assertLess(inputs.distances_to(noisy, p).max(), 1e-12 * diagonal)
            after = inputs.topology(*inputs.arrays_of(out))
            self.assertEqual((after["euler"], after["components"], after["loops"]), (2, 1, 0))
            self.assertGreater(out.GetFieldData().GetArray("RemeshMinimumAngle").GetValue(0), smallest, count)
            self.assertLess(out.GetFieldData().GetArray("RemeshFractionBelow30").GetValue(0), below30, count)

    def test_a_noisy_scan_remeshed_as_finely_as_it_is_says_to_smooth_it(self):
        # bunny00 with noise of 0.3% of its diagonal along its normals
        # (11.7% of its edges folded) at its own vertex count leaves noise
        # spikes 1.2 spacings from the remesh (measured), and 1.47, 1.09 and
        # 1.72 spacings at 2, 4 and 8 times the count: the warning says to
        # smooth it first rather than remesh those counts (32 s) to say that
        # none of them keeps it.
        import inputs
        from beltrami.pipelines import noisy_along_normals
        points, triangles = inputs.arrays_of(inputs.read_off(os.path.join(DATA, "bunny00.off")))
        noisy = noisy_along_normals(inputs.polydata(points, triangles), 0.003 * inputs.diagonal(points), seed=1)
        out, said = self.remeshed(noisy, noisy.GetNumberOfPoints())
        self.assertEqual(out.GetNumberOfPoints(), noisy.GetNumberOfPoints())
        self.assertIn("farther from it than its spacing", said)
        self.assertIn("its far points are its noise", said)
        self.assertNotIn("keeps every part of the input", said)

    def test_a_triangle_without_room_is_reported(self):
        # A plate thinner than the spacing with its sharp edges kept: every
        # triangle on its rim has an angle of at most about atan(thickness /
        # spacing along the rim) (0.68 degrees at 500 vertices, 2.0-2.9 at
        # 5,000-10,000; 0.93-1.17 at 1,000-2,000, where CPUs' rounding
        # moves it across 1); the filter says so where the smallest angle is
        # below 1 degree, and only there.
        import inputs
        plate = inputs.polydata(*inputs.hard_shapes()["thin-plate"])
        warned = []
        for count in (500, 10000):
            out, said = self.remeshed(plate, count, features=True)
            smallest = out.GetFieldData().GetArray("RemeshMinimumAngle").GetValue(0)
            print("thin plate at %d: smallest angle %.3g degrees" % (count, smallest))
            self.assertEqual("leave no room for a rounder one" in said, smallest < 1.0, said)
            warned.append(smallest < 1.0)
        self.assertEqual(warned, [True, False])

    def test_needles_tips_have_room(self):
        # A seam that runs up a needle and down again would leave a flat fin
        # (triangles of 0 degrees at the spiky sphere's and the comb's tips
        # at 2,000 vertices, 3 at 10,000); each narrow fan at the tip gets a
        # sample (measured: spiky 13.0 and 12.9 degrees, comb 5.9 and 5.9).
        import inputs
        shapes = inputs.hard_shapes()
        for name in ("spiky-sphere", "comb"):
            data = inputs.polydata(*shapes[name])
            for count in (2000, 10000):
                out, said = self.remeshed(data, count)
                smallest = out.GetFieldData().GetArray("RemeshMinimumAngle").GetValue(0)
                print("%s at %d: smallest angle %.3g degrees" % (name, count, smallest))
                self.assertEqual(out.GetNumberOfPoints(), count)
                self.assertGreater(smallest, 5.0)
                self.assertNotIn("leave no room", said)

    def test_a_long_narrow_ribbon_has_a_small_control_map(self):
        # Its two charts' maps were boxes 250 times longer than wide: packed
        # into the atlas's square, they left it nearly empty, and the control
        # map at 10,000 vertices took 5159^2 texels (2.8 s, 1.1 GB); the
        # atlas splits charts longer than 100 times their width (12 charts,
        # 967^2 texels, 0.35 s, 0.16 GB; smallest angle 27.5 degrees, was
        # 29.9: the cuts across the strip put corners on its rims).
        import inputs
        strip = inputs.polydata(*inputs.ribbon())
        out, said = self.remeshed(strip, 10000)
        self.assertEqual(out.GetNumberOfPoints(), 10000)
        self.assert_topology_kept(strip, out)
        texels = self.last_control_map_dimensions
        print("ribbon at 10,000: control map %dx%d, smallest angle %.3g degrees" % (
            texels[0], texels[1], out.GetFieldData().GetArray("RemeshMinimumAngle").GetValue(0)))
        self.assertLessEqual(texels[0], 4096)
        self.assertGreater(out.GetFieldData().GetArray("RemeshMinimumAngle").GetValue(0), 15.0)
        self.assertLess(max(out.GetFieldData().GetArray("RemeshDeviation").GetValue(k) for k in range(2)), 1e-4)

    def test_a_long_thin_tube_is_cut_along_its_length(self):
        # A knotted tube 90 times longer than its girth: its atlas halved the
        # tube pieces along their length until they were rings a triangle
        # or two wide (about 400 charts of 12,000 triangles), whose
        # boundaries took 2,052 samples, more than the 2,000 vertices asked
        # for; cut along the length, 202 charts, and 2,000 vertices remesh
        # it (as CGAL does).
        import inputs
        tube = inputs.polydata(*inputs.knotted_tube())
        out, said = self.remeshed(tube, 2000)
        self.assertEqual(out.GetNumberOfPoints(), 2000)
        self.assert_topology_kept(tube, out)
        charts = out.GetFieldData().GetArray("RemeshCharts").GetValue(0)
        print("knotted tube at 2,000: %d charts" % charts)
        self.assertLess(charts, 300)
        self.assertLess(max(out.GetFieldData().GetArray("RemeshDeviation").GetValue(k) for k in range(2)), 0.01)

    def test_a_lattice_at_a_low_count_has_sparser_seams(self):
        # A lattice of bars of genus 28 (320 charts): at 1,000 vertices its
        # chart boundaries take 1,399 samples at the density's spacing, more
        # than the count (it was an error); its seams sampled three times as
        # sparsely (722 samples) it remeshes, with a warning, every handle
        # kept (measured: 2.4% / 3.9% of the diagonal both ways, CGAL 2.3% /
        # 3.1% with 990 vertices; smallest angle 8.0 degrees).
        import inputs
        lattice = inputs.polydata(*inputs.lattice())
        self.assertEqual(inputs.topology(*inputs.arrays_of(lattice))["euler"], -54)
        out, said = self.remeshed(lattice, 1000)
        self.assertIn("sampled 3 times as sparsely", said)
        self.assertEqual(out.GetNumberOfPoints(), 1000)
        self.assert_topology_kept(lattice, out)
        self.assertLess(max(out.GetFieldData().GetArray("RemeshDeviation").GetValue(k) for k in range(2)), 0.05)
        self.assertGreater(out.GetFieldData().GetArray("RemeshMinimumAngle").GetValue(0), 5.0)

    def test_a_triangle_below_a_degree_is_said_in_both_modes(self):
        # A sphere with 100 needles one input vertex wide, at 2,000 vertices:
        # its own chart boundaries take 2,242 samples.  The isotropic remesh
        # is laid out on them with sparser seams: a smoothed copy's remesh
        # had no angle below 5 degrees but rounded the needles off (2.1% of
        # the diagonal from the input; its own charts 1.74%, at the midpoint
        # of a needle's side, 1.2% at the input's vertices alone; CGAL
        # 1.08%).
        # The anisotropic one had five triangles of 0 degrees (three seam
        # samples in a line along a needle's ridge from its tip, which no
        # move or swap could mend), unsaid.  Either mode says an angle below
        # a degree (RemeshMinimumAngle, in space).
        import inputs
        hairy = inputs.polydata(*inputs.hairy_sphere())
        for anisotropy in (0, 1):
            out, said = self.remeshed(hairy, 2000, Anisotropy=anisotropy)
            smallest = out.GetFieldData().GetArray("RemeshMinimumAngle").GetValue(0)
            self.assertEqual(out.GetNumberOfPoints(), 2000)
            self.assertEqual(smallest < 1.0, "has a triangle with an angle of" in said, (anisotropy, smallest, said))
            if anisotropy == 0:
                self.assertIn("sampled 2 times as sparsely", said)
                self.assertIn("farther from it", said)
                deviation = out.GetFieldData().GetArray("RemeshDeviation")
                self.assertLess(max(deviation.GetValue(k) for k in range(2)), 0.019)
                self.assertGreater(smallest, 1.0)

    def test_bad_requests_are_errors_not_crashes(self):
        _, f = self.remesher()
        f.SetNumberOfVertices(5)  # fewer than the chart boundaries need (sampled sparser, 9)
        log = vtkStringOutputWindow()
        vtkOutputWindow.SetInstance(log)
        failed = f.GetExecutive().Update() == 0
        # The error names a count that keeps the input, which does.
        said = re.search(r"A remesh with (\d+) vertices keeps every part of the input", log.GetOutput())
        self.assertIsNotNone(said, log.GetOutput())
        f.SetNumberOfVertices(int(said.group(1)))
        log = vtkStringOutputWindow()
        vtkOutputWindow.SetInstance(log)
        self.assertEqual(f.GetExecutive().Update(), 1, log.GetOutput())
        self.assertEqual(f.GetOutput().GetNumberOfPoints(), int(said.group(1)))
        self.assertNotIn("farther from it than its spacing", log.GetOutput())
        f.GlobalWarningDisplayOff()
        f.SetNumberOfVertices(1000)
        f.SetImportance(vtkSurfaceRemeshing.POINT_ARRAY)  # no array selected
        failed_array = f.GetExecutive().Update() == 0
        f.GlobalWarningDisplayOn()
        self.assertTrue(failed and failed_array)
        self.assertEqual(f.GetOutput().GetNumberOfPoints(), 0)

    def test_isosurface_specks_name_a_count_that_remeshes(self):
        # An isosurface of a real MRI volume (flying edges): 112 components,
        # most of them specks of a few voxels, 48 boundary loops.  At 1,000
        # vertices the charts' boundaries take more; at 2,000 they leave
        # fewer samples than charts (296 of 430 with none inside: measured).
        # Each error names a count that remeshes, which does, keeping every
        # component and loop.
        import inputs
        surface = inputs.isosurface()
        top = inputs.topology(*inputs.arrays_of(surface))
        self.assertEqual((top["components"], top["loops"]), (112, 48))
        for count, reason in ((1000, "the chart boundaries need"), (2000, "charts one inside")):
            f = vtkSurfaceRemeshing()
            f.SetInputData(surface)
            f.SetNumberOfVertices(count)
            log = vtkStringOutputWindow()
            vtkOutputWindow.SetInstance(log)
            self.assertEqual(f.GetExecutive().Update(), 0)
            self.assertEqual(f.GetOutput().GetNumberOfPoints(), 0)
            self.assertIn(reason, log.GetOutput())
            said = re.search(r"A remesh with (\d+) vertices succeeds", log.GetOutput())
            self.assertIsNotNone(said, log.GetOutput())
            out, _ = self.remeshed(surface, int(said.group(1)))
            self.assertEqual(out.GetNumberOfPoints(), int(said.group(1)))
            self.assert_topology_kept(surface, out)

    def test_missed_deviation_keeps_sharp_edges_or_says_why(self):
        # vtkCylinderSource (256 points, its caps unwelded): its rims are
        # sharp; rounded off, the error-driven remesh takes the most
        # vertices it makes, 64 per input point (16,384), to come within
        # 0.5% of the diagonal (0.40%).  Its sharp edges are then kept (as
        # SplitAtFeatures keeps them), with a warning, and 0.5% is met with
        # 228 vertices (measured).  An icosahedron
        # has no edge sharper than FeatureAngle: its remesh, rounding its
        # edges off, stops at 64 vertices per input vertex (768), 0.60% from
        # it, and the warning says so (it had named MaximumDeviationRounds).
        from vtkmodules.vtkFiltersCore import vtkTriangleFilter
        from vtkmodules.vtkFiltersSources import vtkCylinderSource, vtkPlatonicSolidSource
        cylinder = vtkCylinderSource()
        cylinder.SetResolution(64)
        icosahedron = vtkPlatonicSolidSource()
        icosahedron.SetSolidTypeToIcosahedron()
        for source, features, bound in ((cylinder, False, 0.005), (cylinder, True, 0.005), (icosahedron, False, 0.002)):
            triangles = vtkTriangleFilter()
            triangles.SetInputConnection(source.GetOutputPort())
            triangles.Update()
            f = vtkSurfaceRemeshing()
            f.SetInputData(triangles.GetOutput())
            f.SetNumberOfVertices(0)
            f.SetMaximumDeviation(bound)
            f.SetSplitAtFeatures(features)
            log = vtkStringOutputWindow()
            vtkOutputWindow.SetInstance(log)
            self.assertEqual(f.GetExecutive().Update(), 1)
            deviation = f.GetOutput().GetFieldData().GetArray("RemeshDeviation")
            worst = max(deviation.GetValue(0), deviation.GetValue(1))
            if source is cylinder:
                self.assertLessEqual(worst, bound)
                self.assertLess(f.GetOutput().GetNumberOfPoints(), 1000)
                self.assertEqual("those edges are kept" in log.GetOutput(), not features, log.GetOutput())
            else:
                self.assertGreater(worst, bound)
                self.assertIn("64 vertices per input vertex", log.GetOutput())
                self.assertNotIn("SplitAtFeatures", log.GetOutput())

    @staticmethod
    def wavelet_contour(level):
        """ParaView's Wavelet source over [-20, 20]^3 contoured at `level`."""
        from vtkmodules.vtkFiltersCore import vtkContourFilter
        from vtkmodules.vtkImagingCore import vtkRTAnalyticSource
        wavelet = vtkRTAnalyticSource()
        wavelet.SetWholeExtent(-20, 20, -20, 20, -20, 20)
        contour = vtkContourFilter()
        contour.SetInputConnection(wavelet.GetOutputPort())
        contour.SetValue(0, level)
        contour.Update()
        return contour.GetOutput()

    def test_wavelet_contour_remeshes(self):
        # ParaView's Wavelet source over [-20, 20]^3 contoured at 157 (11
        # components, 34 boundary loops, marching-cubes slivers): a sliver's
        # chart map stretched across it made the band beside its chart
        # boundary cover the whole control map, and 5,000 vertices failed
        # ("the image holds between 0 and 0").  At 10,000 a cone point pinned
        # on a chart boundary took a path sample from beyond another one, the
        # path's samples fell out of order, and the boundary crossed itself
        # ("two boundary segments cross"); 12,000 and 15,000 fell back on a
        # smoothed copy.
        import inputs
        surface = self.wavelet_contour(157.0)
        top = inputs.topology(*inputs.arrays_of(surface))
        self.assertEqual((top["components"], top["loops"]), (11, 34))
        for count in (5000, 10000):
            out, log = self.remeshed(surface, count)
            self.assertEqual(out.GetNumberOfPoints(), count)
            self.assertNotIn("smoothed copy", log)
            self.assert_topology_kept(surface, out)

    def test_blade_tips_beside_a_stretched_triangle_keep_their_samples(self):
        # A turbine disk of 20 twisted blades about a marching-cubes cell
        # thick: the chart of one blade's tip held a sliver that its map
        # stretched a thousandfold, and the band left out of the halftone
        # beside that chart boundary, as wide in the map as that stretch
        # asks, covered the tip behind it, squeezed by the map: one sample
        # inside it where its area asks for 90.  The tip was cut off, 2.4% of
        # the diagonal from the remesh at 10,000 vertices (CGAL's isotropic
        # remeshing: 1.03%, measured once with Testing/Benchmarks/
        # benchmark_remeshing.py's cgal at 9,878 vertices); with the band held
        # within a spacing on the surface, 0.52%.
        import inputs
        surface = inputs.polydata(*inputs.turbine_disk(160, 20))
        out, _ = self.remeshed(surface, 10000)
        self.assertEqual(out.GetNumberOfPoints(), 10000)
        self.assert_topology_kept(surface, out)
        deviation = out.GetFieldData().GetArray("RemeshDeviation")
        self.assertLess(max(deviation.GetValue(0), deviation.GetValue(1)), 0.0103)

    def test_a_vertex_on_a_seam_through_a_needle_leaves_its_line(self):
        # Fingers and spikes thinner than the spacing: three samples of a
        # seam running straight along one made a triangle of no area, whose
        # middle vertex could not move towards any neighbour without folding
        # it (the vertex across its long edge was its neighbour already, so
        # no swap either): 0.29 degrees on eight fingers at 3,000 vertices,
        # 0 on eight spikes at 5,000.  It now also tries the moves away from
        # its neighbours: 11.7 and 3.9 degrees measured.
        import inputs
        for shape, count in ((inputs.comb(8, 3.0, 60), 3000), (inputs.spiky_sphere(64, 8, 3.0, 0.05), 5000)):
            surface = inputs.polydata(*shape)
            out, _ = self.remeshed(surface, count)
            self.assertEqual(out.GetNumberOfPoints(), count)
            self.assert_topology_kept(surface, out)
            self.assertGreater(inputs.smallest_angles(*inputs.arrays_of(out)).min(), 2.0)

    def test_corners_of_seams_on_a_rim_slide_off_slivers(self):
        # The Wavelet contoured at 110 (rims where it meets the volume's
        # sides): where two seams reach a rim at nearly one point, their
        # corners lay a fiftieth of a spacing apart, fixed, with triangles of
        # 1-2 degrees beside them.  Such a corner now slides along the rim
        # to where its triangles are roundest (its chords within the line's
        # sag bound).  Triangles below 15 degrees at the rim's corners, at
        # 2,000, 5,000 and 10,000 vertices: 32 + 37 + 30 before, 20 + 27 + 26
        # measured; the topology kept, the remesh as close to the input.
        import inputs
        from vtkmodules.util.numpy_support import vtk_to_numpy
        surface = self.wavelet_contour(110.0)
        slivers = 0
        for count in (2000, 5000, 10000):
            out, _ = self.remeshed(surface, count)
            self.assertEqual(out.GetNumberOfPoints(), count)
            self.assert_topology_kept(surface, out)
            points, triangles = inputs.arrays_of(out)
            edges, counts = inputs.edge_counts(triangles)
            corner = vtk_to_numpy(out.GetPointData().GetArray("SampleKind")) == 2
            corner[np.setdiff1d(np.arange(len(points)), edges[counts == 1].ravel())] = False  # (on the rim)
            smallest = inputs.smallest_angles(points, triangles)
            slivers += int(np.sum((smallest < 15.0) & corner[triangles].any(axis=1)))
            deviation = out.GetFieldData().GetArray("RemeshDeviation")
            farthest = {2000: 0.0635, 5000: 0.0173, 10000: 0.0122}[count]  # (as measured before, and now)
            self.assertLess(max(deviation.GetValue(0), deviation.GetValue(1)), 1.1 * farthest)
        self.assertLessEqual(slivers, 85)

    def test_tips_cut_off_by_one_chord_keep_apart(self):
        # The Wavelet contoured at 180, anisotropic at 2,000 vertices: two
        # pinned tips of one chart lay outside its boundary's chords and were
        # both moved to the centre of the nearest triangle ("1 points
        # coincide with others"), and the remesh failed.
        surface = self.wavelet_contour(180.0)
        out, _ = self.remeshed(surface, 2000, Anisotropy=1)
        self.assertEqual(out.GetNumberOfPoints(), 2000)
        self.assert_topology_kept(surface, out)

    def test_pinched_points_are_split(self):
        # A scan with holes next to each other: the shared cow with 2% of its
        # triangles removed at random has 8 pinched points, where separate
        # fans of triangles meet at one point, and the atlas refused it ("an
        # atlas needs a manifold ... surface").  Each fan now gets its own
        # copy of the point: the remesh has the topology of the split input,
        # exactly, and stays close to it.
        import inputs
        points, triangles = inputs.arrays_of(inputs.read_off(os.path.join(inputs.SHARED_MESHES, "cow.off")))
        keep = np.random.default_rng(1).random(len(triangles)) > 0.02
        holed = inputs.polydata(points, triangles[keep])
        self.assertFalse(inputs.topology(points, triangles[keep])["manifold"])
        out, log = self.remeshed(holed, 10000)
        self.assertEqual(out.GetNumberOfPoints(), 10000)
        self.assertIn("8 points are shared by separate parts of the surface (pinched", log)
        self.assert_topology_kept(holed, out)
        deviation = out.GetFieldData().GetArray("RemeshDeviation")
        self.assertLess(max(deviation.GetValue(0), deviation.GetValue(1)), 0.01)  # (0.30% / 0.58% measured)

    def test_edges_of_three_triangles_are_cut(self):
        # VTK's quadric decimation of the shared cow to a fifth of its
        # triangles folds it along 2 edges, each in three or more triangles:
        # the atlas refused it.  The surface is now cut along them and their
        # ends split, and the remesh has the cut input's topology.
        import inputs
        from vtkmodules.vtkFiltersCore import vtkQuadricDecimation
        decimation = vtkQuadricDecimation()
        decimation.SetInputData(inputs.read_off(os.path.join(inputs.SHARED_MESHES, "cow.off")))
        decimation.SetTargetReduction(0.8)
        decimation.Update()
        points, triangles = inputs.arrays_of(decimation.GetOutput())
        self.assertFalse(inputs.topology(points, triangles)["manifold"])
        out, log = self.remeshed(decimation.GetOutput(), 10000)
        self.assertEqual(out.GetNumberOfPoints(), 10000)
        self.assertIn("at the ends of 2 edges of three or more triangles", log)
        self.assert_topology_kept(decimation.GetOutput(), out)
        deviation = out.GetFieldData().GetArray("RemeshDeviation")
        self.assertLess(max(deviation.GetValue(0), deviation.GetValue(1)), 0.01)  # (0.40% / 0.43% measured)

    def test_a_decimated_scan_within_cgals_deviation(self):
        # bunny00 decimated to a fifth by VTK's quadric decimation, at 2,000
        # vertices: the first remesh leaves a bump of its back 1.82% of the
        # diagonal away; the second, its far vertices pinned, 1.45% with
        # 0.15% of its triangles below 30 degrees (none in the first), was
        # refused for that; within the quality bar it is kept.  CGAL's
        # isotropic remeshing at 1,996 vertices: 1.56% (measured).
        import inputs
        from vtkmodules.vtkFiltersCore import vtkQuadricDecimation
        decimation = vtkQuadricDecimation()
        decimation.SetInputData(inputs.read_off(os.path.join(DATA, "bunny00.off")))
        decimation.SetTargetReduction(0.8)
        decimation.Update()
        out, _ = self.remeshed(decimation.GetOutput(), 2000)
        deviation = out.GetFieldData().GetArray("RemeshDeviation")
        self.assertLess(max(deviation.GetValue(0), deviation.GetValue(1)), 0.0156)
        self.assertGreaterEqual(out.GetFieldData().GetArray("RemeshMinimumAngle").GetValue(0), 15.0)
        self.assertLessEqual(out.GetFieldData().GetArray("RemeshFractionBelow30").GetValue(0), 0.005)

    def test_fidelity_rounds_pin_the_corners_a_remesh_misses(self):
        # The elephant (2,775 vertices) at 10,000: one remesh leaves its feet
        # and trunk 0.514% of the diagonal away; the rounds that pin the
        # input vertices left beyond 0.15 of the spacing bring it to 0.376%
        # (CGAL's isotropic remeshing at about the count: 0.47%), with the
        # same count and triangles within the quality bar.
        import inputs
        surface = inputs.read_off(os.path.join(DATA, "elephant.off"))
        figures = {}
        for rounds in (0, 3):
            out, _ = self.remeshed(surface, 10000, FidelityRounds=rounds)
            self.assertEqual(out.GetNumberOfPoints(), 10000)
            self.assert_topology_kept(surface, out)
            fd = out.GetFieldData()
            figures[rounds] = max(fd.GetArray("RemeshDeviation").GetValue(k) for k in range(2))
            self.assertGreaterEqual(fd.GetArray("RemeshMinimumAngle").GetValue(0), 15.0)
            self.assertLessEqual(fd.GetArray("RemeshFractionBelow30").GetValue(0), 0.005)
        self.assertGreater(figures[0], 0.0047)
        self.assertLess(figures[3], 0.8 * figures[0])
        self.assertLess(figures[3], 0.0047)

    def test_pins_on_a_crease_are_joined_along_it(self):
        # A 12-sided needle with flat ends at 10,000 vertices: the rims of
        # its ends (90-degree creases, 12 input edges 1.6 spacings long) are
        # cut by the remesh's triangles, 0.14% of the diagonal from the
        # input without the fidelity rounds.  The rounds pin vertices on the
        # rims' corners and midpoints and join those on one rim edge by an
        # edge along it: 0.044% (CGAL's isotropic remeshing at the count:
        # 0.078%; pinned without the joins, the triangles still cut the
        # rims: 0.102%).
        import inputs
        import shapes
        needle = inputs.polydata(*shapes.needle())
        figures = {}
        for rounds in (0, 3):
            out, _ = self.remeshed(needle, 10000, FidelityRounds=rounds)
            self.assertEqual(out.GetNumberOfPoints(), 10000)
            self.assert_topology_kept(needle, out)
            figures[rounds] = max(out.GetFieldData().GetArray("RemeshDeviation").GetValue(k) for k in range(2))
            self.assertGreaterEqual(out.GetFieldData().GetArray("RemeshMinimumAngle").GetValue(0), 15.0)
        self.assertGreater(figures[0], 0.0012)
        self.assertLess(figures[3], 0.0006)

    def test_triply_periodic_surface_cut_by_a_box(self):
        # The diamond surface (two periods, a 60^3 grid, contoured at 0.3:
        # genus 54, 12 boundary loops on the box).  Where a chart's map
        # widens towards its boundary (80 times), the band kept free of the
        # halftone beside that boundary reached over the chart and its
        # neighbours in the packing: 31 of 93 charts got no sample inside,
        # and triangles 8 spacings wide bridged them, 2.6% of the diagonal
        # from the input at 10,000 vertices (CGAL 2.1%).
        from vtkmodules.vtkCommonDataModel import vtkImageData
        from vtkmodules.vtkFiltersCore import vtkContourFilter
        n = 60
        x = np.linspace(0.0, 4.0 * np.pi, n)
        X, Y, Z = np.meshgrid(x, x, x, indexing="ij")
        field = (np.sin(X) * np.sin(Y) * np.sin(Z) + np.sin(X) * np.cos(Y) * np.cos(Z) +
                 np.cos(X) * np.sin(Y) * np.cos(Z) + np.cos(X) * np.cos(Y) * np.sin(Z))
        image = vtkImageData()
        image.SetDimensions(n, n, n)
        values = numpy_to_vtk(field.ravel(order="F").copy())
        values.SetName("f")
        image.GetPointData().SetScalars(values)
        contour = vtkContourFilter()
        contour.SetInputData(image)
        contour.SetValue(0, 0.3)
        contour.Update()
        surface = contour.GetOutput()
        out, _ = self.remeshed(surface, 10000)
        self.assert_topology_kept(surface, out)
        deviation = out.GetFieldData().GetArray("RemeshDeviation")
        self.assertLess(max(deviation.GetValue(0), deviation.GetValue(1)), 0.005)

    def test_a_new_count_on_a_kept_filter(self):
        # The filter keeps its atlas and caches over a new count.  The
        # knife-edged washer at 1,668 and then 6,672 vertices: the second
        # count lays the remesh out on another atlas with as many charts,
        # and the charts' locators of the first were used on it (a
        # triangle index past the chart's: the process crashed).
        import inputs
        washer = inputs.polydata(*inputs.hard_shapes()["knife-edge-washer"])
        f = vtkSurfaceRemeshing()
        f.SetInputData(washer)
        vtkOutputWindow.SetInstance(vtkStringOutputWindow())  # (its warnings are the layouts')
        for count in (1668, 6672):
            f.SetNumberOfVertices(count)
            f.Update()
            self.assertEqual(f.GetOutput().GetNumberOfPoints(), count)
            self.assert_topology_kept(washer, f.GetOutput())

    def test_error_driven_mode_takes_few_vertices(self):
        # The error-driven mode with nothing else set starts from the
        # density the curvature needs (where it exceeds twice its mean) and
        # moves remesh vertices onto the input's far ones in each remesh.
        # Measured: the bunny within 0.2% of its diagonal 7,532-8,294 vertices,
        # the elephant 16,845-19,199 (the rounds' path turns on the last
        # digits of a deviation; its input has 2,775: at that scale a
        # polyhedron whose edges the remesh's triangles cut, and a cut
        # falls only as fast as the spacing), three_peaks at 0.5% 2,051
        # and patch-01 at 0.5% 282.  (Measured at the input's vertices and
        # the remesh's triangle centres alone, before the edge midpoints
        # were: 6,026, 10,096, 1,864 and 282; then from a uniform start
        # without the moves 10,111, 15,278, 3,094 and 7,651.)  patch-01 with
        # its sharp edges kept, with a warning: rounded off, it took 2,229
        # vertices, more than its input's; the elephant and three_peaks
        # either way, a few hundred vertices apart (the elephant kept 16,845
        # where rounded off took 17,753; three_peaks 2,051 and 2,296).
        import inputs
        for name, bound, most in (("bunny00.off", 0.002, 9500), ("elephant.off", 0.002, 21000),
                                  ("three_peaks.off", 0.005, 2400), ("patch-01.off", 0.005, 500)):
            surface = inputs.read_off(os.path.join(DATA, name))
            out, log = self.remeshed(surface, 0, MaximumDeviation=bound)
            deviation = out.GetFieldData().GetArray("RemeshDeviation")
            self.assertLessEqual(max(deviation.GetValue(0), deviation.GetValue(1)), bound, name)
            self.assertLessEqual(out.GetNumberOfPoints(), most, name)
            if name in ("bunny00.off", "patch-01.off"):  # (the others either way: a few hundred vertices apart)
                self.assertEqual("those edges are kept" in log, name == "patch-01.off", (name, log))
            self.assert_topology_kept(surface, out)

    def test_isosurface_within_a_deviation(self):
        # The isosurface's largest component (681 points, 5 boundary loops):
        # where its level passes a grid point, five vertices lie within
        # 0.008 of it, and the error-driven mode pinned two of them at once
        # (far from the remesh), one place in their chart's map: from
        # 14,000 vertices on every remesh failed, and the last one, laid out
        # on a smoothed copy, stayed 0.87% from the input (measured).
        import inputs
        surface = inputs.isosurface(largest=True)
        f = vtkSurfaceRemeshing()
        f.SetInputData(surface)
        f.SetNumberOfVertices(0)
        f.SetMaximumDeviation(0.005)
        log = vtkStringOutputWindow()
        vtkOutputWindow.SetInstance(log)
        self.assertEqual(f.GetExecutive().Update(), 1, log.GetOutput())
        self.assertNotIn("smoothed copy", log.GetOutput())
        deviation = f.GetOutput().GetFieldData().GetArray("RemeshDeviation")
        self.assertLessEqual(max(deviation.GetValue(0), deviation.GetValue(1)), 0.005)
        self.assert_topology_kept(surface, f.GetOutput())

    def test_seams_round_thin_charts_and_specks_keep_their_side(self):
        # The isosurface at a fifth of the range, anisotropic.  Its largest
        # component (genus 23, 16 boundary loops) at 2,000 vertices: a
        # chart of three triangles had a seam with no sample between its
        # corners that bent round the chart's other corners; its chord
        # passed on their far side, the chart's polygon of chords turned
        # inside out and its triangles faced the other way ("4 edges with
        # inconsistent orientation"): a chord whose stretch of path holds
        # another boundary sample gets a sample on it.  All of its 181
        # components at 5,500: a speck of eight triangles whose seam loop
        # had two of its samples moved onto the speck's tips (the chord
        # check then runs again, an interior sample taking the new place),
        # and a chart's diagonal cutting off a thin corner between the two
        # ends of its neighbour's rim chord (three triangles on one edge:
        # the diagonal is flipped).
        import inputs
        for surface, count in ((inputs.isosurface(largest=True, level=0.2), 2000),
                               (inputs.isosurface(level=0.2), 5500)):
            out, _ = self.remeshed(surface, count, Anisotropy=vtkSurfaceRemeshing.PRINCIPAL_CURVATURES)
            self.assertEqual(out.GetNumberOfPoints(), count)
            self.assert_topology_kept(surface, out)

    def test_error_driven_anisotropic_remesh_keeps_its_creases(self):
        # fandisk within 0.1% of its diagonal, anisotropic, sharp edges kept
        # (the demo's picture): a vertex of the remesh lying on the chord
        # between two samples of a crease took the crease's edge by a swap
        # (the degenerate triangle removed), but then relaxed off the line,
        # and the two faces beside it were joined by an edge across the
        # crease, 0.15% of the diagonal off the input at every count: the
        # error-driven mode went on to 206,425 vertices and missed the bound.
        # Such a vertex now stays on the line: 4,037 vertices, 0.083% /
        # 0.098% measured.
        import inputs
        fandisk = inputs.read_off(os.path.join(DATA, "fandisk.off"))
        out, _ = self.remeshed(fandisk, 0, features=True, MaximumDeviation=0.001,
                               Anisotropy=vtkSurfaceRemeshing.PRINCIPAL_CURVATURES)
        deviation = out.GetFieldData().GetArray("RemeshDeviation")
        self.assertLessEqual(max(deviation.GetValue(0), deviation.GetValue(1)), 0.001)
        self.assertLess(out.GetNumberOfPoints(), 6000)
        self.assert_topology_kept(fandisk, out)

    def test_anisotropic_mode_from_the_curvature_and_from_a_tensor_array(self):
        # An ellipsoid (semi-axes 1, 1, 3): the remesh's edges of unit
        # length and its triangles near equilateral in the metric (its
        # figures and the metric per point in the output), and closer to
        # the ellipsoid than the isotropic remesh of the same count.
        import inputs
        p, t = inputs.sphere(48)
        ellipsoid = inputs.polydata(p * np.array([1.0, 1.0, 3.0]), t)
        f = vtkSurfaceRemeshing()
        f.SetInputData(ellipsoid)
        f.SetNumberOfVertices(2000)
        self.assertEqual((f.GetAnisotropy(), f.GetMaximumAnisotropy()), (vtkSurfaceRemeshing.ISOTROPIC, 6.0))
        f.Update()
        isotropic = max(f.GetOutput().GetFieldData().GetArray("RemeshDeviation").GetValue(k) for k in range(2))
        f.SetAnisotropy(vtkSurfaceRemeshing.PRINCIPAL_CURVATURES)
        f.Update()
        out = f.GetOutput()
        self.assertEqual(out.GetNumberOfPoints(), 2000)
        figures = out.GetFieldData().GetArray("RemeshMetricQuality")
        median, within, _, mean_smallest, _ = (figures.GetValue(k) for k in range(5))
        self.assertAlmostEqual(median, 1.0, delta=0.1)
        self.assertGreater(within, 0.85)
        self.assertGreater(mean_smallest, 48.0)
        self.assertEqual(out.GetPointData().GetArray("Metric").GetNumberOfComponents(), 6)
        deviation = max(out.GetFieldData().GetArray("RemeshDeviation").GetValue(k) for k in range(2))
        self.assertLess(deviation, 0.7 * isotropic)
        # Another count re-runs the sampling only (the atlas and the metric
        # kept): the remesh of a fresh filter.
        f.SetNumberOfVertices(1500)
        f.Update()
        self.assertEqual(f.GetAtlasBuilds(), 1)
        fresh = vtkSurfaceRemeshing()
        fresh.SetInputData(ellipsoid)
        fresh.SetNumberOfVertices(1500)
        fresh.SetAnisotropy(vtkSurfaceRemeshing.PRINCIPAL_CURVATURES)
        fresh.Update()
        np.testing.assert_array_equal(vtk_to_numpy(fresh.GetOutput().GetPoints().GetData()),
                                      vtk_to_numpy(f.GetOutput().GetPoints().GetData()))
        # A square with a constant tensor of 1 along x and 1/16 along y:
        # edges four times longer along y (the root-mean-square of their
        # y over their x extents), where the isotropic remesh's are even.
        n = 60
        u, v = np.meshgrid(np.linspace(0, 1, n), np.linspace(0, 1, n), indexing="ij")
        grid = np.stack([u.ravel(), v.ravel(), np.zeros(n * n)], axis=1)
        ids = np.arange(n * n).reshape(n, n)
        quads = np.stack([ids[:-1, :-1], ids[1:, :-1], ids[1:, 1:], ids[:-1, 1:]], axis=-1).reshape(-1, 4)
        square = inputs.polydata(grid, np.concatenate([quads[:, [0, 1, 2]], quads[:, [0, 2, 3]]]))
        tensor = numpy_to_vtk(np.tile([1.0, 1.0 / 16.0, 0.0, 0.0, 0.0, 0.0], (n * n, 1)), deep=1)
        tensor.SetName("Wanted")
        square.GetPointData().AddArray(tensor)
        g = vtkSurfaceRemeshing()
        g.SetInputData(square)
        g.SetNumberOfVertices(1500)

        def stretch():
            self.assertEqual(g.GetExecutive().Update(), 1)
            q, tri = inputs.arrays_of(g.GetOutput())
            d = np.concatenate([q[tri[:, k]] - q[tri[:, (k + 1) % 3]] for k in range(3)])
            return np.sqrt((d[:, 1] ** 2).sum() / (d[:, 0] ** 2).sum())
        even = stretch()
        g.SetAnisotropy(vtkSurfaceRemeshing.TENSOR_ARRAY)
        g.SetInputArrayToProcess(1, 0, 0, 0, "Wanted")
        self.assertAlmostEqual(stretch(), 4.0, delta=0.6)
        self.assertAlmostEqual(even, 1.0, delta=0.15)
        # Without a tensor array, or with one not positive in the tangent
        # plane: an error and an empty output.
        for name, values in (("", None), ("Flat", [0.0, 0.0, 1.0, 0.0, 0.0, 0.0])):
            if values is not None:
                bad = numpy_to_vtk(np.tile(values, (n * n, 1)), deep=1)
                bad.SetName(name)
                square.GetPointData().AddArray(bad)
            g.SetInputArrayToProcess(1, 0, 0, 0, name)
            log = vtkStringOutputWindow()
            vtkOutputWindow.SetInstance(log)
            self.assertEqual(g.GetExecutive().Update(), 0, name)
            self.assertIn("TENSOR_ARRAY", log.GetOutput())
            self.assertEqual(g.GetOutput().GetNumberOfPoints(), 0)

    def test_bad_input_is_an_error_or_a_warning_with_an_empty_output(self):
        # Non-orientable and NaN input: a clear error; empty and lines-only
        # input: a warning; in every case an empty remesh, never a crash.  A
        # third triangle on an edge: the surface is cut there, with a warning.
        import inputs
        reader, _ = self.remesher()
        reader.Update()
        mushroom = reader.GetOutput()
        non_manifold = vtkPolyData()
        non_manifold.DeepCopy(mushroom)
        a, b = mushroom.GetCell(0).GetPointId(0), mushroom.GetCell(0).GetPointId(1)
        tip = non_manifold.GetPoints().InsertNextPoint(*(np.array(mushroom.GetPoint(a)) + [0.0, 0.0, 0.3]))
        non_manifold.GetPolys().InsertNextCell(3, [a, b, tip])  # a third triangle on an edge
        with_nan = vtkPolyData()
        with_nan.DeepCopy(mushroom)
        with_nan.GetPoints().SetPoint(5, float("nan"), 0.0, 0.0)
        lines = vtkPolyData()
        lines.SetPoints(vtkPoints())
        lines.GetPoints().InsertNextPoint(0.0, 0.0, 0.0)
        lines.GetPoints().InsertNextPoint(1.0, 0.0, 0.0)
        lines.SetLines(vtkCellArray())
        lines.GetLines().InsertNextCell(2, [0, 1])
        out, log = self.remeshed(non_manifold, 2000)
        self.assertEqual(out.GetNumberOfPoints(), 2000)
        self.assertIn("at the ends of 1 edge of three or more triangles", log)
        self.assertTrue(inputs.topology(*inputs.arrays_of(out))["manifold"])
        for data, succeeds, message in ((inputs.hostile_surfaces()["mobius"], False, "consistently oriented surface"),
                                        (with_nan, False, "NaN or infinite point coordinates"),
                                        (vtkPolyData(), True, "Input has no points"),
                                        (lines, True, "no polygons or triangle strips")):
            log = vtkStringOutputWindow()
            vtkOutputWindow.SetInstance(log)
            f = vtkSurfaceRemeshing()
            f.SetInputData(data)
            f.SetNumberOfVertices(2000)
            self.assertEqual(f.GetExecutive().Update() == 1, succeeds, message)
            self.assertIn(message, log.GetOutput())
            self.assertEqual(f.GetOutput().GetNumberOfPoints(), 0, message)


if __name__ == "__main__":
    unittest.main()
