"""Line drawings for print: vtkSurfaceLineDrawing's Visibility against
analytic occlusion (a sphere in front of a folded plane, orthographic and
perspective; a torus seen at a grazing angle, against rays cast through the
implicit torus), apparent ridges against their closed form (an extruded
profile seen from three directions), a raw scan's long lines at the
defaults, curvatures and lines of a sphere at 1e+-100 and 1e+-150, and
vtkLineDrawingWriter's SVG and PDF."""
import math
import os
import re
import subprocess
import sys
import tempfile
import unittest
import xml.etree.ElementTree as ElementTree

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import inputs  # noqa: E402
from beltrami import vtkLineDrawingWriter, vtkSurfaceLineDrawing  # noqa: E402

CONTOUR, CREASE = vtkSurfaceLineDrawing.CONTOUR, vtkSurfaceLineDrawing.CREASE


def draw(mesh, **settings):
    settings.setdefault("SuggestiveContours", False)
    d = inputs.filter_with(vtkSurfaceLineDrawing, **settings)()
    d.SetInputData(mesh)
    d.Update()
    return d.GetOutput()


def polylines(out):
    """[(type, hidden, points (k x 3))] of a drawing's lines."""
    points = vtk_to_numpy(out.GetPoints().GetData()) if out.GetNumberOfPoints() else np.zeros((0, 3))
    types = vtk_to_numpy(out.GetCellData().GetArray("LineType"))
    hidden_array = out.GetCellData().GetArray("Hidden")
    hidden = vtk_to_numpy(hidden_array) if hidden_array else np.zeros(len(types), np.uint8)
    lines = out.GetLines()
    offsets, ids = vtk_to_numpy(lines.GetOffsetsArray()), vtk_to_numpy(lines.GetConnectivityArray())
    return [(int(types[c]), int(hidden[c]), points[ids[offsets[c]:offsets[c + 1]]]) for c in range(len(types))]


def sphere_before_roof(resolution=100):
    """A unit sphere at the origin before a plane folded along x = 0 at
    z = -2 (slopes 0.6: a 62-degree crease), 6 x 6."""
    ball = inputs.sphere(resolution)
    n = 61
    xs = np.linspace(-3.0, 3.0, n)
    X, Y = np.meshgrid(xs, xs, indexing="ij")
    roof = np.stack([X, Y, -2.0 - 0.6 * np.abs(X)], -1).reshape(-1, 3)
    at = lambda i, j: i * n + j  # noqa: E731
    tris = []
    for i in range(n - 1):
        for j in range(n - 1):
            tris += [(at(i, j), at(i + 1, j), at(i + 1, j + 1)), (at(i, j), at(i + 1, j + 1), at(i, j + 1))]
    return inputs.polydata(*inputs.merge(ball, (roof, np.array(tris))))


class Visibility(unittest.TestCase):
    def crease_parts(self, out):
        return [(h, p) for t, h, p in polylines(out) if t == CREASE]

    def check_roof(self, hidden_below, **camera):
        """The crease (x = 0, z = -2) is hidden where |y| < hidden_below."""
        mesh = sphere_before_roof()
        out = draw(mesh, Visibility=vtkSurfaceLineDrawing.VISIBLE_AND_HIDDEN_LINES, **camera)
        parts = sorted(self.crease_parts(out), key=lambda hp: hp[1][:, 1].min())
        self.assertEqual([h for h, _ in parts], [0, 1, 0])
        view = 6.0  # the drawing's extent
        for (h, p), (lo, hi) in zip(parts, [(-3, -hidden_below), (-hidden_below, hidden_below), (hidden_below, 3)]):
            self.assertLess(abs(p[:, 1].min() - lo), 0.005 * view, (h, p[:, 1].min(), lo))
            self.assertLess(abs(p[:, 1].max() - hi), 0.005 * view, (h, p[:, 1].max(), hi))
        # The sphere's contour and the roof's boundary are seen whole, closed.
        for t, h, p in polylines(out):
            if t != CREASE:
                self.assertEqual(h, 0)
                self.assertTrue(np.allclose(p[0], p[-1]))
        # Visible lines only: the hidden part is gone, the rest the same.
        seen = draw(mesh, Visibility=vtkSurfaceLineDrawing.VISIBLE_LINES, **camera)
        self.assertEqual(len(polylines(seen)), len(polylines(out)) - 1)
        self.assertEqual([h for _, h, _ in polylines(seen)], [0] * len(polylines(seen)))
        # All lines (the default): the crease whole, no Hidden array.
        whole = draw(mesh, **camera)
        self.assertIsNone(whole.GetCellData().GetArray("Hidden"))
        self.assertEqual(len(self.crease_parts(whole)), 1)

    def test_sphere_hides_crease_orthographic(self):
        self.check_roof(1.0, ParallelProjection=True, ViewDirection=(0, 0, -1))

    def test_sphere_hides_crease_perspective(self):
        # From (0, 0, 5) the ray to (0, y, -2) passes the origin at 5|y| / sqrt(y^2 + 49).
        self.check_roof(math.sqrt(49.0 / 24.0), CameraPosition=(0, 0, 5))

    def test_torus_at_grazing_angle(self):
        major, minor, n = 1.0, 0.35, 200
        mesh = inputs.polydata(*inputs.torus(n, n // 2, major, minor))
        eye = np.array([0.0, -4.0, 0.9])  # 13 degrees above the torus' plane
        out = draw(mesh, CameraPosition=eye, ViewDirection=-eye,
                   Visibility=vtkSurfaceLineDrawing.VISIBLE_AND_HIDDEN_LINES)
        lines = polylines(out)
        self.assertGreater(sum(h for _, h, _ in lines), 0)
        self.assertGreater(sum(1 - h for _, h, _ in lines), 0)

        def inside(x):
            return (np.hypot(x[..., 0], x[..., 1]) - major) ** 2 + x[..., 2] ** 2 < minor ** 2

        def truth(p):
            """Hidden: the ray from p (projected onto the torus) to the eye
            runs inside the solid torus somewhere past three edge lengths."""
            rho = np.hypot(p[:, 0], p[:, 1])
            c = np.stack([major * p[:, 0] / rho, major * p[:, 1] / rho, 0 * rho], -1)
            q = c + minor * (p - c) / np.linalg.norm(p - c, axis=1)[:, None]
            d = eye - q
            length = np.linalg.norm(d, axis=1)
            d /= length[:, None]
            t = np.arange(3 * 2 * math.pi * major / n, 6.0, 0.002)
            x = q[:, None, :] + t[None, :, None] * d[:, None, :]
            return (inside(x) & (t[None, :] < length[:, None])).any(1)

        forward = -eye / np.linalg.norm(eye)
        right = np.cross(forward, [0, 0, 1])
        right /= np.linalg.norm(right)
        up = np.cross(right, forward)

        def image(p):
            v = p - eye
            z = v @ forward
            return np.stack([v @ right / z, v @ up / z], -1)
        allpoints = np.vstack([p for _, _, p in lines])
        size = np.ptp(image(allpoints), 0).max()
        flips, wrong = [], []
        for _, h, p in lines:
            hidden = truth(p)
            img = image(p)
            k = np.nonzero(hidden[1:] != hidden[:-1])[0]
            flips += list(0.5 * (img[k] + img[k + 1]))
            wrong += list(img[hidden != bool(h)])
        self.assertGreater(len(flips), 0)
        flips = np.array(flips)
        worst = max((np.min(np.linalg.norm(flips - w, axis=1)) for w in wrong), default=0.0) / size
        print("torus: %d points, %d classified unlike the analytic rays, the farthest %.3f%% of the view from "
              "an analytic occlusion boundary" % (len(allpoints), len(wrong), 100 * worst))
        self.assertLess(worst, 0.005)


def extruded_bump(a=2.0, n=301):
    """z = a exp(-x^2 / 2) over [-4.5, 4.5] x [-2, 2]: a profile extruded along y."""
    xs, ys = np.linspace(-4.5, 4.5, n), np.linspace(-2.0, 2.0, n // 2)
    X, Y = np.meshgrid(xs, ys, indexing="ij")
    points = np.stack([X, Y, a * np.exp(-X ** 2 / 2)], -1).reshape(-1, 3)
    m = len(ys)
    i, j = np.meshgrid(np.arange(n - 1), np.arange(m - 1), indexing="ij")
    p, q, r, s = i * m + j, (i + 1) * m + j, (i + 1) * m + j + 1, i * m + j + 1
    tris = np.concatenate([np.stack([p, q, r], -1).reshape(-1, 3), np.stack([p, r, s], -1).reshape(-1, 3)])
    return inputs.polydata(points, tris)


class ApparentRidges(unittest.TestCase):
    def test_extruded_profile_against_closed_form(self):
        """Seen orthographically along (sin b, 0, -cos b), the profile's
        normal turns by h'' / (1 + h'^2) per unit x and x moves the image by
        cos b + h' sin b: the view-dependent curvature is
        q1 = |h'' / (1 + h'^2) / (cos b + h' sin b)| (the y direction: 0), and
        the apparent ridges are the lines x = const at its maxima in x.
        The fields of the surface itself (Curvature Smoothing 0; the default
        0.5 moves these lines by up to 0.012)."""
        a, size, threshold = 2.0, 0.1, 0.02
        mesh = extruded_bump(a)
        x = np.linspace(-4.4, 4.4, 880001)
        slope, bend = -a * x * np.exp(-x ** 2 / 2), a * (x ** 2 - 1) * np.exp(-x ** 2 / 2)
        valley = x[x > 1][np.argmax((bend / (1 + slope ** 2) ** 1.5)[x > 1])]  # (the surface's own valley)
        for degrees in (0.0, 30.0, -45.0):
            b = math.radians(degrees)
            image = np.cos(b) + slope * np.sin(b)
            q1 = np.where(image > 0, np.abs(bend / (1 + slope ** 2) / np.maximum(image, 1e-300)), 0.0)
            peak = np.nonzero((q1[1:-1] > q1[:-2]) & (q1[1:-1] >= q1[2:]) & (q1[1:-1] * size > threshold)
                              & (image[1:-1] > 0.1))[0] + 1  # (not the contour, where q1 grows without bound)
            expected = x[peak]
            out = draw(mesh, ParallelProjection=True, ViewDirection=(math.sin(b), 0, -math.cos(b)), Contours=False,
                       Boundaries=False, Creases=False, ApparentRidges=True, FeatureSize=size,
                       ApparentRidgeThreshold=threshold, CurvatureSmoothing=0.0)
            lines = [p for t, _, p in polylines(out) if t == vtkSurfaceLineDrawing.APPARENT_RIDGE]
            found = sorted(p[:, 0].mean() for p in lines)
            print("apparent ridges seen at %g degrees: x = %s (closed form %s)"
                  % (degrees, np.round(found, 4), np.round(expected, 4)))
            self.assertEqual(len(lines), len(expected))
            for p, x0 in zip(sorted(lines, key=lambda p: p[:, 0].mean()), expected):
                self.assertLess(np.abs(p[:, 0] - x0).max(), 0.01)  # 0.1% of the view; the grid's step 0.03
                self.assertGreater(np.ptp(p[:, 1]), 3.9)  # across the whole strip
            if degrees == 0.0:
                # The view-dependent curvature, not the surface's: its maximum
                # lies 0.09 from the surface's valley.
                self.assertGreater(abs(expected[-1] - valley), 0.09)


class ScanDefaults(unittest.TestCase):
    """Raw scans at the defaults (Curvature Smoothing 0.5, Minimum Line
    Length 2, Hysteresis Ratio 0.5), their visible contours and suggestive
    contours from the demo's camera: the median line at least 4 feature
    sizes long, none shorter than one, and the long lines (4 feature sizes
    and more) of a smoothed copy (one implicit step of the Laplacian, time
    FeatureSize^2) kept: 85% of their length within half a feature size of
    the scan's lines."""

    def measure(self, scan, label):
        from beltrami import vtkImplicitFairing
        points = vtk_to_numpy(scan.GetPoints().GetData()).astype(float)
        size = 0.01 * np.linalg.norm(np.ptp(points, 0))
        smoothing = inputs.filter_with(vtkImplicitFairing, Order=1, Units=1, TimeStep=size * size)()
        smoothing.SetInputData(scan)
        smoothing.Update()
        camera = dict(CameraPosition=(0.0, 0.02, 0.4), ViewDirection=(0, -0.02, -0.4),
                      Visibility=vtkSurfaceLineDrawing.VISIBLE_LINES, SuggestiveContours=True)

        def lines(mesh, **settings):
            out = draw(mesh, **camera, **settings)
            return [p for t, _, p in polylines(out) if t in (CONTOUR, vtkSurfaceLineDrawing.SUGGESTIVE_CONTOUR)]

        def length(p):
            return np.linalg.norm(np.diff(p, axis=0), axis=1).sum() / size

        def dense(polylines_list):
            out = []
            for p in polylines_list:
                for a, b in zip(p[:-1], p[1:]):
                    k = max(1, int(np.linalg.norm(b - a) / (0.1 * size)))
                    out += [a + (b - a) * i / k for i in range(k)]
            return np.array(out)

        def covered(reference, drawn):
            from scipy.spatial import cKDTree
            return np.mean(cKDTree(drawn).query(reference)[0] < 0.5 * size)
        long_smoothed = dense([p for p in lines(smoothing.GetOutput()) if length(p) >= 4])
        results = {}
        for name, settings in (("defaults", {}), ("without curvature smoothing", dict(CurvatureSmoothing=0.0))):
            ours = lines(scan, **settings)
            lengths = np.array([length(p) for p in ours])
            results[name] = (lengths, covered(long_smoothed, dense(ours)))
            print("%s, %s: %d lines, median %.2f feature sizes, shortest %.2f; the smoothed copy's long lines "
                  "%.1f%% kept" % (label, name, len(ours), np.median(lengths), lengths.min(), 100 * results[name][1]))
        lengths, share = results["defaults"]
        self.assertGreaterEqual(np.median(lengths), 4.0)
        self.assertGreaterEqual(lengths.min(), 1.0)
        self.assertGreater(share, 0.85)

    def test_a_raw_scan_draws_long_lines_at_the_defaults(self):
        self.measure(inputs.read_off(os.path.join(inputs.DATA, "bunny00.off")), "bunny00")

    def test_a_large_scan_draws_long_lines_at_the_defaults(self):
        """bunny00 Loop-subdivided twice (1.2M triangles): its noise becomes
        bumps a few triangles wide, which without the smoothing draw a median
        line of 3.7 feature sizes."""
        from vtkmodules.vtkFiltersModeling import vtkLoopSubdivisionFilter
        loop = vtkLoopSubdivisionFilter()
        loop.SetInputData(inputs.read_off(os.path.join(inputs.DATA, "bunny00.off")))
        loop.SetNumberOfSubdivisions(2)
        loop.Update()
        self.measure(loop.GetOutput(), "bunny00 at 1.2M triangles")

    def test_a_noisy_scan_draws_long_lines_at_the_defaults(self):
        """bunny00 with normal noise of 0.05 mean edge lengths added (a
        median of 3.8 feature sizes without the smoothing; heavier noise
        needs more: at 0.3 mean edge lengths the defaults give 3.8, Curvature
        Smoothing 1 gives 10.9)."""
        scan = inputs.read_off(os.path.join(inputs.DATA, "bunny00.off"))
        points = vtk_to_numpy(scan.GetPoints().GetData()).astype(float)
        triangles = vtk_to_numpy(scan.GetPolys().GetConnectivityArray()).reshape(-1, 3)
        edge = np.linalg.norm(points[triangles] - points[np.roll(triangles, 1, axis=1)], axis=2).mean()
        noisy = points + np.random.default_rng(1).normal(0.0, 0.05 * edge / np.sqrt(3.0), points.shape)
        self.measure(inputs.polydata(noisy, triangles), "bunny00 with noise")


class HugeAndTinyCoordinates(unittest.TestCase):
    def test_curvatures_and_lines_do_not_depend_on_the_scale(self):
        """A sphere scaled by 1e+-100 and 1e+-150 (its squared areas beyond
        double precision's range): the curvatures are the unit sphere's
        scaled (they were NaN, with a warning of zero-area triangles), the
        contour, seen in parallel projection, the unit sphere's scaled, and
        the Beltrami operators of point data on it too (they were NaN
        without a warning)."""
        from beltrami import vtkDiscreteCurvatures
        points, triangles = inputs.sphere(24)

        def mean_curvature(scale):
            c = vtkDiscreteCurvatures()
            said = inputs.Messages(c)
            c.SetInputData(inputs.polydata(points * scale, triangles))
            c.Update()
            self.assertEqual(said.warnings + said.errors, [])
            return vtk_to_numpy(c.GetOutput().GetPointData().GetArray("MeanCurvature"))

        def contour(scale):
            out = draw(inputs.polydata(points * scale, triangles), ParallelProjection=True, ViewDirection=(0.3, 0.2, -1),
                       Visibility=vtkSurfaceLineDrawing.VISIBLE_LINES)
            lines = [p for t, _, p in polylines(out) if t == CONTOUR]
            self.assertEqual(len(lines), 1)
            return lines[0]
        def operators(scale):
            from beltrami import vtkBeltramiOperators
            f = vtkBeltramiOperators()
            said = inputs.Messages(f)
            mesh = inputs.polydata(points * scale, triangles)
            values = numpy_to_vtk(np.sin(points[:, 0]) + 0.05 * np.cos(37.0 * np.arange(len(points))), deep=True)
            values.SetName("Scalars")  # (the same data at every scale)
            mesh.GetPointData().AddArray(values)
            f.SetInputData(mesh)
            f.SetInputArrayToProcess(0, 0, 0, 0, "Scalars")
            f.Update()
            self.assertEqual(said.warnings + said.errors, [])
            data = f.GetOutput().GetPointData()
            # (per length, per length^2, none: brought back to the unit sphere's)
            return [vtk_to_numpy(data.GetArray(name)) * scale ** power
                    for name, power in (("MeanCurvature", 1), ("BeltramiOperator", 2), ("GaussianCurvature", 2),
                                        ("EdgeIndicator", 0))]
        unit, unit_contour, unit_operators = mean_curvature(1.0), contour(1.0), operators(1.0)
        for scale in (1e100, 1e-100, 1e150, 1e-150):
            np.testing.assert_allclose(mean_curvature(scale) * scale, unit, rtol=1e-9, err_msg=str(scale))
            np.testing.assert_allclose(contour(scale) / scale, unit_contour, rtol=1e-9, atol=1e-12, err_msg=str(scale))
            for ours, theirs in zip(operators(scale), unit_operators):
                np.testing.assert_allclose(ours, theirs, rtol=1e-9, atol=1e-12, err_msg=str(scale))


NAMES = ("contour", "suggestive-contour", "suggestive-highlight", "ridge", "valley", "boundary", "crease",
         "apparent-ridge")
PAGE, MARGIN = 504.0, 18.0  # the writer's defaults, points


def write(drawing_output, path, **settings):
    w = inputs.filter_with(vtkLineDrawingWriter, **settings)()
    said = inputs.Messages(w)
    w.SetInputData(drawing_output)
    w.SetFileName(path)
    w.Write()
    return said


def field(out, name):
    return vtk_to_numpy(out.GetFieldData().GetArray(name)).ravel()


def projected(out, hidden_too):
    """{class: [page polyline (k x 2)]} of a drawing, projected here from its
    field arrays (the writer's page: longer side PAGE less the margins, y down)."""
    eye, forward, up = field(out, "CameraPosition"), field(out, "ViewDirection"), field(out, "ViewUp")
    forward = forward / np.linalg.norm(forward)
    up = up - (up @ forward) * forward
    up /= np.linalg.norm(up)
    right = np.cross(forward, up)
    parallel = field(out, "ParallelProjection")[0] != 0
    lines = [(t, h, p) for t, h, p in polylines(out) if hidden_too or not h]

    def plane(p):
        if parallel:
            return np.stack([p @ right, p @ up], -1)
        v = p - eye
        z = v @ forward
        return np.stack([v @ right / z, v @ up / z], -1)
    flat = [(t, h, plane(p)) for t, h, p in lines]
    allxy = np.vstack([xy for _, _, xy in flat])
    lo, hi = allxy.min(0), allxy.max(0)
    scale = (PAGE - 2 * MARGIN) / (hi - lo).max()
    pages = {}
    for t, h, xy in flat:
        page = np.stack([MARGIN + (xy[:, 0] - lo[0]) * scale, MARGIN + (hi[1] - xy[:, 1]) * scale], -1)
        pages.setdefault("hidden" if h else NAMES[t], []).append(page)
    return pages, (hi - lo) * scale + 2 * MARGIN


def svg_paths(path):
    """{class: [polyline (k x 2)]} and (width, height) of an SVG page."""
    root = ElementTree.parse(path).getroot()  # (valid XML, or this raises)
    ns = "{http://www.w3.org/2000/svg}"
    paths = {}
    for group in root.iter(ns + "g"):
        for element in group.iter(ns + "path"):
            d = element.get("d")
            xy = np.array([[float(v) for v in pair.split(",")] for pair in re.findall(r"[ML]([-0-9.e]+,[-0-9.e]+)", d)])
            if d.rstrip().endswith("Z"):
                xy = np.vstack([xy, xy[:1]])
            paths.setdefault(group.get("class"), []).append(xy)
    size = np.array([float(root.get(k).rstrip("pt")) for k in ("width", "height")])
    return paths, size


def distance_to_polylines(points, polylines_list):
    """The distance from each point to the nearest segment of the polylines."""
    a = np.vstack([p[:-1] for p in polylines_list])
    b = np.vstack([p[1:] for p in polylines_list])
    ab = b - a
    best = np.full(len(points), np.inf)
    for start in range(0, len(points), 256):
        q = points[start:start + 256, None, :]
        t = np.clip(((q - a) * ab).sum(-1) / np.maximum((ab * ab).sum(-1), 1e-300), 0, 1)
        d = np.linalg.norm(q - (a + t[..., None] * ab), axis=-1).min(1)
        best[start:start + 256] = d
    return best


def ink(grey, points_per_pixel):
    """The ink of a greyscale raster (0-255) in square points (1 - grey, summed)."""
    return (1.0 - grey / 255.0).sum() * points_per_pixel ** 2


def read_pgm(path):
    with open(path, "rb") as f:
        data = f.read()
    magic, width, height, maximum, rest = re.match(rb"(P5)\s+(\d+)\s+(\d+)\s+(\d+)\s(.*)", data, re.S).groups()
    return np.frombuffer(rest, np.uint8)[: int(width) * int(height)].reshape(int(height), int(width)).astype(float)


class Writer(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.mkdtemp()

    def test_svg_rereads_to_the_projected_polylines(self):
        for camera in (dict(CameraPosition=(0, 0, 5)), dict(ParallelProjection=True, ViewDirection=(0.2, -0.3, -1),
                                                               ViewUp=(1, 1, 0))):
            out = draw(sphere_before_roof(), Visibility=vtkSurfaceLineDrawing.VISIBLE_AND_HIDDEN_LINES, **camera)
            svg = os.path.join(self.tmp, "roof.svg")
            said = write(out, svg, DrawHiddenLines=True)
            self.assertEqual(said.errors + said.warnings, [])
            paths, size = svg_paths(svg)
            expected, expected_size = projected(out, hidden_too=True)
            self.assertTrue(np.allclose(size, expected_size, atol=2e-3), (size, expected_size))
            self.assertEqual(sorted(paths), sorted(expected))
            self.assertEqual(len(paths["hidden"]), 1)  # the crease behind the sphere
            self.assertEqual(len(paths["crease"]), 2)  # and its two visible ends
            tolerance = vtkLineDrawingWriter().GetTolerance()
            for name in expected:
                ours = np.vstack(paths[name])
                theirs = np.vstack(expected[name])
                # Every vertex written is a projected vertex (simplification
                # keeps a subset; 3 decimals) and every projected vertex lies
                # within the tolerance of the written lines.
                nearest = np.array([np.linalg.norm(theirs - p, axis=1).min() for p in ours])
                self.assertLess(nearest.max(), 2e-3, name)
                self.assertLess(distance_to_polylines(theirs, paths[name]).max(), tolerance + 2e-3, name)
            # Hidden lines left out by default.
            said = write(out, svg)
            self.assertNotIn("hidden", svg_paths(svg)[0])

    def test_pdf_and_svg_rasterise_to_the_expected_ink(self):
        """A sphere's contour, a circle filling the page less its margins:
        its ink is the circumference times the contour's width."""
        mesh = inputs.polydata(*inputs.sphere(96))
        out = draw(mesh, ParallelProjection=True, ViewDirection=(0, 0, -1),
                   Visibility=vtkSurfaceLineDrawing.VISIBLE_LINES)
        width = vtkLineDrawingWriter().GetLineWidths()[0]
        expected = math.pi * (PAGE - 2 * MARGIN) * width
        pdf, svg = os.path.join(self.tmp, "sphere.pdf"), os.path.join(self.tmp, "sphere.svg")
        for path in (pdf, svg):
            said = write(out, path)
            self.assertEqual(said.errors + said.warnings, [])
        with open(pdf, "rb") as f:
            self.assertEqual(f.read(5), b"%PDF-")
        # (At 288 dpi: poppler's rasteriser widens strokes by about an
        # eighth of a pixel, 2.6% of this contour's ink at 288 dpi, 5% at 144.)
        subprocess.run(["pdftoppm", "-r", "288", "-gray", pdf, os.path.join(self.tmp, "page")], check=True)
        raster = read_pgm(os.path.join(self.tmp, "page-1.pgm"))
        self.assertEqual(raster.shape, (2016, 2016))  # 504 pt at 288 dpi
        pdf_ink = ink(raster, 0.25)
        print("sphere contour: ink %.1f pt^2 in the PDF, %.1f expected" % (pdf_ink, expected))
        self.assertLess(abs(pdf_ink / expected - 1), 0.035)
        # The ink lies on the circle of radius (PAGE - 2 MARGIN) / 2 about the page's centre.
        ys, xs = np.nonzero(raster < 128)
        radius = np.hypot(xs * 0.25 + 0.125 - PAGE / 2, ys * 0.25 + 0.125 - PAGE / 2)
        self.assertLess(np.abs(radius - (PAGE / 2 - MARGIN)).max(), width)
        png = os.path.join(self.tmp, "sphere.png")
        subprocess.run(["rsvg-convert", "--dpi-x", "288", "--dpi-y", "288", "-b", "white", "-o", png, svg], check=True)
        from vtkmodules.vtkIOImage import vtkPNGReader
        reader = vtkPNGReader()
        reader.SetFileName(png)
        reader.Update()
        image = reader.GetOutput()
        rgb = vtk_to_numpy(image.GetPointData().GetScalars()).astype(float)
        self.assertEqual((image.GetDimensions()[0], image.GetDimensions()[1]), (2016, 2016))
        svg_ink = ink(rgb[:, :3].mean(1), 0.25)
        print("sphere contour: ink %.1f pt^2 in the SVG" % svg_ink)
        self.assertLess(abs(svg_ink / expected - 1), 0.035)

    def test_tapering_and_styles(self):
        mesh = inputs.read_off(os.path.join(inputs.DATA, "bunny00.off"))
        out = draw(mesh, SuggestiveContours=True, CameraPosition=(0.5, 0.2, 2.0), ViewDirection=(-0.25, -0.1, -1),
                   Visibility=vtkSurfaceLineDrawing.VISIBLE_LINES)
        svg = os.path.join(self.tmp, "bunny.svg")
        root_plain = (write(out, svg), ElementTree.parse(svg).getroot())[1]
        write(out, svg, TaperByStrength=True, LineColors=[0.2, 0.3, 0.4] + [0] * 21)
        root = ElementTree.parse(svg).getroot()
        ns = "{http://www.w3.org/2000/svg}"
        widths = {}
        for g in root.iter(ns + "g"):
            widths.setdefault(g.get("class"), set()).add(float(g.get("stroke-width")))
            if g.get("class") == "contour":
                self.assertEqual(g.get("stroke"), "#334d66")
        self.assertEqual(widths["contour"], {1.2})  # contours are not tapered
        self.assertGreater(len(widths["suggestive-contour"]), 3)
        self.assertLessEqual(max(widths["suggestive-contour"]), 0.7)
        self.assertGreaterEqual(min(widths["suggestive-contour"]), 0.7 * 0.2)
        plain = {float(g.get("stroke-width")) for g in root_plain.iter(ns + "g") if g.get("class") == "suggestive-contour"}
        self.assertEqual(plain, {0.7})

    def test_bad_input(self):
        svg = os.path.join(self.tmp, "none.svg")
        mesh = inputs.polydata(*inputs.sphere(12))
        said = write(mesh, svg)  # no camera: an error, nothing written
        self.assertTrue(any("no camera" in e for e in said.errors), said.errors)
        self.assertFalse(os.path.exists(svg))
        out = draw(mesh)  # not tested for visibility: written, with a warning
        said = write(out, svg)
        self.assertTrue(any("visibility" in w for w in said.warnings), said.warnings)
        self.assertTrue(os.path.exists(svg))
        said = write(out, os.path.join(self.tmp, "no", "such", "dir.pdf"))
        self.assertTrue(any("Cannot write" in e for e in said.errors), said.errors)


if __name__ == "__main__":
    unittest.main()
