from paraview.simple import *

remesh = SurfaceRemeshing(Input=OpenDataFile("Testing/Data/fandisk.off"))
remesh.NumberOfVertices = 3000
remesh.SplitAtFeatures = 1
remesh.UpdatePipeline()
print(remesh.GetDataInformation().GetNumberOfPoints())
