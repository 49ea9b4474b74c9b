from paraview.simple import *

mushroom = OpenDataFile("Testing/Data/mushroom.off")
flat = IntrinsicParameterization(Input=mushroom)
flat.Boundary = "Natural"
flat.OutputFlattenedMesh = 1
flat.UpdatePipeline()
print(flat.CellData["AngleDistortion"].GetRange())
