"""SurfaceDataDenoising on surfaces split over the ranks of pvbatch:
each rank smooths the point data of its own piece, the noise estimate (an
exact median over the ranks), the mean edge length, the stops' sums and the
semi-implicit solves run over all ranks, and the results equal the serial
ones (plain VTK on the whole surface) to the solver tolerance, with the same
number of steps.  Run by ctest with 1, 2 and 3 ranks (mpirun --oversubscribe).

Checked on the real bunny cut anywhere by RedistributeDataSet, with noisy
point data (noise from the coordinates, so every layout has the same): the
defaults (semi-implicit steps, least-risk stop, noise estimated), explicit
steps stopped at the noise level, a fixed-points array, and a rank with an
empty piece."""
import os
import sys

from paraview.simple import *  # noqa: F401,F403
from paraview import servermanager
from vtkmodules.util.numpy_support import vtk_to_numpy
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from configure import check, check_split_flow, empty_rank_partitions  # noqa: E402

DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "Data")

LoadPlugin(os.environ["BELTRAMI_PLUGIN"], ns=globals())
from beltrami import vtkSurfaceDataDenoising  # noqa: E402

ranks = servermanager.ActiveConnection.GetNumberOfDataPartitions()
bunny = OpenDataFile(os.path.join(DATA, "bunny00.off"))
# A smooth function plus noise of about 0.05 from the coordinates, and a mask.
NOISY = ("sin(40*coordsX)*cos(30*coordsY) + 0.0866*(2*(1e4*abs(sin(12.9898e3*coordsX + 78.233e3*coordsY"
         " + 37.719e3*coordsZ)) - floor(1e4*abs(sin(12.9898e3*coordsX + 78.233e3*coordsY + 37.719e3*coordsZ)))) - 1)")
MASK = "coordsY > 0.15"


def with_data(source):
    f = Calculator(Input=source, ResultArrayName="f", Function=NOISY)
    return Calculator(Input=f, ResultArrayName="mask", Function=MASK, ResultArrayType="Unsigned Char")


def serial(polydata, settings):
    """The filter on the whole surface in plain VTK (a serial run)."""
    f = vtkSurfaceDataDenoising()
    f.SetInputData(polydata)
    f.SetInputArrayToProcess(0, 0, 0, 0, "f")
    f.SetInputArrayToProcess(1, 0, 0, 0, "mask")
    for name, value in settings.items():
        getattr(f, "Set" + name)(value)
    f.Update()
    return f.GetOutput()


def split_run(label, tolerance, partitions=0, panel=None, mode=None, **settings):
    """The proxy on the redistributed bunny (its `panel` settings, by the
    panel's names) against the serial VTK filter (`settings`)."""
    redistributed = RedistributeDataSet(Input=bunny)
    redistributed.NumberOfPartitions = partitions
    if mode:
        redistributed.BoundaryMode = mode
    smoothed = SurfaceDataDenoising(Input=with_data(ExtractSurface(Input=redistributed)))
    smoothed.ArrayToSmooth = ["POINTS", "f"]
    smoothed.FixedPointsArray = ["POINTS", "mask"]
    smoothed.UseFixedPointsArray = 1
    for name, value in (panel or {}).items():
        setattr(smoothed, name, value)
    smoothed.UpdatePipeline()
    result = servermanager.Fetch(smoothed)
    whole = servermanager.Fetch(with_data(bunny))
    reference = serial(whole, dict(settings, UseFixedPointsArray=1))
    check_split_flow(label, ranks, result, whole, reference, "f", tolerance, settings.get("StoppingRule", 2) == 2)
    return result


split_run("defaults", 1e-6)
split_run("explicit steps, noise-level stop", 1e-9, panel={"Integration": "Explicit", "StoppingRule": "Noise Level"},
          Integration=vtkSurfaceDataDenoising.EXPLICIT, StoppingRule=1)
if ranks > 1:
    split_run("defaults, an empty rank", 1e-6, partitions=empty_rank_partitions(ranks))
# Overlapping pieces (the cells on a cut copied, unmarked, to every piece they
# touch): each cell and point counted once, so the same noise estimate.
split_run("defaults, overlapping pieces", 1e-6, mode="Assign to all regions")
print("distributed denoising test passed")
