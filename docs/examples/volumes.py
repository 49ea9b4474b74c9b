# A tetrahedral mesh of a closed surface, then point data smoothed on it.
import numpy as np
from beltrami import vtkOFFReader, vtkTetGenTetrahedralizer, vtkTetrahedralBeltramiDenoising
from vtkmodules.vtkFiltersCore import vtkElevationFilter
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy

reader = vtkOFFReader()
reader.SetFileName("Testing/Data/eight.off")
tetgen = vtkTetGenTetrahedralizer()
tetgen.SetInputConnection(reader.GetOutputPort())
tetgen.SetMaximumVolume(0.001)
height = vtkElevationFilter()
height.SetInputConnection(tetgen.GetOutputPort())
height.Update()
grid = height.GetOutput()
print("tetrahedra:", grid.GetNumberOfCells())

values = vtk_to_numpy(grid.GetPointData().GetArray("Elevation"))
noisy = numpy_to_vtk(values + np.random.default_rng(0).normal(0, 0.05, values.shape), deep=1)
noisy.SetName("Elevation")
grid.GetPointData().SetScalars(noisy)
smooth = vtkTetrahedralBeltramiDenoising()
smooth.SetInputData(grid)
smooth.Update()
out = vtk_to_numpy(smooth.GetOutput().GetPointData().GetArray("Elevation"))
print("RMS error: noisy 0.05, denoised %.4f" % np.sqrt(((out - values) ** 2).mean()))
