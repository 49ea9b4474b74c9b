"""SurfaceVectorFieldDecomposition on surfaces split over the ranks of
pvbatch: each rank holds its piece and the rings around it, the two Poisson
systems are solved over the ranks, and every rank gets the values of its
piece, equal to a serial run's (plain VTK on the whole surface) to the
solvers' tolerance.  Run by ctest with 1, 2 and 3 ranks (mpirun
--oversubscribe).

Checked with a field made from the coordinates (every layout has the
same), cut by RedistributeDataSet: on the bunny (genus 0, no harmonic part)
as point data, also with a rank whose piece is empty; on the eight (genus 2:
a harmonic part) as cell data; on an open patch under both boundary
conditions.  Every point array of the output (the parts, potential, stream
function, divergence, curl) at every point of every piece, the cell arrays
of cell data, and the field data; and that the ranks solved together (their
conjugate gradients' iterations, where a serial run of these sizes
factorizes)."""
import builtins  # (ParaView's programmable filters put numpy_interface's max, abs... in __main__)
import os
import sys
import tempfile

from paraview.simple import *  # noqa: F401,F403
from paraview import servermanager
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonDataModel import vtkPointLocator
from vtkmodules.vtkFiltersCore import vtkCellCenters
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from configure import check, empty_rank_partitions, rank_rows  # noqa: E402

DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "Data")
LoadPlugin(os.environ["BELTRAMI_PLUGIN"], ns=globals())
from beltrami import vtkSurfaceVectorFieldDecomposition  # noqa: E402

ranks = servermanager.ActiveConnection.GetNumberOfDataPartitions()
WIND = "(coordsY - 0.1)*iHat - (coordsX + 0.02)*jHat + 10*exp(-200*((coordsX + 0.03)^2 + (coordsY - 0.1)^2))*kHat"
ARRAYS = ("TangentField", "CurlFreePart", "DivergenceFreePart", "HarmonicPart", "Potential", "StreamFunction",
          "Divergence", "Curl", "NormalComponent")
POINT_ONLY = ("Potential", "StreamFunction", "Divergence", "Curl")


def with_wind(source, on_cells):
    wind = Calculator(Input=source, ResultArrayName="Wind", Function=WIND)
    return PointDatatoCellData(Input=wind) if on_cells else wind


def serial(polydata, on_cells, boundary):
    f = vtkSurfaceVectorFieldDecomposition()
    f.SetInputData(polydata)
    f.SetInputArrayToProcess(0, 0, 0, 1 if on_cells else 0, "Wind")
    f.SetBoundaryCondition(boundary)
    f.Update()
    return f.GetOutput()


def cell_index(result, reference):
    """Per cell of the fetched pieces, the cell of the reference with the
    same centre."""
    centres = []
    for data in (result, reference):
        c = vtkCellCenters()
        c.SetInputData(data)
        c.Update()
        centres.append(c.GetOutput())
    locator = vtkPointLocator()
    locator.SetDataSet(centres[1])
    locator.BuildLocator()
    return np.array([locator.FindClosestPoint(*x) for x in vtk_to_numpy(centres[0].GetPoints().GetData())], dtype=int)


def split_run(label, path, on_cells=False, boundary=0, partitions=0, scale=1.0):
    source = OpenDataFile(path)
    if scale != 1.0:
        source = Transform(Input=source)
        source.Transform.Scale = [scale] * 3
    redistributed = RedistributeDataSet(Input=source)
    redistributed.NumberOfPartitions = partitions
    decomposition = SurfaceVectorFieldDecomposition(Input=with_wind(ExtractSurface(Input=redistributed), on_cells))
    decomposition.VectorField = ["CELLS" if on_cells else "POINTS", "Wind"]
    decomposition.BoundaryCondition = boundary
    decomposition.UpdatePipeline()
    result = servermanager.Fetch(decomposition)
    reference = serial(servermanager.Fetch(with_wind(source, on_cells)), on_cells, boundary)
    locator = vtkPointLocator()
    locator.SetDataSet(reference)
    locator.BuildLocator()
    p = vtk_to_numpy(result.GetPoints().GetData())
    index = np.array([locator.FindClosestPoint(*x) for x in p], dtype=int)
    check(np.abs(vtk_to_numpy(reference.GetPoints().GetData())[index] - p).max() == 0,
          "%s: every point of the pieces is a point of the surface" % label, quiet=True)
    tangent = vtk_to_numpy((reference.GetCellData() if on_cells else reference.GetPointData()).GetArray("TangentField"))
    for name in ARRAYS:
        cells = on_cells and name not in POINT_ONLY
        a = vtk_to_numpy((result.GetCellData() if cells else result.GetPointData()).GetArray(name))
        b = vtk_to_numpy((reference.GetCellData() if cells else reference.GetPointData()).GetArray(name))
        b = b[cell_index(result, reference)] if cells else b[index]
        # (The parts against the field's size: the bunny's harmonic part is
        # round-off.  NaN where triangles are left out, at the same places.)
        scale = np.nanmax(np.abs(tangent)) if name.endswith("Part") else builtins.max(1e-300, np.nanmax(np.abs(b)))
        difference = np.nanmax(np.abs(a - b)) / scale
        check((np.isnan(a) == np.isnan(b)).all() and difference <= 1e-9, "%s over %d rank(s): %s as serial (%.1e)"
              % (label, ranks, name, difference), quiet=name != "HarmonicPart")
    energy = reference.GetFieldData().GetArray("TangentEnergy").GetValue(0)
    for name in ("TangentEnergy", "CurlFreeEnergy", "DivergenceFreeEnergy", "HarmonicEnergy", "ExcludedTriangles"):
        a = result.GetFieldData().GetArray(name).GetValue(0)
        b = reference.GetFieldData().GetArray(name).GetValue(0)
        check(builtins.abs(a - b) <= 1e-9 * energy, "%s: %s as serial" % (label, name), quiet=True)
    # (Where one rank holds the whole surface, it runs as serial.)
    iterations = rank_rows(decomposition, "SolverIterations", ("value",))[0]
    held = iterations >= 0
    together = held.sum() > 1
    check(reference.GetFieldData().GetArray("SolverIterations").GetValue(0) == 0 and
          ((iterations[held] > 0).all() if together else (iterations[held] == 0).all()) and
          (iterations[held] == iterations[held][0]).all(),
          "%s: %s (%s iterations each; serial: factorized)"
          % (label, "the ranks solved together" if together else "one rank, as serial", iterations[held]))
    return reference


split_run("bunny", os.path.join(DATA, "bunny00.off"))
if ranks > 1:
    split_run("bunny, an empty rank", os.path.join(DATA, "bunny00.off"), partitions=empty_rank_partitions(ranks))
eight = split_run("eight, cell data", os.path.join(DATA, "eight.off"), on_cells=True)
check(eight.GetFieldData().GetArray("HarmonicEnergy").GetValue(0) >
      1e-3 * eight.GetFieldData().GetArray("TangentEnergy").GetValue(0), "the eight has a harmonic part")
for boundary in (0, 1):
    split_run("open patch, boundary condition %d" % boundary, os.path.join(DATA, "patch-01.off"), boundary=boundary)
# Coordinates far from unit size (and vectors as large): the whole surface's
# scale, the same on every rank.  (RedistributeDataSet itself aborts
# beyond about 1e100.)
split_run("bunny at 1e30", os.path.join(DATA, "bunny00.off"), scale=1e30)
# A fin on the bunny: a triangle hanging from one of its points, which is
# non-manifold there; every rank leaves out the same triangles (those at
# that point) as the serial run.
with open(os.path.join(DATA, "bunny00.off")) as f:
    lines = [line for line in f.read().splitlines() if line.strip() and not line.startswith("#")]
nv, nt = map(int, lines[1].split()[:2])
x0 = [float(c) for c in lines[2].split()]  # (a small fin: in the same piece as the point's triangles)
fin = ["%.9g %.9g %.9g" % (x0[0] + dx, x0[1] + dy, x0[2] + 0.01) for dx, dy in ((0.005, 0.0), (0.0, 0.005))]
fin_path = os.path.join(tempfile.mkdtemp(), "bunny-with-fin.off")
with open(fin_path, "w") as f:
    f.write("\n".join(["OFF", "%d %d 0" % (nv + 2, nt + 1)] + lines[2:2 + nv] + fin +
                      lines[2 + nv:2 + nv + nt] + ["3 0 %d %d" % (nv, nv + 1)]) + "\n")
fin = split_run("bunny with a fin", fin_path)
excluded = fin.GetFieldData().GetArray("ExcludedTriangles").GetValue(0)
check(excluded >= 3, "the fin's point left out: %d triangles" % excluded)
print("distributed vector field test passed")
