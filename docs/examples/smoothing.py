# Smoothing a noisy scan with no setting: the step is chosen from the noise.
import numpy as np
from beltrami import vtkOFFReader, vtkImplicitFairing
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonDataModel import vtkPolyData
from vtkmodules.vtkCommonCore import vtkPoints

reader = vtkOFFReader()
reader.SetFileName("Testing/Data/bunny00.off")
reader.Update()
clean = vtk_to_numpy(reader.GetOutput().GetPoints().GetData()).astype(float)
diagonal = np.linalg.norm(clean.max(0) - clean.min(0))

noisy = vtkPolyData()
noisy.DeepCopy(reader.GetOutput())
points = vtkPoints()
points.SetData(numpy_to_vtk(clean + np.random.default_rng(1).normal(0, 0.001 * diagonal, clean.shape), deep=1))
noisy.SetPoints(points)

fairing = vtkImplicitFairing()
fairing.SetInputData(noisy)
fairing.Update()
smoothed = vtk_to_numpy(fairing.GetOutput().GetPoints().GetData())
field = fairing.GetOutput().GetFieldData()
print("estimated noise / diagonal:", field.GetArray("FairingNoise").GetValue(0) / diagonal)
print("chosen time step:", field.GetArray("FairingTimeStep").GetValue(0))


def rms(x):
    return np.sqrt(((x - clean) ** 2).sum(1).mean()) / diagonal


print("RMS error / diagonal: noisy", rms(vtk_to_numpy(noisy.GetPoints().GetData())), "smoothed", rms(smoothed))

# Stronger, broader smoothing by hand: three order-1 steps of 2 h^2.
fairing.SetOrder(1)
fairing.SetTimeStep(2.0)
fairing.SetNumberOfIterations(3)
fairing.Update()
