# The same in pvpython or pvbatch (with build/beltrami-env.sh sourced).
from paraview.simple import *

bunny = OpenDataFile("Testing/Data/bunny00.off")
curvatures = DiscreteCurvatures(Input=bunny)
curvatures.BoundaryHandling = "Interior average"
curvatures.UpdatePipeline()
print(curvatures.PointData["MeanCurvature"].GetRange())
