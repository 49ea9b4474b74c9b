#!/usr/bin/python3
"""Beltrami demo: line drawings with vtkSurfaceLineDrawing (thesis 1.1).

Draws the bundled bunny (contours, suggestive contours, ridges and valleys)
and the CAD part fandisk (contours, suggestive contours, creases) from fixed
cameras, then the bunny from a second camera (only the per-view pass runs
again), every piece of every line, and the bunny once more at the filter's
defaults, without the short lines its scan noise draws (CurvatureSmoothing
0.5, MinimumLineLength 2 feature sizes, HysteresisRatio 0.5); prints the line counts and
times and writes the lines (.vtp) and
pictures: contours black, suggestive contours blue, ridges red, valleys
green, creases grey; and each drawing for print, its visible lines only, as
SVG and PDF pages (vtkLineDrawingWriter; the bunny's hidden lines dashed).

    source build/beltrami-env.sh
    xvfb-run -a /usr/bin/python3 Examples/line_drawing_demo.py [output-dir]
"""
import os
import sys

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy

from beltrami.pipelines import line_drawing, render_line_drawing, write_print_drawing, write_vtp

HERE = os.path.dirname(os.path.abspath(__file__))
DATA = os.path.join(HERE, "..", "Testing", "Data")
NAMES = ("contours", "suggestive contours", "suggestive highlights", "ridges", "valleys", "boundaries", "creases")

RUNS = (  # mesh, label, view direction, zoom, options
    ("bunny00.off", "front", (0.8, 0.2, 1), 1.2, dict(ridges=True, valleys=True)),
    # The filter's defaults: the curvatures measured on a copy of the scan
    # smoothed over half a feature size (CurvatureSmoothing), the curvature
    # lines joined where its noise breaks them (HysteresisRatio 0.5), and
    # the lines shorter than 2 feature sizes dropped (MinimumLineLength); the
    # run above keeps every piece of the scan's own lines (0, 1 and 0).
    ("bunny00.off", "front_long_lines", (0.8, 0.2, 1), 1.2,
     dict(ridges=True, valleys=True, minimum_length=2.0, hysteresis=0.5, smoothing=0.5)),
    ("fandisk.off", "front", (1, 0.6, 0.8), 0.9, {}),
)


def main(argv):
    out_dir = argv[1] if len(argv) > 1 else "demo-output"
    os.makedirs(out_dir, exist_ok=True)
    for mesh, label, direction, zoom, options in RUNS:
        drawing = line_drawing(os.path.join(DATA, mesh), **options)
        views = [(label, direction)] + ([("side", (-1, 0.3, -0.2))] if mesh.startswith("bunny") and label == "front" else [])
        for view, d in views:
            stem = os.path.join(out_dir, "%s_line_drawing_%s" % (os.path.splitext(mesh)[0], view))
            _, seconds = render_line_drawing(drawing, stem + ".png", direction=d, zoom=zoom)
            lines = drawing.GetOutput()
            if lines.GetCellData().GetArray("LineType") is None:
                print("error: no line drawing of %s (see the error above)" % mesh, file=sys.stderr)
                return 1
            counts = np.bincount(vtk_to_numpy(lines.GetCellData().GetArray("LineType")), minlength=len(NAMES))
            print("line drawing of %s (%s view) in %.3f s: %s; view-independent pass run %d time(s)"
                  % (mesh, view, seconds, ", ".join("%d %s" % (c, n) for c, n in zip(counts, NAMES) if c),
                     drawing.GetGeometryBuilds()))
            write_vtp(lines, stem + ".vtp")
            print("wrote %s.vtp\nwrote %s.png" % (stem, stem))
            for path in write_print_drawing(drawing, stem, hidden_dashed=mesh.startswith("bunny")):
                print("wrote %s" % path)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
