"""SurfaceLineDrawing on surfaces split over the ranks of pvbatch (issue
27/28): each rank computes the curvatures and their derivatives of its own
piece (with the ring of the others' triangles around its edge), finds the
segments of the triangles and edges it owns, and rank 0 chains the gathered
segments.  Run by ctest with 1, 2, 3 and 4 ranks (mpirun --oversubscribe).

Checked against plain VTK on the whole surface (a serial run): the bunny
(contours, suggestive contours and highlights, ridges, valleys
with hysteresis and a minimum length, which need whole polylines) and
fandisk (creases) and the mushroom (boundaries), cut by RedistributeDataSet (points where three or more
pieces meet from 3 ranks on; also into overlapping pieces), and a sphere per
rank: the same polylines per line type (count,
closed ones, points, lengths, strengths: every point of each drawing within
1e-9 of the diagonal of a point of the other), the per-point arrays of
output 1 (CurvatureDerivative, NdotV, RadialCurvature...) on every piece;
a new camera re-runs only the per-view pass; a rank with an empty piece; a
NaN point (no hang); Visibility (each rank casts the rays through its own
triangles: the serial visible and hidden lines, also where one rank's
sphere hides another's, and no rank holds more than its piece) and the
Line Drawing Writer (one page, by rank 0);
what each rank holds (with 4 ranks no rank more than a third of the points
and triangles)."""
import builtins  # (ParaView's programmable filters put numpy_interface's max, abs... in __main__)
import os
import sys

from paraview.simple import *  # noqa: F401,F403
from paraview import servermanager
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonDataModel import vtkPointLocator, vtkPolyData
from vtkmodules.vtkCommonCore import vtkPoints
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from configure import (DISJOINT_SPHERES, check, configured, empty_rank_partitions, moved_points,  # noqa: E402
                       piecewise_source, rank_rows)

DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "Data")
LoadPlugin(os.environ["BELTRAMI_PLUGIN"], ns=globals())
from beltrami import vtkLineDrawingWriter, vtkSurfaceLineDrawing  # noqa: E402

ranks = servermanager.ActiveConnection.GetNumberOfDataPartitions()
SETTINGS = dict(SuggestiveHighlights=1, Ridges=1, Valleys=1, HysteresisRatio=0.5, MinimumLineLength=2.0)


def points(polydata):
    return vtk_to_numpy(polydata.GetPoints().GetData()).astype(float)


def nearest(reference, query):
    """For each query point, the distance to the nearest reference point and its index."""
    cloud = vtkPolyData()
    p = vtkPoints()
    p.SetDataTypeToDouble()
    for x in reference:
        p.InsertNextPoint(*x)
    cloud.SetPoints(p)
    locator = vtkPointLocator()
    locator.SetDataSet(cloud)
    locator.BuildLocator()
    ids = np.array([locator.FindClosestPoint(*x) for x in query], dtype=int)
    return (np.linalg.norm(reference[ids] - query, axis=1) if len(ids) else np.zeros(0)), ids


def per_type(lines):
    """Per line type: (polylines, closed ones, points, total length, points, point strengths)."""
    out = {}
    if lines.GetNumberOfCells() == 0:
        return out
    p = points(lines)
    kinds = vtk_to_numpy(lines.GetCellData().GetArray("LineType"))
    strength = vtk_to_numpy(lines.GetPointData().GetArray("Strength"))
    offsets = vtk_to_numpy(lines.GetLines().GetOffsetsArray())
    ids = vtk_to_numpy(lines.GetLines().GetConnectivityArray())
    for kind in sorted(set(kinds)):
        count = closed = 0
        length = 0.0
        used = []
        for c in np.nonzero(kinds == kind)[0]:
            cell = ids[offsets[c]:offsets[c + 1]]
            count += 1
            closed += int(cell[0] == cell[-1] and len(cell) > 2)
            length += np.linalg.norm(np.diff(p[cell], axis=0), axis=1).sum()
            used.extend(cell)
        used = np.unique(used)
        out[int(kind)] = (count, closed, len(used), length, p[used], strength[used])
    return out


def serial(polydata, camera):
    return configured(vtkSurfaceLineDrawing(), polydata, CameraPosition=camera, **SETTINGS)


def compare(label, drawing, whole, camera, diagonal):
    """The split drawing against the serial one; returns the fetched lines.
    With Curvature Smoothing (the default) the fields come from a faired
    copy, which the distributed solve gives to its tolerance (residual
    reduced by 1e-8, mixed precision): the lines agree to 1e-7 of the
    diagonal (measured: 5e-9) and their strengths to 1e-5, without it to
    1e-9 and 1e-7."""
    close = 1e-9 if SETTINGS.get("CurvatureSmoothing", 0.5) == 0 else 1e-7
    lines = servermanager.Fetch(drawing)
    reference = serial(whole, camera)
    ours, theirs = per_type(lines), per_type(reference.GetOutput())
    check(sorted(ours) == sorted(theirs) and len(theirs) >= 1, "%s: the same line types %s" % (label, sorted(ours)))
    for kind in theirs:
        a, b = ours[kind], theirs[kind]
        check(a[:3] == b[:3] and builtins.abs(a[3] - b[3]) <= close * b[3],
              "%s over %d rank(s), type %d: %d polylines (%d closed), %d points, length %.6f as serial %s %.6f"
              % (label, ranks, kind, a[0], a[1], a[2], a[3], b[:3], b[3]))
        there, index = nearest(b[4], a[4])
        back, _ = nearest(a[4], b[4])
        # (A crease's strength is its edge's angle: where two meet, the
        # point takes the one the chain comes from, which follows the
        # direction the chain is walked in, so the values are compared as sets.)
        same = (np.array_equal(np.unique(np.round(a[5], 4)), np.unique(np.round(b[5], 4))) if kind == 6
                else np.abs(a[5] - b[5][index]).max() <= 100 * close * builtins.max(1.0, np.abs(b[5]).max()))
        far = builtins.max(there.max(), back.max()) / diagonal
        check(far <= close and same, "%s, type %d: every point (within %.1e of the diagonal) and strength as serial"
              % (label, kind, far), quiet=True)
    # Output 1: every piece with its arrays, as the serial surface's.
    pieces = servermanager.Fetch(drawing, idx=1)
    whole_out = reference.GetOutput(1)
    _, index = nearest(points(whole_out), points(pieces))
    for name in ("CurvatureDerivative", "NdotV", "RadialCurvature", "RadialCurvatureDerivative"):
        a = vtk_to_numpy(pieces.GetPointData().GetArray(name)).astype(float)
        b = vtk_to_numpy(whole_out.GetPointData().GetArray(name))[index]
        both = np.isfinite(a) & np.isfinite(b)
        off = np.abs(a[both] - b[both]).max() / builtins.max(1.0, np.abs(b[both]).max())
        # (With Curvature Smoothing: the faired copy's normals and
        # derivatives, which the distributed solve gives to its tolerance
        # times the system's condition: measured up to 1.1e-5, on fandisk's
        # rounded creases.)
        check((np.isfinite(a) == np.isfinite(b)).all() and off <= 1000 * close,
              "%s: %s on every piece as serial (%.1e of its largest)" % (label, name, off), quiet=True)
    return lines


def run(path, label, cameras, partitions=0, mode=None):
    """`path` (a bundled mesh, cut by RedistributeDataSet into `partitions`
    pieces (0: one per rank) with its BoundaryMode `mode`; or a source
    whose pieces are the ranks') drawn from each camera against serial."""
    source = OpenDataFile(os.path.join(DATA, path)) if isinstance(path, str) else path
    whole = servermanager.Fetch(source)
    b = whole.GetBounds()
    diagonal = np.linalg.norm([b[1] - b[0], b[3] - b[2], b[5] - b[4]])
    if isinstance(path, str):
        redistributed = RedistributeDataSet(Input=source)
        redistributed.NumberOfPartitions = partitions
        if mode:
            redistributed.BoundaryMode = mode
        split = ExtractSurface(Input=redistributed)
    else:
        split = source
    drawing = SurfaceLineDrawing(Input=split, CameraPosition=cameras[0], **SETTINGS)
    drawing.UpdatePipeline()
    compare(label, drawing, whole, cameras[0], diagonal)
    builds = drawing.GetClientSideObject().GetGeometryBuilds()
    for camera in cameras[1:]:
        drawing.CameraPosition = camera
        drawing.UpdatePipeline()
        compare("%s, camera %s" % (label, camera), drawing, whole, camera, diagonal)
    check(drawing.GetClientSideObject().GetGeometryBuilds() == builds, "%s: a new camera re-runs the per-view pass only" % label)
    return drawing, whole


bunny_cameras = ((0.0, 0.02, 0.4), (0.4, 0.1, 0.0))
drawing, whole = run("bunny00.off", "bunny", bunny_cameras)
run("fandisk.off", "fandisk", ((3.0, 2.0, 4.0),))
run("mushroom.off", "mushroom", ((0.5, 0.3, 1.0),))
# Pieces that overlap (RedistributeDataSet's "Assign to all regions" copies
# the cells on a cut to every piece they touch, unmarked): each drawn once.
run("bunny00.off", "bunny, overlapping pieces", bunny_cameras[:1], mode="Assign to all regions")
# Pieces that touch nowhere: a sphere per rank.
run(piecewise_source(DISJOINT_SPHERES), "a sphere per rank", ((1.5, 2.0, 6.0),))

if ranks > 1:
    owned, ghosts, triangles = rank_rows(OutputPort(drawing, 1), "LineDrawingDistribution", ("Owned", "Ghosts", "Triangles"))
    check((owned >= 0).all() and owned.sum() == whole.GetNumberOfPoints(), "each point owned by one rank (%s)" % owned)
    check(ranks != 4 or ((owned + ghosts).max() <= whole.GetNumberOfPoints() / 3
                         and triangles.max() <= whole.GetNumberOfCells() / 3),
          "no rank holds more than a third: points %s of %d, triangles %s of %d"
          % (owned + ghosts, whole.GetNumberOfPoints(), triangles, whole.GetNumberOfCells()))
    run("bunny00.off", "bunny on %d of %d ranks" % (empty_rank_partitions(ranks), ranks), bunny_cameras[:1],
        partitions=empty_rank_partitions(ranks))

# Visibility: each rank casts rank 0's rays through its own triangles, so
# the surface is not gathered: the serial visible and hidden lines.  The
# Line Drawing Writer writes them once, on rank 0.
SETTINGS["Visibility"] = vtkSurfaceLineDrawing.VISIBLE_AND_HIDDEN_LINES


def hidden_lines(drawing):
    hidden = servermanager.Fetch(drawing).GetCellData().GetArray("Hidden")
    return [hidden.GetValue(i) for i in range(hidden.GetNumberOfTuples())] if hidden else []


# A sphere per rank, in a row seen along it: the nearest hides the others.
spheres, _ = run(piecewise_source(DISJOINT_SPHERES), "spheres in a row, visibility", ((20.0, 0.6, 0.4),))
flags = hidden_lines(spheres)
check((ranks == 1 and flags == [0]) or ranks - 1 <= builtins.sum(flags) < len(flags),
      "the spheres in a row: %d of %d lines hidden over %d rank(s)" % (builtins.sum(flags), len(flags), ranks))
drawing, whole = run("bunny00.off", "bunny with visibility", bunny_cameras[:1])
flags = hidden_lines(drawing)
check(0 < builtins.sum(flags) < len(flags), "visible and hidden lines over %d rank(s)" % ranks)
if ranks == 4:
    owned, ghosts, triangles = rank_rows(OutputPort(drawing, 1), "LineDrawingDistribution", ("Owned", "Ghosts", "Triangles"))
    check((owned + ghosts).max() <= whole.GetNumberOfPoints() / 3 and triangles.max() <= whole.GetNumberOfCells() / 3,
          "with visibility no rank holds more than a third: points %s of %d, triangles %s of %d"
          % (owned + ghosts, whole.GetNumberOfPoints(), triangles, whole.GetNumberOfCells()))
folder = os.environ.get("BELTRAMI_TEST_OUTPUT_DIR", "/tmp")
page, serial_page = (os.path.join(folder, "distributed_drawing_%s.svg" % k) for k in (ranks, "%d_serial" % ranks))
SaveData(page, proxy=drawing)  # (rank 0 writes)
reference = serial(whole, bunny_cameras[0])
writer = vtkLineDrawingWriter()
writer.SetInputConnection(reference.GetOutputPort())
writer.SetFileName(serial_page)
writer.Write()
del SETTINGS["Visibility"]
texts = []
for path in (page, serial_page):
    with open(path) as f:
        texts.append(f.read())
counts = [(t.count("<path"), t.count(" L")) for t in texts]
check(texts[0].startswith("<?xml") and texts[0].rstrip().endswith("</svg>") and counts[0] == counts[1]
      and counts[0][0] > 20, "the Line Drawing Writer wrote the serial page over %d rank(s) (paths, segments %s, "
      "serial %s)" % (ranks, counts[0], counts[1]))

# A NaN point (made after RedistributeDataSet, whose k-d tree does not take
# one): no hang, a defined output: the lines elsewhere (the NaN's triangles
# have none), or, where the NaN is at the edge of a piece and cannot be
# matched to the other pieces' points, an error on every rank and no lines.
nan = "p[(p == np.array(%r)).all(axis=1)] = np.nan" % (points(whole)[3000].tolist(),)
split = ExtractSurface(Input=RedistributeDataSet(Input=OpenDataFile(os.path.join(DATA, "bunny00.off"))))
drawing = SurfaceLineDrawing(Input=moved_points(split, nan), CameraPosition=bunny_cameras[0])
drawing.UpdatePipeline()
lines = servermanager.Fetch(drawing)
check(lines.GetNumberOfCells() == 0 or np.isfinite(points(lines)).all(),
      "a NaN point: %d polylines, none through it" % lines.GetNumberOfCells())
print("distributed line drawing test passed")
