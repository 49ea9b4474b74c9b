# Remeshing to an exact vertex count, uniform and adapted to curvature.
from beltrami import vtkOFFReader, vtkSurfaceRemeshing

reader = vtkOFFReader()
reader.SetFileName("Testing/Data/bunny00.off")
remesh = vtkSurfaceRemeshing()
remesh.SetInputConnection(reader.GetOutputPort())
remesh.SetNumberOfVertices(3000)
remesh.Update()
field = remesh.GetOutput().GetFieldData()
print("vertices:", remesh.GetOutput().GetNumberOfPoints(),
      "smallest angle: %.1f deg" % field.GetArray("RemeshMinimumAngle").GetValue(0))

# Denser where the mean curvature is larger; a re-run keeps the atlas.
remesh.SetImportance(vtkSurfaceRemeshing.MEAN_CURVATURE)
remesh.Update()
deviation = field = remesh.GetOutput().GetFieldData().GetArray("RemeshDeviation")
print("deviation from the input / diagonal: %.4f" % max(deviation.GetValue(0), deviation.GetValue(1)))

# Anisotropic: triangles stretched along the directions of least curvature,
# fewer vertices for the same deviation (RemeshMetricQuality: in the metric).
remesh.SetImportance(vtkSurfaceRemeshing.UNIFORM)
remesh.SetAnisotropy(vtkSurfaceRemeshing.PRINCIPAL_CURVATURES)
remesh.Update()
figures = remesh.GetOutput().GetFieldData().GetArray("RemeshMetricQuality")
print("in the metric: median edge %.2f, mean smallest angle %.1f deg" % (figures.GetValue(0), figures.GetValue(3)))
