from paraview.simple import *

remesh = SurfaceRemeshing(Input=OpenDataFile("Testing/Data/fandisk.off"))
remesh.NumberOfVertices = 3000
remesh.SplitAtFeatures = 1
remesh.UpdatePipeline()
print(remesh.GetDataInformation().GetNumberOfPoints())

# Anisotropic, within 0.1% of the diagonal both ways (the count left to it).
remesh.Anisotropy = "Principal curvatures"
remesh.NumberOfVertices = 0
remesh.MaximumDeviation = 0.001
remesh.UpdatePipeline()
print(remesh.GetDataInformation().GetNumberOfPoints())
