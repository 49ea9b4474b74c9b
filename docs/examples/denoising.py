# Denoising a photograph with no setting, then point data on a surface.
import numpy as np
from beltrami import vtkImageBeltramiDenoising, vtkOFFReader, vtkSurfaceDataDenoising
from vtkmodules.vtkIOImage import vtkPNGReader
from vtkmodules.vtkFiltersCore import vtkElevationFilter
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy

reader = vtkPNGReader()
reader.SetFileName("Testing/Data/camera.png")
reader.Update()
image = reader.GetOutput()
clean = vtk_to_numpy(image.GetPointData().GetScalars()).astype(float) / 255
noisy = clean + np.random.default_rng(0).normal(0, 0.1, clean.shape)
image.GetPointData().SetScalars(numpy_to_vtk(noisy, deep=1))

denoise = vtkImageBeltramiDenoising()
denoise.SetInputData(image)
denoise.Update()
result = vtk_to_numpy(denoise.GetOutput().GetPointData().GetScalars())


def psnr(x):
    return 10 * np.log10(1 / ((x - clean) ** 2).mean())


print("PSNR noisy %.2f dB, denoised %.2f dB" % (psnr(noisy), psnr(result)))
print("estimated noise:", denoise.GetOutput().GetFieldData().GetArray("EstimatedNoiseLevel").GetValue(0))

# Point data on a surface: a noisy height field on the bunny.
mesh = vtkOFFReader()
mesh.SetFileName("Testing/Data/bunny00.off")
height = vtkElevationFilter()
height.SetInputConnection(mesh.GetOutputPort())
height.Update()
surface = height.GetOutput()
values = vtk_to_numpy(surface.GetPointData().GetArray("Elevation"))
array = numpy_to_vtk(values + np.random.default_rng(0).normal(0, 0.05, values.shape), deep=1)
array.SetName("Elevation")
surface.GetPointData().SetScalars(array)
smooth = vtkSurfaceDataDenoising()
smooth.SetInputData(surface)
smooth.Update()
out = vtk_to_numpy(smooth.GetOutput().GetPointData().GetArray("Elevation"))
print("RMS error of the point data: noisy 0.05, denoised %.4f" % np.sqrt(((out - values) ** 2).mean()))
