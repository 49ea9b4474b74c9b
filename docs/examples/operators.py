# Edge and feature maps of an image: the operators of section 2.8.
from beltrami import vtkBeltramiOperators
from vtkmodules.vtkIOImage import vtkPNGReader
from vtkmodules.vtkImagingColor import vtkImageLuminance
from vtkmodules.util.numpy_support import vtk_to_numpy

reader = vtkPNGReader()
reader.SetFileName("Testing/Data/coffee.png")
grey = vtkImageLuminance()
grey.SetInputConnection(reader.GetOutputPort())
operators = vtkBeltramiOperators()
operators.SetInputConnection(grey.GetOutputPort())
operators.Update()

edges = vtk_to_numpy(operators.GetOutput().GetPointData().GetArray("EdgeIndicator"))
print("share of pixels on edges (1/W < 0.5):", (edges < 0.5).mean())
print("contrast scale used:", operators.GetOutput().GetFieldData().GetArray("GraphContrastScale").GetValue(0))
