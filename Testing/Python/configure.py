"""The helpers the Python tests share: a VTK filter set up from keyword
settings, the way the tests and benchmarks describe their runs, and the
checks of the pvpython/pvbatch scripts."""
import sys


def configured(f, source=None, update=True, **settings):
    """f with Set<Key>(value) for every keyword, fed by source (a data
    object or an algorithm; None: left as it is), updated unless update is
    False.  Returns f."""
    if source is not None:
        if hasattr(source, "GetOutputPort"):
            f.SetInputConnection(source.GetOutputPort())
        else:
            f.SetInputData(source)
    for key, value in settings.items():
        getattr(f, "Set" + key)(value)
    if update:
        f.Update()
    return f


def check(condition, message, quiet=False):
    """A pvpython/pvbatch script's check: "FAILED: message" and exit 1 when
    `condition` fails (ctest's FAIL_REGULAR_EXPRESSION), else "ok: message"
    unless quiet."""
    if not condition:
        print("FAILED: " + message)
        sys.exit(1)
    if not quiet:
        print("ok: " + message)


def report(data, name):
    """The values of the field array `name` of `data`."""
    a = data.GetFieldData().GetArray(name)
    return [a.GetValue(k) for k in range(a.GetNumberOfTuples())]


def fetch_pieces(proxy):
    """Every rank's piece of a pvbatch proxy's output (unstructured grid or
    image), joined: written as a parallel XML file and read back
    (servermanager.Fetch gives rank 0's piece of those only)."""
    import os
    import tempfile
    from paraview.simple import SaveData
    from vtkmodules.vtkIOXML import vtkXMLPImageDataReader, vtkXMLPUnstructuredGridReader
    image = proxy.GetDataInformation().GetDataClassName() == "vtkImageData"
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "pieces.pvti" if image else "pieces.pvtu")
        SaveData(path, proxy=proxy)
        reader = vtkXMLPImageDataReader() if image else vtkXMLPUnstructuredGridReader()
        reader.SetFileName(path)
        reader.Update()
        return reader.GetOutput()


def empty_rank_partitions(ranks):
    """A partition count for RedistributeDataSet that leaves a rank empty:
    it cuts into a power of two of pieces (3 asked on 4 ranks gave 4
    non-empty pieces), so the largest power of two below `ranks`."""
    count = 1
    while 2 * count < ranks:
        count *= 2
    return count


def rank_rows(proxy, array, names):
    """Per rank of a pvbatch run, the first len(names) values of the field
    array `array` of the proxy's output (-1 where it has none): a numpy
    array (of doubles) per name, one value per rank."""
    from paraview import servermanager
    from paraview.simple import ProgrammableFilter
    from vtkmodules.util.numpy_support import vtk_to_numpy
    rows = ProgrammableFilter(Input=proxy, OutputDataSetType="vtkPolyData")
    rows.Script = """
from vtkmodules.vtkCommonCore import vtkDoubleArray, vtkPoints
d = self.GetInput().GetFieldData().GetArray(%r)
out = self.GetOutput()
p = vtkPoints()
p.InsertNextPoint(0.0, 0.0, 0.0)
out.SetPoints(p)
for k, name in enumerate(%r):
    a = vtkDoubleArray()
    a.SetName(name)
    a.InsertNextValue(d.GetTuple1(k) if d else -1)
    out.GetPointData().AddArray(a)
""" % (array, list(names))
    table = servermanager.Fetch(rows).GetPointData()
    return [vtk_to_numpy(table.GetArray(name)) for name in names]


def check_split_flow(label, ranks, result, whole, reference, array, tolerance, least_risk):
    """The checks of a graph flow split over `ranks` ranks of pvbatch
    (`result`: every rank's piece, joined) against the serial run
    (`reference`, of the `whole` input with its point array "mask"): the
    pieces cover the input (points matched by coordinates), the serial run
    smoothed, the values equal to `tolerance` of its largest change, the
    same steps, noise estimate and settings (and with the least-risk stop
    the same estimated errors), the masked points kept."""
    import numpy as np
    from vtkmodules.util.numpy_support import vtk_to_numpy
    index = {tuple(x): i for i, x in enumerate(vtk_to_numpy(whole.GetPoints().GetData()))}
    ids = np.array([index.get(tuple(x), -1) for x in vtk_to_numpy(result.GetPoints().GetData())])
    check(ids.min() >= 0 and len(set(ids)) == whole.GetNumberOfPoints(), "%s: the pieces cover the input" % label)
    ours = vtk_to_numpy(result.GetPointData().GetArray(array))
    theirs = vtk_to_numpy(reference.GetPointData().GetArray(array))[ids]
    before = vtk_to_numpy(whole.GetPointData().GetArray(array))
    moved = np.abs(vtk_to_numpy(reference.GetPointData().GetArray(array)) - before).max()
    difference = np.abs(ours - theirs).max()
    check(moved > 0.01, "%s: the serial run smoothed the data (largest change %.3g)" % (label, moved))
    check(difference <= tolerance * moved, "%s over %d rank(s) equals the serial result: difference %.3g <= %.0e x %.3g"
          % (label, ranks, difference, tolerance, moved))
    for name in ("FlowIterations", "EstimatedNoiseLevel", "FlowNoiseLevel", "FlowContrastScale"):
        a, b = report(result, name), report(reference, name)
        check(np.allclose(a, b, rtol=1e-9, atol=0), "%s: %s %s as serial %s" % (label, name, a, b))
    if least_risk:
        a, b = report(result, "FlowEstimatedError"), report(reference, "FlowEstimatedError")
        check(np.allclose(a, b, rtol=1e-6), "%s: estimated error %s as serial %s" % (label, a, b))
    kept = vtk_to_numpy(whole.GetPointData().GetArray("mask"))[ids] != 0
    check(np.array_equal(ours[kept], before[ids][kept]), "%s: fixed points kept" % label)


# A height field (a disk) cut so that one rank's piece is a single triangle
# whose corners all belong to lower ranks' pieces (and, on 4 ranks, the last
# piece empty): a piece that owns no point.
LONE_TRIANGLE_GRID = """
import numpy as np
from vtkmodules.vtkCommonCore import vtkPoints
from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkPolyData
def height_field(piece, pieces):
    n = 24
    u, v = np.meshgrid(np.linspace(0.0, 1.0, n), np.linspace(0.0, 1.0, n), indexing="ij")
    z = 0.1 * np.sin(6.0 * u) * np.cos(5.0 * v) + 0.02 * np.sin(37.0 * u * v)
    xyz = np.column_stack([u.ravel(), v.ravel(), z.ravel()])
    cells, centres = [], []
    for i in range(n - 1):
        for j in range(n - 1):
            a, b, c, d = i * n + j, (i + 1) * n + j, (i + 1) * n + j + 1, i * n + j + 1
            for t in ((a, b, c), (a, c, d)):
                cells.append(t)
                centres.append(xyz[list(t)].mean(0))
    lone = (n // 2) * 2 * (n - 1) + 2 * (n // 2)  # a triangle inside, next to the cut x = 0.5
    owner = [0 if (k != lone and c[0] < 0.5) or pieces == 1 else 1 if k != lone else 2 for k, c in enumerate(centres)]
    if pieces == 2:
        owner = [0 if k != lone else 1 for k in range(len(cells))]
    keep = [k for k in range(len(cells)) if owner[k] == piece]
    used = sorted({p for k in keep for p in cells[k]})
    index = {p: m for m, p in enumerate(used)}
    out = vtkPolyData()
    pts = vtkPoints()
    pts.SetDataTypeToDouble()
    for p in used:
        pts.InsertNextPoint(*xyz[p])
    polys = vtkCellArray()
    for k in keep:
        polys.InsertNextCell(3, [index[p] for p in cells[k]])
    out.SetPoints(pts)
    out.SetPolys(polys)
    return out
"""


def piecewise_source(code):
    """A pvbatch programmable source that honours piece requests: `code`
    defines make(piece, pieces), each rank's piece as a vtkPolyData (each
    rank makes its own)."""
    from paraview.simple import ProgrammableSource
    source = ProgrammableSource(OutputDataSetType="vtkPolyData")
    source.ScriptRequestInformation = """
from vtkmodules.vtkCommonExecutionModel import vtkAlgorithm
self.GetOutputInformation(0).Set(vtkAlgorithm.CAN_HANDLE_PIECE_REQUEST(), 1)
"""
    source.Script = code + """
from vtkmodules.vtkCommonExecutionModel import vtkStreamingDemandDrivenPipeline as sddp
info = self.GetOutputInformation(0)
self.GetOutput().ShallowCopy(make(info.Get(sddp.UPDATE_PIECE_NUMBER()), info.Get(sddp.UPDATE_NUMBER_OF_PIECES())))
"""
    return source


def lone_triangle_source():
    """The height field above, each rank making its own piece."""
    return piecewise_source(LONE_TRIANGLE_GRID + "\nmake = height_field\n")


# Pieces that touch nowhere: each rank's piece a sphere of its own, side by
# side (the whole: as many spheres as pieces).
DISJOINT_SPHERES = """
def make(piece, pieces):
    from vtkmodules.vtkFiltersSources import vtkSphereSource
    s = vtkSphereSource()
    s.SetThetaResolution(30)
    s.SetPhiResolution(20)
    s.SetCenter(3.0 * piece, 0.0, 0.0)
    s.Update()
    return s.GetOutput()
"""


# A flat disk whose ragged rim (2,000 points, every other one 1% further out)
# is fanned from one centre point through a ring, with noise of 0.3% across
# it (seed 11): long slivers round a point of valence 2,000, as a hole filled
# by a fan.  The whole on piece 0 (RedistributeDataSet splits it).
FANNED_DISK = """
def make(piece, pieces):
    import numpy as np
    from vtkmodules.util.numpy_support import numpy_to_vtk, numpy_to_vtkIdTypeArray
    from vtkmodules.vtkCommonCore import vtkPoints
    from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkPolyData
    out = vtkPolyData()
    if piece != 0:
        return out
    n = 2000
    a = 2 * np.pi * np.arange(n) / n
    rim = 1.0 + 0.01 * (np.arange(n) % 2)
    p = np.vstack([[[0.0, 0.0, 0.0]], np.c_[0.5 * np.cos(a), 0.5 * np.sin(a), np.zeros(n)],
                   np.c_[rim * np.cos(a), rim * np.sin(a), np.zeros(n)]])
    p[:, 2] = np.random.default_rng(11).normal(0.0, 0.003, len(p))
    i = np.arange(n)
    j = (i + 1) % n
    t = np.vstack([np.c_[np.zeros(n, dtype=np.int64), 1 + i, 1 + j], np.c_[1 + i, 1 + n + i, 1 + n + j],
                   np.c_[1 + i, 1 + n + j, 1 + j]]).astype(np.int64)
    points = vtkPoints()
    points.SetData(numpy_to_vtk(p, deep=True))
    cells = vtkCellArray()
    cells.SetData(numpy_to_vtkIdTypeArray(np.arange(0, 3 * len(t) + 1, 3, dtype=np.int64), deep=True),
                  numpy_to_vtkIdTypeArray(t.ravel(), deep=True))
    out.SetPoints(points)
    out.SetPolys(cells)
    return out
"""

def lone_triangle_whole():
    """The whole height field as one poly data (for the serial run)."""
    from vtkmodules.vtkFiltersCore import vtkCleanPolyData
    namespace = {}
    exec(LONE_TRIANGLE_GRID, namespace)
    clean = vtkCleanPolyData()
    clean.SetInputData(namespace["height_field"](0, 1))
    clean.Update()
    return clean.GetOutput()


def moved_points(source, change):
    """`source` with its points changed by `change` (Python code on p, the
    piece's n x 3 points) on every rank's piece (and in the serial run)."""
    from paraview.simple import ProgrammableFilter
    f = ProgrammableFilter(Input=source)
    f.Script = """
import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy
out = self.GetOutput()
out.DeepCopy(self.GetInput())
if out.GetNumberOfPoints():
    p = vtk_to_numpy(out.GetPoints().GetData())
    %s
    out.GetPoints().Modified()
""" % change
    return f


def with_point_arrays(source, arrays):
    """`source` with point arrays computed on every rank's piece (and in a
    serial run) from its n x 3 points p: `arrays` maps each name to a numpy
    expression in p (np is numpy)."""
    from paraview.simple import ProgrammableFilter
    f = ProgrammableFilter(Input=source)
    f.Script = """
import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
out = self.GetOutput()
out.ShallowCopy(self.GetInput())
if out.GetNumberOfPoints():
    p = vtk_to_numpy(out.GetPoints().GetData()).astype(float)
    for name, expression in %r.items():
        a = numpy_to_vtk(np.ascontiguousarray(eval(expression)), deep=1)
        a.SetName(name)
        out.GetPointData().AddArray(a)
""" % (arrays,)
    return f
