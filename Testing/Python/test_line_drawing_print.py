"""Line drawings for print: vtkSurfaceLineDrawing's Visibility against
analytic occlusion (a sphere in front of a folded plane, orthographic and
perspective; a torus seen at a grazing angle, against rays cast through the
implicit torus), and vtkLineDrawingWriter's SVG and PDF."""
import math
import os
import sys
import unittest

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import inputs  # noqa: E402
from beltrami import vtkSurfaceLineDrawing  # noqa: E402

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


if __name__ == "__main__":
    unittest.main()
