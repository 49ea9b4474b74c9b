"""The ParaView plugin from pvpython / pvbatch: OpenDataFile on .off, the
DiscreteCurvatures, ImplicitFairing and IntrinsicParameterization proxies, their defaults, and the OFF writer."""
import math
import os
import sys
import tempfile

from paraview.simple import *  # noqa: F401,F403
from paraview import servermanager
from vtkmodules.util.numpy_support import vtk_to_numpy
import numpy as np

DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "Data")


def check(condition, message):
    if not condition:
        print("FAILED: " + message)
        sys.exit(1)


LoadPlugin(os.environ["BELTRAMI_PLUGIN"], ns=globals())
reader = OpenDataFile(os.path.join(DATA, "bunny00.off"))
check(reader is not None and reader.GetXMLName() == "OFFReader",
      "OpenDataFile picks the plugin's OFF reader")
curvatures = DiscreteCurvatures(Input=reader)
check(curvatures.Method == "Meyer 2003 (thesis operators)", "default method")
check(curvatures.NormalWeighting == "Mean curvature normal", "default normal weighting")
check(curvatures.BoundaryHandling == "NaN (undefined)", "default boundary handling")
curvatures.UpdatePipeline()
data = servermanager.Fetch(curvatures)
check(data.GetNumberOfPoints() == 37706, "all bunny points")
pd = data.GetPointData()
for name in ("MeanCurvatureNormal", "MixedArea", "MeanCurvature", "GaussianCurvature",
             "MaximumCurvature", "MinimumCurvature", "PrincipalDirection1",
             "PrincipalDirection2", "Normals", "VertexStatus"):
    check(pd.GetArray(name) is not None, "array " + name)
g = vtk_to_numpy(pd.GetArray("GaussianCurvature"))
a = vtk_to_numpy(pd.GetArray("MixedArea"))
check(abs(float(np.sum(g * a)) - 4 * math.pi) < 1e-9, "Gauss-Bonnet on the bunny (genus 0)")
info = curvatures.PointData["MeanCurvature"].GetRange()
check(info[0] < 0 < info[1], "mean curvature range spans both signs")

fairing = ImplicitFairing(Input=reader)
check(fairing.Operator == "Curvature Flow", "default smoothing operator")
check(fairing.Integration == "Implicit", "default integration")
check(fairing.Invariant == "Automatic", "default invariant")
fairing.TimeStep = 2.0
fairing.UpdatePipeline()
smoothed = servermanager.Fetch(fairing)
check(smoothed.GetNumberOfPoints() == 37706, "smoothed bunny keeps its points")


def volume(polydata):
    p = vtk_to_numpy(polydata.GetPoints().GetData()).astype(float)
    t = vtk_to_numpy(polydata.GetPolys().GetConnectivityArray()).reshape(-1, 3)
    return float(np.sum(np.einsum("ij,ij->i", p[t[:, 0]], np.cross(p[t[:, 1]], p[t[:, 2]])))) / 6


x = vtk_to_numpy(smoothed.GetPoints().GetData())
check(np.isfinite(x).all(), "finite smoothed points")
if servermanager.ActiveConnection.GetNumberOfDataPartitions() == 1:
    # (Distributed: each piece is smoothed with its piece boundary fixed; see README.)
    original = servermanager.Fetch(reader)
    check(abs(volume(smoothed) / volume(original) - 1) < 1e-9, "volume preserved through the plugin")

mushroom = OpenDataFile(os.path.join(DATA, "mushroom.off"))
param = IntrinsicParameterization(Input=mushroom)
check(param.ConformalWeight == 1 and param.AuthalicWeight == 0, "default energy: DCP")
check(param.Boundary == "Circle" and param.BoundarySpacing == "Arc Length", "default boundary")
if servermanager.ActiveConnection.GetNumberOfDataPartitions() == 1:
    # (Distributed: a parameterization needs the whole surface; pieces pass through with a warning.)
    param.UpdatePipeline()
    flat = servermanager.Fetch(param)
    uv = vtk_to_numpy(flat.GetPointData().GetTCoords())
    check(uv.shape == (2337, 2) and np.isfinite(uv).all(), "UV texture coordinates on every point")
    mean_angle = flat.GetFieldData().GetArray("MeanAngleDistortion").GetValue(0)
    check(abs(mean_angle - 3.48) < 0.01, "DCP mean angle distortion as CGAL's (%.3f)" % mean_angle)
    param.Boundary = "Natural"
    param.UpdatePipeline()
    natural = servermanager.Fetch(param).GetFieldData().GetArray("MeanAngleDistortion").GetValue(0)
    check(natural < 1.73, "natural conformal map below LSCM's 1.73 degrees (%.3f)" % natural)

with tempfile.TemporaryDirectory() as tmp:
    path = os.path.join(tmp, "bunny.off")
    SaveData(path, proxy=reader)
    again = OpenDataFile(path)
    again.UpdatePipeline()
    check(again.GetDataInformation().GetNumberOfPoints() == 37706, "OFF writer round trip")
print("pvpython plugin test passed")
