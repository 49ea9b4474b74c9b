"""Benchmark (on demand): vtkSurfaceLineDrawing on the 1.2M-triangle bunny
(bunny00 Loop-subdivided twice) split over 1, 2 and 4 ranks of pvbatch
(RedistributeDataSet): the first update (the ring exchange, the
view-independent pass and one view) and a new camera (the per-view pass:
each rank's segments, gathered and chained on rank 0), contours, suggestive
contours, ridges and valleys; the polylines drawn and the largest share of
points a rank holds.  One thread per rank, so 4 ranks are oversubscribed on
2 cores (2 per core): read the 4-rank times as such.  The 1-rank run is the
serial code path.
Run:  source build/beltrami-env.sh && /usr/bin/python3 Testing/Benchmarks/benchmark_distributed_line_drawing.py
(it starts `mpirun ... pvbatch` itself; a worker prints one JSON line)."""
import json
import os
import subprocess
import sys
import tempfile
import time

HERE = os.path.abspath(__file__)
CAMERAS = ((0.0, 0.02, 0.4), (0.4, 0.1, 0.0), (-0.3, 0.2, -0.2), (0.1, 0.3, 0.3))


def worker(mesh_file):
    from paraview import simple
    sys.path[:0] = [os.path.dirname(HERE), os.path.join(os.path.dirname(HERE), "..", "Python")]
    from benchmark_distributed_fairing import split_mesh
    from configure import rank_rows
    import beltrami  # noqa: F401 (the filter's wrapping, for GetGeometryBuilds)
    ranks, split = split_mesh(mesh_file)
    drawing = simple.SurfaceLineDrawing(Input=split, NumberOfThreads=1, Ridges=1, Valleys=1,
                                        CameraPosition=CAMERAS[0])
    start = time.perf_counter()
    drawing.UpdatePipeline()
    first = time.perf_counter() - start
    views = []
    for camera in CAMERAS[1:]:
        drawing.CameraPosition = camera
        start = time.perf_counter()
        drawing.UpdatePipeline()
        views.append(time.perf_counter() - start)
    owned, ghosts = rank_rows(simple.OutputPort(drawing, 1), "LineDrawingDistribution", ("Owned", "Ghosts"))
    # (numpy's max: rank_rows' programmable filter puts numpy_interface's in this namespace)
    held = float((owned + ghosts).max() / owned.sum()) if ranks > 1 else 1.0
    print("RESULT " + json.dumps(dict(ranks=ranks, first=first, view=sorted(views)[0], held=held,
                                      lines=drawing.GetDataInformation().GetNumberOfCells(),
                                      builds=drawing.GetClientSideObject().GetGeometryBuilds())), flush=True)


def driver():
    sys.path.insert(0, os.path.dirname(HERE))
    from benchmark_parameterization import mesh  # (bundled meshes, Loop-subdivided)
    from beltrami.pipelines import write_vtp
    bunny = mesh("bunny00.off", 2)
    print("Bunny: %d points, %d triangles; one thread per rank" % (bunny.GetNumberOfPoints(), bunny.GetNumberOfCells()))
    print("%5s %22s %16s %9s %14s" % ("ranks", "first update (s)", "new camera (ms)", "polylines", "points/rank"))
    with tempfile.TemporaryDirectory() as tmp:
        mesh_file = os.path.join(tmp, "bunny.vtp")
        write_vtp(bunny, mesh_file)
        base = None
        for ranks in (1, 2, 4):
            out = subprocess.run(["mpirun", "--allow-run-as-root", "--oversubscribe", "-np", str(ranks),
                                  "pvbatch", HERE, "--worker", mesh_file], capture_output=True, text=True,
                                 timeout=1800).stdout
            r = next(json.loads(line[7:]) for line in out.splitlines() if line.startswith("RESULT "))
            base = base or r
            print("%5d %13.3f (%4.2fx) %9.1f (%4.2fx) %9d %13.1f%%" % (
                ranks, r["first"], base["first"] / r["first"], 1000 * r["view"], base["view"] / r["view"],
                r["lines"], 100 * r["held"]))


if __name__ == "__main__":
    if "--worker" in sys.argv:
        worker(sys.argv[sys.argv.index("--worker") + 1])
    else:
        driver()
