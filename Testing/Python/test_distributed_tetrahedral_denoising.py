"""TetrahedralBeltramiDenoising on tetrahedra split over the ranks of pvbatch
each rank smooths the point data of its own piece, with the
tetrahedra of the other pieces around its points (exchanged, not gathered);
the noise estimate (an exact median over the ranks), the mean edge length,
the stops' sums and the semi-implicit solves run over all ranks, and the
results equal the serial ones (plain VTK on the whole mesh) to the solver
tolerance, with the same number of steps.  Run by ctest with 1, 2, 3 and 4
ranks (mpirun --oversubscribe).

Checked on the real elephant filled by TetGen and cut anywhere by
RedistributeDataSet (points where three or more pieces meet from 3 ranks
on), with noisy point data (noise from the coordinates, so every layout has
the same): the defaults (semi-implicit steps, least-risk stop, noise
estimated), adaptive explicit steps, a 3-component array, log-Euclidean
tensors,
a fixed-points array, a rank with an empty piece, NaN values in a piece
(an error on every rank, the output the input), and the counts each rank
reports: with 4 ranks no rank holds more than a third of the points or
tetrahedra.  And BeltramiOperators of the same point data on the split
tetrahedra (computed where they are, the automatic contrast scale's noise
estimate and mean edge length over the ranks): every array on every piece
as in serial, also with overlapping pieces and an empty rank."""
import os
import sys

from paraview.simple import *  # noqa: F401,F403
from paraview import servermanager

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from configure import check, check_split_flow, empty_rank_partitions, fetch_pieces, rank_rows, report  # noqa: E402

DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "Data")

LoadPlugin(os.environ["BELTRAMI_PLUGIN"], ns=globals())
from beltrami import vtkBeltramiOperators, vtkTetrahedralBeltramiDenoising  # noqa: E402

ranks = servermanager.ActiveConnection.GetNumberOfDataPartitions()
filled = TetGenTetrahedralize(Input=OpenDataFile(os.path.join(DATA, "elephant.off")), MaximumVolume=1e-6)
whole = servermanager.Fetch(filled)
check(whole.GetNumberOfCells() > 8000, "the elephant's tetrahedra (%d)" % whole.GetNumberOfCells())
# A smooth function plus noise of about 0.05 from the coordinates, a vector
# of it, and a mask.
NOISE = ("0.0866*(2*(1e4*abs(sin(12.9898e3*coordsX + 78.233e3*coordsY + 37.719e3*coordsZ))"
         " - floor(1e4*abs(sin(12.9898e3*coordsX + 78.233e3*coordsY + 37.719e3*coordsZ)))) - 1)")
NOISY = "sin(12*coordsX)*cos(9*coordsY) + " + NOISE
VECTOR = "(cos(8*coordsZ) + %s)*iHat + coordsY*jHat + (%s)*kHat" % (NOISE, NOISY)
MASK = "coordsY > 0.3"


# Noisy diffusion-like tensors (XX, YY, ZZ, XY, YZ, XZ; positive definite).
TENSORS = """
import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
out = self.GetOutput()
out.ShallowCopy(self.GetInput())
p = vtk_to_numpy(out.GetPoints().GetData()).astype(float) if out.GetNumberOfPoints() else np.zeros((0, 3))
x, y, z = p.T
h = 1e4 * np.abs(np.sin(12.9898e3 * x + 78.233e3 * y + 37.719e3 * z))
noise = 0.15 * (2 * (h - np.floor(h)) - 1)
t = np.stack([2 + np.sin(8 * x) + noise, 1.5 + 0.5 * np.cos(6 * y), 1 + 0.3 * noise,
              0.3 * np.sin(5 * z), 0.2 + 0.1 * noise, 0.1 * np.cos(4 * x)], axis=1)
a = numpy_to_vtk(np.ascontiguousarray(t), deep=1)
a.SetName("t")
out.GetPointData().AddArray(a)
"""


def with_data(source, nan=False, tensors=False):
    f = Calculator(Input=source, ResultArrayName="f", Function=NOISY)
    v = Calculator(Input=f, ResultArrayName="v", Function=VECTOR)
    data = Calculator(Input=v, ResultArrayName="mask", Function=MASK, ResultArrayType="Unsigned Char")
    if tensors:
        data = ProgrammableFilter(Input=data, Script=TENSORS)
    if not nan:
        return data
    spoiled = ProgrammableFilter(Input=data)  # f NaN where x > 0.3 (in whichever pieces hold those points)
    spoiled.Script = """
import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy
out = self.GetOutput()
out.DeepCopy(self.GetInput())
if out.GetNumberOfPoints():
    f = vtk_to_numpy(out.GetPointData().GetArray("f"))
    f[vtk_to_numpy(out.GetPoints().GetData())[:, 0] > 0.3] = np.nan
"""
    return spoiled


def serial(grid, array, settings):
    """The filter on the whole mesh in plain VTK (a serial run)."""
    f = vtkTetrahedralBeltramiDenoising()
    f.SetInputData(grid)
    f.SetInputArrayToProcess(0, 0, 0, 0, array)
    f.SetInputArrayToProcess(1, 0, 0, 0, "mask")
    for name, value in settings.items():
        getattr(f, "Set" + name)(value)
    f.Update()
    return f.GetOutput()


def split_smoothing(partitions=0, nan=False, array="f", panel=None, mode=None):
    """The proxy on the redistributed elephant (its `panel` settings, by the
    panel's names)."""
    redistributed = RedistributeDataSet(Input=filled)
    redistributed.NumberOfPartitions = partitions
    if mode:
        redistributed.BoundaryMode = mode
    smoothed = TetrahedralBeltramiDenoising(Input=with_data(redistributed, nan, tensors=array == "t"))
    smoothed.ArrayToSmooth = ["POINTS", array]
    smoothed.FixedPointsArray = ["POINTS", "mask"]
    smoothed.UseFixedPointsArray = 1
    for name, value in (panel or {}).items():
        setattr(smoothed, name, value)
    smoothed.UpdatePipeline()
    return smoothed


def split_run(label, tolerance, partitions=0, array="f", panel=None, mode=None, **settings):
    """The split run against the serial VTK filter (`settings`)."""
    smoothed = split_smoothing(partitions, array=array, panel=panel, mode=mode)
    result = fetch_pieces(smoothed)
    noisy = servermanager.Fetch(with_data(filled, tensors=array == "t"))
    reference = serial(noisy, array, dict(settings, UseFixedPointsArray=1))
    check_split_flow(label, ranks, result, noisy, reference, array, tolerance, settings.get("StoppingRule", 2) == 2)
    return smoothed


smoothed = split_run("defaults", 1e-6)
# (Adaptive explicit steps: TetGen's tetrahedra allow about 0.002 h^2, and
# beyond the stability limit the serial run itself depends on the order of
# its sums.)
split_run("adaptive explicit steps", 1e-9, panel={"Integration": "Explicit", "AdaptiveTimeStep": 1,
                                                  "StoppingRule": "Fixed Number Of Iterations", "NumberOfIterations": 40},
          Integration=vtkTetrahedralBeltramiDenoising.EXPLICIT, AdaptiveTimeStep=1, StoppingRule=0, NumberOfIterations=40)
split_run("a vector", 1e-6, array="v")
split_run("log-Euclidean tensors", 1e-6, array="t", panel={"LogEuclideanTensors": 1}, LogEuclideanTensors=1)
if ranks > 1:
    split_run("defaults, an empty rank", 1e-6, partitions=empty_rank_partitions(ranks))
# Overlapping pieces (RedistributeDataSet's "Assign to all regions": the
# tetrahedra on a cut copied, unmarked, to every piece they touch).
split_run("defaults, overlapping pieces", 1e-6, mode="Assign to all regions")


def split_operators(label, partitions=0, mode=None, array="f"):
    """BeltramiOperators of `array` on the redistributed elephant against the serial VTK filter."""
    import numpy as np
    from vtkmodules.util.numpy_support import vtk_to_numpy
    redistributed = RedistributeDataSet(Input=filled)
    redistributed.NumberOfPartitions = partitions
    if mode:
        redistributed.BoundaryMode = mode
    operators = BeltramiOperators(Input=with_data(redistributed))
    operators.DataArray = ["POINTS", array]
    result = fetch_pieces(operators)
    noisy = servermanager.Fetch(with_data(filled))
    f = vtkBeltramiOperators()
    f.SetInputData(noisy)
    f.SetInputArrayToProcess(0, 0, 0, 0, array)
    f.Update()
    reference = f.GetOutput()
    index = {tuple(x): i for i, x in enumerate(vtk_to_numpy(noisy.GetPoints().GetData()))}
    ids = np.array([index.get(tuple(x), -1) for x in vtk_to_numpy(result.GetPoints().GetData())])
    check(ids.min() >= 0 and len(set(ids)) == noisy.GetNumberOfPoints(), "operators, %s: the pieces cover the input" % label)
    for name in ("MeanCurvatureNormal", "BeltramiOperator", "MeanCurvature", "EdgeIndicator"):
        ours = vtk_to_numpy(result.GetPointData().GetArray(name))
        theirs = vtk_to_numpy(reference.GetPointData().GetArray(name))[ids]
        same = np.isfinite(ours) == np.isfinite(theirs)
        both = np.isfinite(ours) & np.isfinite(theirs)
        scale = np.abs(theirs[both]).max()
        difference = np.abs(ours[both] - theirs[both]).max()
        check(same.all() and difference <= 1e-9 * scale and both.sum() > 0.5 * theirs.size,
              "operators, %s over %d rank(s): %s as serial (difference %.2g of %.3g)" % (label, ranks, name, difference, scale))
    for name in ("GraphContrastScale", "EstimatedNoiseLevel", "GraphUndefinedPoints"):
        a, b = report(result, name), report(reference, name)
        check(np.allclose(a, b, rtol=1e-12, atol=0), "operators, %s: %s %s as serial %s" % (label, name, a, b))


split_operators("defaults")
split_operators("a vector", array="v")
split_operators("overlapping pieces", mode="Assign to all regions")
if ranks > 1:
    split_operators("an empty rank", partitions=empty_rank_partitions(ranks))

# What each rank holds: its own points, the ghost points of the rings, its
# tetrahedra (field data FlowDistribution, one row per rank).
owned, ghosts, cells = rank_rows(smoothed, "FlowDistribution", ("Owned", "Ghosts", "Cells"))
if ranks > 1:
    check((owned >= 0).all() and owned.sum() == whole.GetNumberOfPoints(),
          "each point owned by one rank (%s)" % owned)
    check(ranks != 4 or ((owned + ghosts).max() <= whole.GetNumberOfPoints() / 3
                         and cells.max() <= whole.GetNumberOfCells() / 3),
          "no rank holds more than a third: points %s of %d, tetrahedra %s of %d"
          % (owned + ghosts, whole.GetNumberOfPoints(), cells, whole.GetNumberOfCells()))

# NaN values in a piece: an error on every rank (no hang), the output the
# input there (no report of a run).
bad = split_smoothing(nan=True)
check(bad.GetDataInformation().GetNumberOfPoints() == bad.Input.GetDataInformation().GetNumberOfPoints()
      and "FlowIterations" not in bad.FieldData.keys() and "f" in bad.PointData.keys(),
      "NaN values in a piece: no run on any rank, the output the input")
print("distributed tetrahedral denoising test passed")
