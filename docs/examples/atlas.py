# Texture coordinates for a closed surface: an atlas of disk-like charts.
from beltrami import vtkOFFReader, vtkSurfaceAtlas

reader = vtkOFFReader()
reader.SetFileName("Testing/Data/fandisk.off")
atlas = vtkSurfaceAtlas()
atlas.SetInputConnection(reader.GetOutputPort())
atlas.SetSplitAtFeatures(True)  # sharp edges become chart boundaries
atlas.SetMapResolution(0)       # no geometry images
atlas.Update()
field = atlas.GetOutput().GetFieldData()
print("charts:", int(field.GetArray("AtlasCharts").GetValue(0)),
      "packing efficiency: %.2f" % field.GetArray("AtlasPackingEfficiency").GetValue(0))
