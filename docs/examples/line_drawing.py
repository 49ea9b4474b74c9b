# A line drawing of a scan for one camera: contours, suggestive contours, ridges.
from beltrami import vtkOFFReader, vtkSurfaceLineDrawing

reader = vtkOFFReader()
reader.SetFileName("Testing/Data/bunny00.off")
drawing = vtkSurfaceLineDrawing()
drawing.SetInputConnection(reader.GetOutputPort())
drawing.SetCameraPosition(0.0, 0.1, 1.0)
drawing.SetRidges(True)
drawing.Update()
print("polylines:", drawing.GetOutput().GetNumberOfCells())

# A new camera re-runs only the per-view pass.
drawing.SetCameraPosition(1.0, 0.1, 0.0)
drawing.Update()
print("polylines from the side:", drawing.GetOutput().GetNumberOfCells())
