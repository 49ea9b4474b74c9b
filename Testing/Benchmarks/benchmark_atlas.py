"""The atlas (vtkSurfaceAtlas, thesis section 4.2) of bunny00 and of its Loop
subdivisions (300k and 1.2M triangles), with square, circle and natural
chart boundaries: charts, packing efficiency, mean angle distortion
(area-weighted over the charts), time without the maps; then the geometry
maps at 512^2, per chart and as one atlas image (on demand, not a test).
Then, when build/bin/beltrami-benchmark-cgal-parameterization is
built (apt install libcgal-dev, rebuild), the peer on the same charts: each
chart of bunny00's atlas given to CGAL 5.5's DCP (circle border) and LSCM
(natural), against our circle and natural charts.

    source build/beltrami-env.sh
    /usr/bin/python3 Testing/Benchmarks/benchmark_atlas.py [levels]
"""
import os
import sys

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkPoints
from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkPolyData

import beltrami

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from benchmark_parameterization import cgal, mesh  # noqa: E402  (CGAL on one mesh; bundled meshes)
from timing import timed  # noqa: E402
import results  # noqa: E402


def atlas_of(data, boundary):
    f = beltrami.vtkSurfaceAtlas()
    f.SetInputData(data)
    f.SetChartBoundary(boundary)
    f.SetMapResolution(0)
    f.Update()
    return f.GetOutput()


def chart_mesh(cut, chart):
    """The triangles of one chart of the cut surface as a mesh of their own."""
    ids = vtk_to_numpy(cut.GetCellData().GetArray("ChartId"))
    triangles = vtk_to_numpy(cut.GetPolys().GetConnectivityArray()).reshape(-1, 3)[ids == chart]
    used, local = np.unique(triangles, return_inverse=True)
    points = vtkPoints()
    points.SetData(numpy_to_vtk(vtk_to_numpy(cut.GetPoints().GetData())[used].astype(float), deep=1))
    cells = vtkCellArray()
    cells.SetData(numpy_to_vtk(np.arange(0, 3 * len(triangles) + 1, 3, dtype=np.int64), deep=1),
                  numpy_to_vtk(local.astype(np.int64), deep=1))
    pd = vtkPolyData()
    pd.SetPoints(points)
    pd.SetPolys(cells)
    return pd


def against_cgal(data):
    """Per chart: our circle and natural maps against CGAL's DCP and LSCM."""
    ours = {name: atlas_of(data, b) for name, b in (("DCP", beltrami.vtkSurfaceAtlas.CIRCLE),
                                                      ("DCPsquare", beltrami.vtkSurfaceAtlas.SQUARE),
                                                      ("natural", beltrami.vtkSurfaceAtlas.NATURAL))}
    cut = ours["DCP"]
    charts = cut.GetFieldData().GetArray("AtlasCharts").GetValue(0)
    areas = vtk_to_numpy(cut.GetFieldData().GetArray("AtlasChartArea"))
    rows = {"DCP": [], "DCPsquare": [], "natural": []}
    for c in range(charts):
        peer = cgal(chart_mesh(cut, c))
        if not peer:
            print("  (CGAL comparison skipped: build/bin/beltrami-benchmark-cgal-parameterization not built)")
            return []
        for name in rows:
            mine = vtk_to_numpy(ours[name].GetFieldData().GetArray("AtlasChartAngleDistortion"))[c]
            rows[name].append((mine, peer[name][1]))
    table = []
    for name, label in (("DCP", "DCP on circles"), ("DCPsquare", "DCP on squares"), ("natural", "natural vs LSCM")):
        mine, theirs = np.array(rows[name]).T
        table.append([label, float(np.average(mine, weights=areas)), float(np.average(theirs, weights=areas)),
                      int(np.sum(mine > theirs + 0.01)), int(charts)])
        print("  %-16s mean angle distortion (area-weighted) ours %.3f deg, CGAL %.3f deg; charts where ours is "
              "worse by more than 0.01 deg: %d of %d" % (label, np.average(mine, weights=areas),
                                                         np.average(theirs, weights=areas),
                                                         int(np.sum(mine > theirs + 0.01)), charts))
    return table


def first_and_best(f, repeats=3):
    """Seconds of f.Update(): the first run and the best of `repeats` (timing.timed)."""
    def run():
        f.Modified()
        f.Update()
    first = timed(run, 1)[1]
    return first, min(first, timed(run, repeats - 1)[1])


def main(argv):
    levels = int(argv[1]) if len(argv) > 1 else 2
    bunny = mesh("bunny00.off")
    print("time: the first run and the best of 3 (timings here vary by up to 50% between runs)")
    print("%-10s %9s %7s %13s %9s %11s %7s" % ("boundary", "triangles", "charts", "time s", "packing",
                                              "mean angle", "splits"))
    rows = []
    for level in range(levels + 1):
        data = mesh("bunny00.off", level) if level else bunny
        for boundary, name in ((beltrami.vtkSurfaceAtlas.SQUARE, "square"), (beltrami.vtkSurfaceAtlas.CIRCLE, "circle"),
                               (beltrami.vtkSurfaceAtlas.NATURAL, "natural")):
            f = beltrami.vtkSurfaceAtlas()
            f.SetInputData(data)
            f.SetChartBoundary(boundary)
            f.SetMapResolution(0)  # the atlas only
            first, elapsed = first_and_best(f)
            fd = f.GetOutput().GetFieldData()
            angles = fd.GetArray("AtlasChartAngleDistortion")
            areas = fd.GetArray("AtlasChartArea")
            n = angles.GetNumberOfTuples()
            total = sum(areas.GetValue(k) for k in range(n))
            mean = sum(angles.GetValue(k) * areas.GetValue(k) for k in range(n)) / total
            print("%-10s %9d %7d %6.2f / %4.2f %8.1f%% %9.2f deg %7d" % (
                name, data.GetNumberOfCells(), n, first, elapsed, 100 * fd.GetArray("AtlasPackingEfficiency").GetValue(0),
                mean, fd.GetArray("AtlasSplitsForFlips").GetValue(0)))
            rows.append([name, data.GetNumberOfCells(), n, first, elapsed,
                         100 * fd.GetArray("AtlasPackingEfficiency").GetValue(0), mean])
    results.save("atlas", "Atlas", "Charts, packing and distortion", "none for whole atlases in Debian (see the "
                 "per-chart comparison with CGAL below)", "bunny00 and its Loop subdivisions",
                 ["chart boundary", "triangles", "charts", "first run s", "best of 3 s", "packing %",
                  "mean angle distortion deg"], rows, "Without the geometry maps; angle distortion area-weighted "
                 "over the charts.")
    print("geometry maps at 512^2 (FaceId, Embedding, AreaRatio, MeanCurvature, GaussianCurvature; best of 5, "
          "the atlas excluded):")
    for level in range(min(levels, 1) + 1):
        data = mesh("bunny00.off", level) if level else bunny
        seconds = {}
        for layout, resolution in ((beltrami.vtkSurfaceAtlas.CHARTS, 0), (beltrami.vtkSurfaceAtlas.CHARTS, 512),
                                   (beltrami.vtkSurfaceAtlas.ATLAS, 512)):
            f = beltrami.vtkSurfaceAtlas()
            f.SetInputData(data)
            f.SetMapLayout(layout)
            f.SetMapResolution(resolution)
            seconds[layout, resolution] = first_and_best(f, 5)[1]
        charts = f.GetOutput().GetFieldData().GetArray("AtlasCharts").GetValue(0)
        atlas = seconds[beltrami.vtkSurfaceAtlas.CHARTS, 0]
        print("  %7d triangles, %d charts: one image per chart (%.1f Mpixels) %.3f s; one atlas image (0.26 Mpixels) "
              "%.3f s" % (data.GetNumberOfCells(), charts, charts * 512 * 512 / 1e6,
                          seconds[beltrami.vtkSurfaceAtlas.CHARTS, 512] - atlas,
                          seconds[beltrami.vtkSurfaceAtlas.ATLAS, 512] - atlas))
    print("bunny00's charts against CGAL 5.5:")
    table = against_cgal(bunny)
    if table:
        results.save("atlas_charts", "Atlas", "Each chart's map against CGAL",
                     "CGAL 5.5 Surface_mesh_parameterization (DCP on a circle, LSCM) on the same charts",
                     "the charts of bunny00's atlas, each given to both", ["map", "ours deg", "CGAL deg",
                                                                           "charts where ours is worse by > 0.01 deg",
                                                                           "charts"], table,
                     "Mean angle distortion, area-weighted over the charts.")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
