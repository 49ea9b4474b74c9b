"""The atlas (vtkSurfaceAtlas, thesis section 4.2) of bunny00 and of its Loop
subdivisions (300k and 1.2M triangles), with square, circle and natural
chart boundaries: charts, packing efficiency, mean angle distortion
(area-weighted over the charts), time without the maps (on demand, not a
test).

    source build/beltrami-env.sh
    /usr/bin/python3 Testing/Benchmarks/benchmark_atlas.py [levels]
"""
import os
import sys
import time

from vtkmodules.vtkFiltersModeling import vtkLoopSubdivisionFilter

import beltrami

DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "Data")


def main(argv):
    levels = int(argv[1]) if len(argv) > 1 else 2
    reader = beltrami.vtkOFFReader()
    reader.SetFileName(os.path.join(DATA, "bunny00.off"))
    reader.Update()
    print("%-10s %9s %7s %8s %9s %11s %7s" % ("boundary", "triangles", "charts", "time s", "packing",
                                             "mean angle", "splits"))
    for level in range(levels + 1):
        mesh = reader.GetOutput()
        if level:
            loop = vtkLoopSubdivisionFilter()
            loop.SetNumberOfSubdivisions(level)
            loop.SetInputData(mesh)
            loop.Update()
            mesh = loop.GetOutput()
        for boundary, name in ((beltrami.vtkSurfaceAtlas.SQUARE, "square"), (beltrami.vtkSurfaceAtlas.CIRCLE, "circle"),
                               (beltrami.vtkSurfaceAtlas.NATURAL, "natural")):
            f = beltrami.vtkSurfaceAtlas()
            f.SetInputData(mesh)
            f.SetChartBoundary(boundary)
            f.SetMapResolution(0)  # the atlas only
            start = time.perf_counter()
            f.Update()
            elapsed = time.perf_counter() - start
            fd = f.GetOutput().GetFieldData()
            angles = fd.GetArray("AtlasChartAngleDistortion")
            areas = fd.GetArray("AtlasChartArea")
            n = angles.GetNumberOfTuples()
            total = sum(areas.GetValue(k) for k in range(n))
            mean = sum(angles.GetValue(k) * areas.GetValue(k) for k in range(n)) / total
            print("%-10s %9d %7d %8.2f %8.1f%% %9.2f deg %7d" % (
                name, mesh.GetNumberOfCells(), n, elapsed, 100 * fd.GetArray("AtlasPackingEfficiency").GetValue(0),
                mean, fd.GetArray("AtlasSplitsForFlips").GetValue(0)))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
