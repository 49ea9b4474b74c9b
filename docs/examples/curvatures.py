# Curvatures of a closed scan (Python: /usr/bin/python3 or pvpython).
from beltrami import vtkOFFReader, vtkDiscreteCurvatures
from vtkmodules.util.numpy_support import vtk_to_numpy

reader = vtkOFFReader()
reader.SetFileName("Testing/Data/bunny00.off")
curvatures = vtkDiscreteCurvatures()
curvatures.SetInputConnection(reader.GetOutputPort())
curvatures.Update()

points = curvatures.GetOutput().GetPointData()
H = vtk_to_numpy(points.GetArray("MeanCurvature"))
K = vtk_to_numpy(points.GetArray("GaussianCurvature"))
area = vtk_to_numpy(points.GetArray("MixedArea"))
# Gauss-Bonnet: the integral of K over a closed surface is 2 pi chi.
print("integral of K / 2 pi =", (K * area).sum() / 6.283185307179586)
print("mean curvature range:", H.min(), H.max())
