"""Line drawings (vtkSurfaceLineDrawing) on the 1.2M-triangle
Loop-subdivided bunny (on demand, not a test): the view-independent pass
(curvatures, their derivatives, feature edges; with ridges on, the ridge
and valley candidates too) against our curvature filter alone
(vtkDiscreteCurvatures, the part every drawing needs), and one per-view
pass (a new camera: contours, suggestive contours, boundaries, creases, and
ridges when on, chaining), at the filter's defaults (Curvature Smoothing
0.5: one implicit fairing solve in the view-independent pass), without the
smoothing, with ridges, and with Visibility on visible lines only (the rays' tree is built with the first
view: counted in the view-independent pass), on 1 and 2 threads, best of
three.

    source build/beltrami-env.sh
    /usr/bin/python3 Testing/Benchmarks/benchmark_line_drawing.py [levels]
"""
import os
import sys

import beltrami

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from benchmark_parameterization import mesh  # noqa: E402  (bundled meshes, Loop-subdivided)
from timing import timed  # noqa: E402
import results  # noqa: E402


def drawing_passes(data, threads, ridges, cameras, visibility=0, smoothing=0.5):
    """(view-independent pass, per-view pass, the drawing) of vtkSurfaceLineDrawing
    at its defaults, ridges added when `ridges`."""
    drawing = beltrami.vtkSurfaceLineDrawing()
    drawing.SetInputData(data)
    drawing.SetCurvatureSmoothing(smoothing)
    drawing.SetRidges(ridges)
    drawing.SetVisibility(visibility)
    drawing.SetNumberOfThreads(threads)

    def whole_run():
        data.Modified()  # a new input: both passes
        drawing.Update()
    _, whole = timed(whole_run)
    state = {"camera": 0}

    def view_run():
        state["camera"] += 1
        drawing.SetCameraPosition(cameras[state["camera"] % len(cameras)])
        drawing.Update()
    _, per_view = timed(view_run, repeats=len(cameras))
    return whole - per_view, per_view, drawing


def main(argv):
    levels = int(argv[1]) if len(argv) > 1 else 2
    data = mesh("bunny00.off", levels)
    print("bunny00 after %d Loop subdivisions: %d points, %d triangles"
          % (levels, data.GetNumberOfPoints(), data.GetNumberOfCells()))
    cameras = [(0.0, 0.02, 0.4), (0.4, 0.1, 0.0), (-0.3, 0.2, -0.2), (0.1, 0.3, 0.3)]
    rows = []
    for threads in (1, 2):
        curvatures = beltrami.vtkDiscreteCurvatures()
        curvatures.SetInputData(data)
        curvatures.SetNumberOfThreads(threads)

        def curvature_run():
            curvatures.Modified()
            curvatures.Update()
        _, curvature_time = timed(curvature_run)
        print("%d thread(s): curvature filter %.3f s" % (threads, curvature_time))
        visible = beltrami.vtkSurfaceLineDrawing.VISIBLE_LINES
        for ridges, visibility, smoothing, what in ((False, 0, 0.5, "defaults"),
                                                    (False, 0, 0.0, "without curvature smoothing"),
                                                    (True, 0, 0.5, "with ridges"),
                                                    (False, visible, 0.5, "visible lines only")):
            independent, per_view, drawing = drawing_passes(data, threads, ridges, cameras, visibility, smoothing)
            lines = drawing.GetOutput()
            print("  line drawing, %s: view-independent pass %.3f s (%.2fx the curvature filter), per-view pass "
                  "%.1f ms (%d polylines, %d points); view-independent builds %d"
                  % (what, independent, independent / curvature_time, 1000 * per_view,
                     lines.GetNumberOfCells(), lines.GetNumberOfPoints(), drawing.GetGeometryBuilds()))
            rows.append([what, threads, curvature_time, independent, 1000 * per_view, lines.GetNumberOfCells()])
    results.save("line_drawing", "Line drawings", "Speed on a large scan",
                 "none packaged in Debian (rtsc, the reference implementation, is not); our curvature filter, "
                 "the part every drawing needs, as the yardstick",
                 "bunny00 after %d Loop subdivisions (%d triangles)" % (levels, data.GetNumberOfCells()),
                 ["lines", "threads", "curvature filter s", "view-independent pass s", "per-view pass ms", "polylines"],
                 rows, "The view-independent pass runs once per input; a new camera re-runs only the per-view pass. "
                 "Best of three runs.")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
