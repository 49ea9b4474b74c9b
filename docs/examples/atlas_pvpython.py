from paraview.simple import *

atlas = SurfaceAtlas(Input=OpenDataFile("Testing/Data/bunny00.off"))
atlas.MapResolution = 0
atlas.UpdatePipeline()
print(atlas.PointData["UV"].GetRange(0))
