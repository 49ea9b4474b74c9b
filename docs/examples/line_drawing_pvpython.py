from paraview.simple import *

drawing = SurfaceLineDrawing(Input=OpenDataFile("Testing/Data/bunny00.off"))
drawing.CameraPosition = [0.0, 0.1, 1.0]
drawing.UpdatePipeline()
print(drawing.GetDataInformation().GetNumberOfCells())
# In the GUI's Python shell, keep the drawing's camera on the view's:
#   import beltrami_paraview; beltrami_paraview.follow_camera(drawing, GetActiveView())
