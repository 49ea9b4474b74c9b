from paraview.simple import *

sphere = Sphere(ThetaResolution=128, PhiResolution=64)
# The gradient of x*y (sources and sinks) plus a rotation about z (a vortex at each pole).
field = Calculator(Input=sphere, ResultArrayName="Wind",
                   Function="coordsY*iHat + coordsX*jHat + 3*(coordsX*jHat - coordsY*iHat)")
decomposition = SurfaceVectorFieldDecomposition(Input=field)
decomposition.VectorField = ["POINTS", "Wind"]
decomposition.UpdatePipeline()
print("divergence range:", decomposition.PointData["Divergence"].GetRange())
print("curl range:", decomposition.PointData["Curl"].GetRange())
print("harmonic energy:", decomposition.FieldData["HarmonicEnergy"].GetRange()[0])
