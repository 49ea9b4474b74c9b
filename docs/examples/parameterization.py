# Flattening a disk-like surface: the natural conformal map and a point constraint.
from beltrami import vtkOFFReader, vtkIntrinsicParameterization

reader = vtkOFFReader()
reader.SetFileName("Testing/Data/mushroom.off")
flat = vtkIntrinsicParameterization()  # DCP on a circle by default
flat.SetInputConnection(reader.GetOutputPort())
flat.Update()
print("circle: mean angle distortion %.2f deg, flipped %d"
      % (flat.GetMeanAngleDistortion(), flat.GetNumberOfFlippedTriangles()))

flat.SetBoundary(vtkIntrinsicParameterization.NATURAL)
flat.Update()
print("natural: mean angle distortion %.2f deg" % flat.GetMeanAngleDistortion())
uv = flat.GetOutput().GetPointData().GetArray("UV")  # also the TCoords
