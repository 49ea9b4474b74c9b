from paraview.simple import *

tets = TetGenTetrahedralize(Input=OpenDataFile("Testing/Data/eight.off"))
height = Elevation(Input=tets)
smoothed = TetrahedralBeltramiDenoising(Input=height)
smoothed.ArrayToSmooth = ["POINTS", "Elevation"]
smoothed.UpdatePipeline()
print(smoothed.PointData["Elevation"].GetRange())
