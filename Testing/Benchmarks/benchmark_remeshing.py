#!/usr/bin/python3
"""Benchmark (on demand, not a test): vtkSurfaceRemeshing against CGAL 5.5's
isotropic_remeshing, in the same run, on the same meshes and vertex counts.

    source build/beltrami-env.sh
    /usr/bin/python3 Testing/Benchmarks/benchmark_remeshing.py [--big | --corpus [--noise N | --variants] |
                                                                 --deviation D]

CGAL runs through build/bin/beltrami-benchmark-cgal-isotropic-remeshing
(built when Debian's libcgal-dev is installed): 5 iterations, the target edge
length of equilateral triangles that cover the surface with the requested
number of vertices, sqrt(2 area / (sqrt(3) N)), and on fandisk the edges
sharper than 60 degrees kept as constrained polylines.  Both remeshes are
measured by the same code here: vertex count, mean and smallest minimum
angle, share of triangles below 30 degrees, share of interior vertices of
valence 6, edge-length variation, and the two-sided Hausdorff distance to
the input (inputs.remesh_deviation, as the filter's RemeshDeviation: vertices,
edge midpoints and triangle centres), over the bounding-box diagonal.

Our time is the whole filter (atlas included) on a fresh filter, then the
re-run after a change of the vertex count (the atlas kept) with its parts:
sampling (the thesis' interactive preview), triangulation, optimisation.
--big adds the 1.2M-triangle bunny (bunny00 after two Loop subdivisions) to
about 100k vertices.  --corpus instead writes one table of every real mesh
and every generated hard shape at 2,000 and 10,000 vertices, ours and
CGAL's side by side at about the same count (CGAL's target edge length
calibrated to the count (within 1%); Hausdorff both ways; the CAD parts' sharp edges
kept), for the guide's benchmarks page; with --noise N (e.g. 0.003) the
real meshes with Gaussian noise of N times the diagonal along their normals
instead (synthetic noisy scans); with --variants, shapes no setting was
tuned on: each real mesh stretched 6 times along x, flattened to 0.15 of its
height and quadric-decimated to a tenth of its triangles (where that stays
manifold and oriented), printed only.  --deviation D (a fraction of the
diagonal, e.g. 0.005) writes the table of the vertex counts that keep every
mesh within D both ways: the error-driven mode (MaximumDeviation D, the count
left to it), and the smallest count found for the uniform mode, the
curvature-adapted mode (max |k|, gamma 0.5) and CGAL (six tries each, the
count scaled by the deviation's ratio to D after each); sharp edges kept on
the CAD parts."""
import os
import sys
import time

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkFiltersCore import vtkTriangleFilter

import peers
import results
import timing  # noqa: F401 (the shared allocator settings)
from beltrami import vtkSurfaceRemeshing
from benchmark_parameterization import mesh

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "Python"))
import inputs  # noqa: E402

CGAL = os.path.join(HERE, "..", "..", "build", "bin", "beltrami-benchmark-cgal-isotropic-remeshing")


def arrays(data):
    """(points, triangles) as numpy arrays."""
    tri = vtkTriangleFilter()
    tri.SetInputData(data)
    tri.Update()
    cells = vtk_to_numpy(tri.GetOutput().GetPolys().GetConnectivityArray()).reshape(-1, 3)
    return vtk_to_numpy(tri.GetOutput().GetPoints().GetData()).astype(float), cells


def area(points, triangles):
    p = points[triangles]
    return 0.5 * np.linalg.norm(np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), axis=1).sum()


def quality(remesh, input_data, diagonal):
    """The figures of the issue, measured the same way for every remesher."""
    points, triangles = arrays(remesh)
    p = points[triangles]
    angles = []
    for k in range(3):
        u = p[:, (k + 1) % 3] - p[:, k]
        v = p[:, (k + 2) % 3] - p[:, k]
        cos = (u * v).sum(1) / np.maximum(np.linalg.norm(u, axis=1) * np.linalg.norm(v, axis=1), 1e-300)
        angles.append(np.degrees(np.arccos(np.clip(cos, -1.0, 1.0))))
    minimum = np.min(angles, axis=0)
    edges = np.sort(np.concatenate([triangles[:, [0, 1]], triangles[:, [1, 2]], triangles[:, [2, 0]]]), axis=1)
    unique, counts = np.unique(edges, axis=0, return_counts=True)
    boundary = np.zeros(len(points), bool)
    boundary[unique[counts == 1].ravel()] = True
    valence = np.bincount(unique.ravel(), minlength=len(points))
    interior = ~boundary & (valence > 0)
    lengths = np.linalg.norm(points[unique[:, 0]] - points[unique[:, 1]], axis=1)
    # (as the filter's RemeshDeviation: the remesh's triangle centres and
    # edge midpoints, the input's vertices, edge midpoints and triangle
    # centres; the input's polygons as fans, the triangles CGAL is given,
    # where the filter splits quads along their shorter diagonal: the
    # double torus's non-planar quads are two slightly different surfaces)
    to_input, from_input = inputs.remesh_deviation(inputs.polydata(*inputs.arrays_of(input_data)), remesh)
    return dict(vertices=int((valence > 0).sum()), mean_min=minimum.mean(), worst=minimum.min(),
                below30=100.0 * (minimum < 30.0).mean(), valence6=100.0 * (valence[interior] == 6).mean(),
                cv=lengths.std() / lengths.mean(), hausdorff=100.0 * max(from_input, to_input) / diagonal,
                to_input=100.0 * to_input / diagonal, from_input=100.0 * from_input / diagonal)


def cgal(data, count, features, calibrate=False):
    """(seconds, remesh) from CGAL, or None when it is not built.  The target
    edge length of equilateral triangles that cover the surface with `count`
    vertices; `calibrate`: then again, scaled by the square root of the
    vertex count it gave over `count` (CGAL's remeshes have 10-30% more
    vertices than that target implies), until the count is within 1% (at
    most six runs; the closest kept): a comparison at equal counts."""
    if not os.path.exists(CGAL):
        return None
    points, triangles = arrays(data)
    target = np.sqrt(2.0 * area(points, triangles) / (np.sqrt(3.0) * count))
    closest = None
    for attempt in range(6 if calibrate else 1):
        run, remesh = peers.run_on_off(CGAL, data, [repr(target), 5, 60 if features else 0], timeout=3600)
        if remesh is None:
            print("  CGAL failed: " + run.stderr.strip())
            return None
        miss = abs(remesh.GetNumberOfPoints() - count) / count
        if closest is None or miss < closest[0]:
            closest = (miss, float(run.stdout.split()[0]), remesh)
        if miss <= 0.01:
            break
        target *= np.sqrt(remesh.GetNumberOfPoints() / count)
    return closest[1], closest[2]


def ours(data, count, features):
    """(seconds of a fresh filter, the filter after a re-run with count - 1
    vertices and its seconds, the remesh of the first run)."""
    f = vtkSurfaceRemeshing()
    f.SetInputData(data)
    f.SetNumberOfVertices(count)
    f.SetSplitAtFeatures(features)
    start = time.perf_counter()
    f.Update()
    seconds = time.perf_counter() - start
    remesh = type(f.GetOutput())()
    remesh.DeepCopy(f.GetOutput())
    f.SetNumberOfVertices(count - 1)
    start = time.perf_counter()
    f.Update()
    return seconds, f, time.perf_counter() - start, remesh


def line(name, seconds, q):
    return ("  %-6s %8.2f s  %7d vertices  min angle mean %.2f worst %5.2f  <30deg %.3f%%  valence 6 %.1f%%  "
            "edge cv %.3f  Hausdorff %.3f%%" % (name, seconds, q["vertices"], q["mean_min"], q["worst"],
                                               q["below30"], q["valence6"], q["cv"], q["hausdorff"]))


def corpus_table(counts, noise=0.0, variants=False):
    """Every real mesh (the shared corpus and Testing/Data) and the shapes
    made to break a remesher, uniform at each count, ours and CGAL's: one
    Markdown table (Hausdorff both ways in % of the diagonal, as the
    filter's RemeshDeviation: the remesh's triangle centres and edge
    midpoints to the input, the input's vertices, edge midpoints and
    triangle centres to the remesh).  noise > 0: the real meshes only, each
    with that noise along its normals (a fraction of the diagonal;
    test_corpus_sweep.noisy)."""
    from test_corpus_sweep import CAD, noisy
    meshes = [(os.path.basename(p), inputs.read_off(p)) for p in inputs.corpus_paths()]
    if noise > 0.0:
        meshes = [(name, noisy(data, noise)) for name, data in meshes]
    elif variants:
        meshes = [variant for name, data in meshes for variant in inputs.variants_of(name, data)]
    else:
        meshes += [(name, inputs.polydata(*shape)) for name, shape in inputs.hard_shapes().items()]
    columns = ["mesh", "count", "remesher", "vertices", "to input %", "from input %", "worst angle",
               "mean min angle", "<30 deg %", "valence 6 %", "seconds"]
    print("| " + " | ".join(columns) + " |")
    print("|" + "---|" * len(columns))
    table = []
    for name, data in meshes:
        bounds = np.array(data.GetBounds())
        diagonal = np.linalg.norm(bounds[1::2] - bounds[::2])
        for count in counts:
            rows = []
            f = vtkSurfaceRemeshing()
            f.SetInputData(data)
            f.SetNumberOfVertices(count)
            features = name.split(" ")[0] in CAD
            f.SetSplitAtFeatures(features)
            f.GlobalWarningDisplayOff()
            start = time.perf_counter()
            f.Update()
            rows.append(("ours", time.perf_counter() - start, f.GetOutput()))
            peer = cgal(inputs.polydata(*inputs.arrays_of(data)), count, features, True)  # (triangles: its input)
            if peer:
                rows.append(("CGAL", peer[0], peer[1]))
            for who, seconds, remesh in rows:
                if remesh.GetNumberOfPoints() == 0:
                    row = [name, count, who, "refused", "", "", "", "", "", "", round(seconds, 2)]
                else:
                    q = quality(remesh, data, diagonal)
                    row = [name, count, who, q["vertices"], round(q["to_input"], 3), round(q["from_input"], 3),
                           round(q["worst"], 1), round(q["mean_min"], 1), round(q["below30"], 2),
                           round(q["valence6"], 1), round(seconds, 2)]
                table.append(row)
                print("| " + " | ".join(map(str, row)) + " |")
            sys.stdout.flush()
    if variants:
        return
    if noise > 0.0:
        results.save("remeshing_noisy_corpus", "Remeshing", "Isotropic remeshing of every corpus mesh, noisy",
                     "CGAL 5.5 isotropic_remeshing (5 iterations, the equilateral target edge length of the count)",
                     "the shared corpus and Testing/Data, each with Gaussian noise of %g%% of its diagonal along its "
                     "normals (seed 1); the CAD parts with their edges sharper than 60 degrees kept" % (100 * noise),
                     columns, table, "As the corpus table; the deviations are to the noisy input.")
        return
    results.save("remeshing_corpus", "Remeshing", "Isotropic remeshing of every corpus mesh and hard shape",
                 "CGAL 5.5 isotropic_remeshing (5 iterations, the equilateral target edge length of the count)",
                 "the shared corpus, Testing/Data and the generated hard shapes (spikes, fingers, a thin neck and "
                 "handle, a speck, a thin plate, huge and tiny coordinates); the CAD parts with their edges sharper "
                 "than 60 degrees kept", columns, table,
                 "Hausdorff both ways in % of the diagonal: 'to input' the remesh's triangle centres and edge "
                 "midpoints, 'from input' the input's vertices, edge midpoints and triangle centres. CGAL's "
                 "target edge length calibrated to give the count within 1% where six runs reach it.")


def remesher(data, features, **settings):
    """A quiet vtkSurfaceRemeshing on `data` (sharp edges kept where
    `features`) with the settings given by name."""
    f = vtkSurfaceRemeshing()
    f.SetInputData(data)
    f.SetSplitAtFeatures(features)
    f.GlobalWarningDisplayOff()
    for key, value in settings.items():
        getattr(f, "Set" + key)(value)
    return f


def smallest_count(run, bound, start, tries=6):
    """(vertices, deviation %) of the fewest vertices found within `bound`
    (%) by run(count) -> (vertices, deviation %), over `tries` counts: each
    the last scaled by the deviation's ratio to the bound (it falls about
    as 1/count); None when none met it."""
    best, count = None, start
    for _ in range(tries):
        vertices, deviation = run(int(count))
        if deviation is not None and deviation <= bound and (best is None or vertices < best[0]):
            best = (vertices, deviation)
        ratio = deviation / bound if deviation else 4.0
        count = max(10, count * (min(4.0, 1.1 * ratio) if ratio > 1 else max(0.7, 1.05 * ratio)))
    return best


def deviation_table(bound):
    """The counts each mode and CGAL need to keep every mesh within `bound`
    (fraction of the diagonal) both ways: one Markdown table."""
    from test_corpus_sweep import CAD
    meshes = [(os.path.basename(p), inputs.read_off(p)) for p in inputs.corpus_paths()]
    meshes += [(name, inputs.polydata(*shape)) for name, shape in inputs.hard_shapes().items()]
    percent = 100.0 * bound
    print("| mesh | error-driven: vertices | deviation % | rounds | seconds | uniform | curvature (max k, 0.5) "
          "| CGAL |")
    print("|---|---|---|---|---|---|---|---|")

    def measure(remesh, data, diagonal):
        if remesh.GetNumberOfPoints() == 0:
            return remesh.GetNumberOfPoints(), None
        q = quality(remesh, data, diagonal)
        return q["vertices"], max(q["to_input"], q["from_input"])

    def reported(f):
        """(vertices, deviation %) as the filter measured it (the corpus
        sweep checks it against VTK's distances)."""
        out = f.GetOutput()
        if out.GetNumberOfPoints() == 0:
            return 0, None
        d = out.GetFieldData().GetArray("RemeshDeviation")
        return out.GetNumberOfPoints(), 100.0 * max(d.GetValue(0), d.GetValue(1))

    rows = []
    for name, data in meshes:
        bounds = np.array(data.GetBounds())
        diagonal = np.linalg.norm(bounds[1::2] - bounds[::2])
        features = name in CAD

        f = remesher(data, features, NumberOfVertices=0, MaximumDeviation=bound)
        start = time.perf_counter()
        f.Update()
        seconds = time.perf_counter() - start
        vertices, deviation = reported(f)
        rounds = f.GetOutput().GetFieldData().GetArray("RemeshRounds")
        driven = "refused | | | %.2f" % seconds if deviation is None else "%d | %.3f | %d | %.2f" % (
            vertices, deviation, rounds.GetNumberOfTuples(), seconds)
        cells = []
        for mode in ({}, {"Importance": vtkSurfaceRemeshing.MAXIMUM_CURVATURE, "Gamma": 0.5}):
            g = remesher(data, features, **mode)  # one filter a mode: its atlas kept between the counts

            def run(count, g=g):
                g.SetNumberOfVertices(count)
                g.Update()
                return reported(g)
            cells.append(smallest_count(run, percent, max(vertices, 100)))
        cgal_input = inputs.polydata(*inputs.arrays_of(data))

        def run_cgal(count):
            peer = cgal(cgal_input, count, features)
            return measure(peer[1], data, diagonal) if peer else (0, None)
        cells.append(smallest_count(run_cgal, percent, max(vertices, 100)) if os.path.exists(CGAL) else None)
        print("| %s | %s | %s |" % (name, driven, " | ".join(
            "%d (%.3f%%)" % cell if cell else "not met" for cell in cells)))
        sys.stdout.flush()
        rows.append([name] + (["refused", "", ""] if deviation is None else [vertices, round(deviation, 3),
                                                                            rounds.GetNumberOfTuples()])
                    + [round(seconds, 2)] + [cell[0] if cell else "not met" for cell in cells])
    save_deviation_table(rows, bound)


def save_deviation_table(rows, bound):
    """deviation_table's rows into docs/benchmarks/remeshing_deviation.json."""
    results.save("remeshing_deviation", "Remeshing",
                 "Error-driven remeshing: vertices within %.1f%% of the diagonal" % (100 * bound),
                 "CGAL isotropic_remeshing", "the shared corpus and the generated hard shapes",
                 ["mesh", "error-driven vertices", "deviation %", "rounds", "seconds", "uniform", "curvature (max k, 0.5)",
                  "CGAL"], rows,
                 "Error-driven: MaximumDeviation %g with the count left to it (its own deviation, the larger of the "
                 "two); the other columns: the fewest vertices found within the bound over six counts each (the "
                 "count scaled by the deviation's ratio to the bound after each); sharp edges kept on the CAD parts."
                 % bound)


def main(argv):
    if "--deviation" in argv:
        deviation_table(float(argv[argv.index("--deviation") + 1]))
        return 0
    if "--corpus" in argv:
        corpus_table([2000, 10000], float(argv[argv.index("--noise") + 1]) if "--noise" in argv else 0.0,
                     "--variants" in argv)
        return 0
    cases = [("bunny00.off", 0, 10000, False), ("mushroom.off", 0, 10000, False), ("eight.off", 0, 10000, False),
             ("fandisk.off", 0, 10000, True), ("bunny00.off", 0, 2000, False)]
    if "--big" in argv:
        cases.append(("bunny00.off", 2, 100000, False))
    if not os.path.exists(CGAL):
        print("(CGAL comparison skipped: %s not built; apt install libcgal-dev and rebuild)" % CGAL)
    rows = []
    for name, levels, count, features in cases:
        data = mesh(name, levels)
        bounds = np.array(data.GetBounds())
        diagonal = np.linalg.norm(bounds[1::2] - bounds[::2])
        print("%s%s (%d triangles) to %d vertices%s:" % (
            name, ", %d Loop levels" % levels if levels else "", data.GetNumberOfCells(), count,
            ", sharp edges kept" if features else ""))
        seconds, f, rerun, remesh = ours(data, count, features)
        peer = cgal(data, count, features)
        parts = f.GetOutput().GetFieldData().GetArray("RemeshSeconds")
        label = name[:-4] + (" (%d Loop levels)" % levels if levels else "") + (", sharp edges kept" if features else "")
        for who, s, q in [("ours", seconds, quality(remesh, data, diagonal))] + (
                [("CGAL", peer[0], quality(peer[1], data, diagonal))] if peer else []):
            rows.append([label, count, who, q["vertices"], q["worst"], q["mean_min"], q["below30"], q["valence6"],
                         q["cv"], q["hausdorff"], s])
        print(line("ours", seconds, quality(remesh, data, diagonal)) +
              "\n         re-run with another count, atlas kept: %.3f s (sampling %.3f, triangulation %.3f, "
              "optimisation %.3f)" % (rerun, parts.GetValue(0), parts.GetValue(1), parts.GetValue(2)))
        if peer:
            print(line("CGAL", peer[0], quality(peer[1], data, diagonal)) +
                  "\n         ours %.1fx faster than CGAL" % (peer[0] / seconds))
        sys.stdout.flush()
    results.save("remeshing" + ("_big" if "--big" in argv else ""), "Remeshing", "Isotropic remeshing to a vertex count",
                 "CGAL 5.5 isotropic_remeshing (5 iterations, the equilateral target edge length of the count)",
                 "real meshes; fandisk with its edges sharper than 60 degrees kept",
                 ["mesh", "count", "remesher", "vertices", "worst angle", "mean min angle", "<30 deg %",
                  "valence 6 %", "edge length cv", "Hausdorff % diag.", "seconds"], rows,
                 "Both remeshes measured by the same code. Ours: the whole filter (atlas included) on a fresh filter.")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
