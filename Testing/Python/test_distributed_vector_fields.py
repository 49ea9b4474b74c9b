"""SurfaceVectorFieldDecomposition on surfaces split over the ranks of
pvbatch: the pieces are gathered on rank 0, decomposed there, and every
rank gets the values of its piece, equal to a serial run's (plain VTK on the
whole surface).  Run by ctest with 1, 2 and 3 ranks (mpirun --oversubscribe).

Checked on the bunny cut by RedistributeDataSet with a point field made
from the coordinates (every layout has the same): every point array of the
output (the parts, potential, stream function, divergence, curl) at every
point of every piece, and the field data; also with a rank whose piece is
empty."""
import builtins  # (ParaView's programmable filters put numpy_interface's max, abs... in __main__)
import os
import sys

from paraview.simple import *  # noqa: F401,F403
from paraview import servermanager
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonDataModel import vtkPointLocator
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from configure import check, empty_rank_partitions  # noqa: E402

DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "Data")
LoadPlugin(os.environ["BELTRAMI_PLUGIN"], ns=globals())
from beltrami import vtkSurfaceVectorFieldDecomposition  # noqa: E402

ranks = servermanager.ActiveConnection.GetNumberOfDataPartitions()
bunny = OpenDataFile(os.path.join(DATA, "bunny00.off"))
WIND = "(coordsY - 0.1)*iHat - (coordsX + 0.02)*jHat + 10*exp(-200*((coordsX + 0.03)^2 + (coordsY - 0.1)^2))*kHat"
ARRAYS = ("TangentField", "CurlFreePart", "DivergenceFreePart", "HarmonicPart", "Potential", "StreamFunction",
          "Divergence", "Curl", "NormalComponent")


def with_wind(source):
    return Calculator(Input=source, ResultArrayName="Wind", Function=WIND)


def serial(polydata):
    f = vtkSurfaceVectorFieldDecomposition()
    f.SetInputData(polydata)
    f.SetInputArrayToProcess(0, 0, 0, 0, "Wind")
    f.Update()
    return f.GetOutput()


def split_run(label, partitions=0):
    redistributed = RedistributeDataSet(Input=bunny)
    redistributed.NumberOfPartitions = partitions
    decomposition = SurfaceVectorFieldDecomposition(Input=with_wind(ExtractSurface(Input=redistributed)))
    decomposition.VectorField = ["POINTS", "Wind"]
    decomposition.UpdatePipeline()
    result = servermanager.Fetch(decomposition)
    reference = serial(servermanager.Fetch(with_wind(bunny)))
    locator = vtkPointLocator()
    locator.SetDataSet(reference)
    locator.BuildLocator()
    p = vtk_to_numpy(result.GetPoints().GetData())
    index = np.array([locator.FindClosestPoint(*x) for x in p], dtype=int)
    check(np.abs(vtk_to_numpy(reference.GetPoints().GetData())[index] - p).max() == 0,
          "%s: every point of the pieces is a point of the surface" % label, quiet=True)
    for name in ARRAYS:
        a = vtk_to_numpy(result.GetPointData().GetArray(name))
        b = vtk_to_numpy(reference.GetPointData().GetArray(name))[index]
        # (The parts against the field's size: the bunny's harmonic part is round-off.)
        scale = np.abs(vtk_to_numpy(reference.GetPointData().GetArray("TangentField"))).max() \
            if name.endswith("Part") else builtins.max(1e-300, np.abs(b).max())
        check(np.abs(a - b).max() <= 1e-9 * scale, "%s over %d rank(s): %s as serial (%.1e)"
              % (label, ranks, name, np.abs(a - b).max() / scale), quiet=name != "HarmonicPart")
    for name in ("TangentEnergy", "CurlFreeEnergy", "DivergenceFreeEnergy", "HarmonicEnergy"):
        a = result.GetFieldData().GetArray(name).GetValue(0)
        b = reference.GetFieldData().GetArray(name).GetValue(0)
        check(builtins.abs(a - b) <= 1e-9 * reference.GetFieldData().GetArray("TangentEnergy").GetValue(0),
              "%s: %s as serial" % (label, name), quiet=True)


split_run("bunny")
if ranks > 1:
    split_run("bunny, an empty rank", partitions=empty_rank_partitions(ranks))
print("distributed vector field test passed")
