"""The ParaView plugin from pvpython / pvbatch: OpenDataFile on .off, the
DiscreteCurvatures, ImplicitFairing, IntrinsicParameterization, ImageBeltramiDenoising,
SurfaceDataDenoising and TetrahedralBeltramiDenoising proxies, their defaults, and the OFF writer."""
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
partitions = servermanager.ActiveConnection.GetNumberOfDataPartitions()
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

def matching_points(pieces, whole, label, decimals=None):
    """For every point of `pieces` (fetched from all ranks) the id of the point
    of `whole` at the same coordinates; checks that they cover `whole`."""
    key = (lambda x: tuple(np.round(x, decimals))) if decimals else tuple
    index = {key(x): i for i, x in enumerate(vtk_to_numpy(whole.GetPoints().GetData()))}
    matched = [index.get(key(x), -1) for x in vtk_to_numpy(pieces.GetPoints().GetData())]
    check(min(matched) >= 0 and len(set(matched)) == whole.GetNumberOfPoints(),
          "%s: the pieces cover the whole surface's points" % label)
    return matched


def saved_pieces(proxy):
    """The image pieces of every rank, saved as a .pvti and read back whole."""
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "pieces.pvti")
        SaveData(path, proxy=proxy)
        pieces = vtkXMLPImageDataReader()
        pieces.SetFileName(path)
        pieces.Update()
        return pieces.GetOutput()


def check_equal_to_serial(pieces, whole, label, decimals=None):
    """The curvatures of `pieces` equal those of the serial `whole` at the
    same coordinates, every point included; returns how many points three or
    more pieces share (Fetch appends the pieces without merging points)."""
    matched = matching_points(pieces, whole, label, decimals)
    for name in ("MeanCurvature", "GaussianCurvature", "MaximumCurvature", "MinimumCurvature"):
        ours = vtk_to_numpy(pieces.GetPointData().GetArray(name))
        reference = vtk_to_numpy(whole.GetPointData().GetArray(name))[matched]
        difference = np.abs(ours - reference).max()
        check(np.isfinite(ours).all() and difference < 1e-9 * np.abs(reference).max(),
              "%s: %s over %d partition(s) equals the serial value at every point (max difference %g)"
              % (label, name, partitions, difference))
    shared = int((np.bincount(matched) >= 3).sum())
    print("%s: curvatures over %d partition(s) at %d points equal the serial ones (%d points in 3 or more pieces)"
          % (label, partitions, len(matched), shared))
    return shared


def check_piece_arrays(proxy, label):
    """This process's piece of `proxy`'s output (rank 0's under pvbatch): one
    value per point in every point array, ghost points' values dropped."""
    piece = proxy.GetClientSideObject().GetOutputDataObject(0)
    pd = piece.GetPointData()
    for a in range(pd.GetNumberOfArrays()):
        check(pd.GetArray(a).GetNumberOfTuples() == piece.GetNumberOfPoints(),
              "%s: %s has one value per point of the piece (%d, %d points)"
              % (label, pd.GetArrayName(a), pd.GetArray(a).GetNumberOfTuples(), piece.GetNumberOfPoints()))


# A source that splits into pieces (an ellipsoid from the sphere source): with
# MPI no piece comes with ghost cells, so the pieces exchange the triangles
# around their common points; the curvatures then equal the serial ones at
# every point, seam points included - also the poles, which every piece shares
# (with 3 or more ranks).
from beltrami import vtkDiscreteCurvatures  # noqa: E402
from vtkmodules.vtkCommonTransforms import vtkTransform  # noqa: E402
from vtkmodules.vtkFiltersGeneral import vtkTransformPolyDataFilter  # noqa: E402
from vtkmodules.vtkFiltersSources import vtkSphereSource  # noqa: E402
ellipsoid = Transform(Input=Sphere(ThetaResolution=48, PhiResolution=40))
ellipsoid.Transform.Scale = [1.0, 2.0, 3.0]
split_curvatures = DiscreteCurvatures(Input=ellipsoid)
split_curvatures.UpdatePipeline()
whole_sphere = vtkSphereSource()
whole_sphere.SetThetaResolution(48)
whole_sphere.SetPhiResolution(40)
scale = vtkTransform()
scale.Scale(1.0, 2.0, 3.0)
whole_ellipsoid = vtkTransformPolyDataFilter()
whole_ellipsoid.SetInputConnection(whole_sphere.GetOutputPort())
whole_ellipsoid.SetTransform(scale)
serial_curvatures = vtkDiscreteCurvatures()
serial_curvatures.SetInputConnection(whole_ellipsoid.GetOutputPort())
serial_curvatures.Update()
# (The sphere source's seam points differ in the last bits between pieces.)
shared = check_equal_to_serial(servermanager.Fetch(split_curvatures), serial_curvatures.GetOutput(), "ellipsoid", 9)
check(shared == (2 if partitions >= 3 else 0), "ellipsoid: the poles are in every piece")
check_piece_arrays(split_curvatures, "ellipsoid")

# A multiblock file (3 blocks on 2 ranks): blocks are data sets of their own,
# run one by one without talking between ranks (no hang), as in serial.
from vtkmodules.vtkCommonDataModel import vtkMultiBlockDataSet  # noqa: E402
from vtkmodules.vtkIOXML import vtkXMLMultiBlockDataWriter  # noqa: E402
with tempfile.TemporaryDirectory() as tmp:
    blocks = vtkMultiBlockDataSet()
    for b in range(3):
        ball = vtkSphereSource()
        ball.SetCenter(3.0 * b, 0.0, 0.0)
        ball.SetThetaResolution(16 + 4 * b)
        ball.SetPhiResolution(16)
        ball.Update()
        blocks.SetBlock(b, ball.GetOutput())
    writer = vtkXMLMultiBlockDataWriter()
    writer.SetInputData(blocks)
    writer.SetFileName(os.path.join(tmp, "blocks.vtm"))
    writer.Write()
    block_curvatures = DiscreteCurvatures(Input=XMLMultiBlockDataReader(FileName=[os.path.join(tmp, "blocks.vtm")]))
    block_curvatures.UpdatePipeline()
    block_range = block_curvatures.PointData["MeanCurvature"].GetRange()
    check(block_curvatures.GetDataInformation().GetNumberOfPoints() == blocks.GetNumberOfPoints()
          and 1.95 < block_range[0] <= block_range[1] < 2.05,
          "curvatures of a multiblock file, block by block (range %s)" % (block_range,))

# The bunny (read whole on one rank, double coordinates) redistributed over the
# ranks: the same check on a real mesh cut anywhere.
redistributed = DiscreteCurvatures(Input=ExtractSurface(Input=RedistributeDataSet(Input=reader)))
redistributed.UpdatePipeline()
shared = check_equal_to_serial(servermanager.Fetch(redistributed), data, "redistributed bunny")
check(partitions < 3 or shared > 0, "redistributed bunny: points where three pieces meet")
check_piece_arrays(redistributed, "redistributed bunny")
# Pieces that overlap: RedistributeDataSet's "Assign to all regions" copies
# the cells on a cut, unmarked, to every piece they touch (with 3 ranks, two
# regions into one rank); each is joined once (before: 696 points NaN).
overlapping = RedistributeDataSet(Input=reader)
overlapping.BoundaryMode = "Assign to all regions"
overlap_curvatures = DiscreteCurvatures(Input=ExtractSurface(Input=overlapping))
overlap_curvatures.UpdatePipeline()
check_equal_to_serial(servermanager.Fetch(overlap_curvatures), data, "overlapping pieces of the bunny")
# Beltrami Operators on point data over the redistributed bunny: each rank its
# piece (1-rings exchanged), the automatic contrast's noise estimate (a median
# over all ranks) and mean edge length taken over the ranks: the serial numbers.
EXPRESSION = "sin(40*coordsX)*cos(30*coordsY) + 0.02*sin(12345*coordsZ + 777*coordsX)"
graph_data = {}
for label, source in (("serial", reader), ("split", ExtractSurface(Input=RedistributeDataSet(Input=reader)))):
    values = Calculator(Input=source, ResultArrayName="f", Function=EXPRESSION)
    graph = BeltramiOperators(Input=values)
    graph.DataArray = ["POINTS", "f"]
    graph.UpdatePipeline()
    graph_data[label] = servermanager.Fetch(graph)
matched = matching_points(graph_data["split"], graph_data["serial"], "Beltrami operators on the split bunny")
for name in ("MeanCurvatureNormal", "BeltramiOperator", "MeanCurvature", "GaussianCurvature", "EdgeIndicator"):
    ours = vtk_to_numpy(graph_data["split"].GetPointData().GetArray(name))
    reference = vtk_to_numpy(graph_data["serial"].GetPointData().GetArray(name))[matched]
    finite = np.isfinite(reference)
    check(np.array_equal(finite, np.isfinite(ours)) and
          np.abs(ours[finite] - reference[finite]).max() <= 1e-9 * np.abs(reference[finite]).max(),
          "Beltrami operators on the bunny over %d partition(s) equal serial (%s)" % (partitions, name))
for name in ("GraphContrastScale", "EstimatedNoiseLevel", "GraphUndefinedPoints"):
    ours = graph_data["split"].GetFieldData().GetArray(name).GetValue(0)
    reference = graph_data["serial"].GetFieldData().GetArray(name).GetValue(0)
    check(abs(ours - reference) <= 1e-12 * abs(reference) and (name == "GraphUndefinedPoints" or reference > 0),
          "Beltrami operators over %d partition(s): %s %g as serial (%g)" % (partitions, name, ours, reference))
if "--curvatures-only" in sys.argv:  # the run on 3 ranks (ctest ParaView.CurvaturesInPvbatchOn3Ranks)
    print("pvpython plugin test passed")
    sys.exit(0)

# ParaView preselects an array of the input for every array selection (here a
# curvature array, non-zero nearly everywhere); the masks are off until asked for.
fairing_on_curvatures = ImplicitFairing(Input=curvatures, TimeStep=4.0)  # (0, the default, leaves a clean mesh)
check(fairing_on_curvatures.UseFixedPointsArray == 0 and fairing_on_curvatures.UseSmoothingWeightsArray == 0,
      "fixed points and weights off by default")
fairing_on_curvatures.UpdatePipeline()
moved = vtk_to_numpy(servermanager.Fetch(fairing_on_curvatures).GetPoints().GetData()).astype(float)
still = vtk_to_numpy(data.GetPoints().GetData()).astype(float)
check(np.abs(moved - still).max() > 1e-4, "fairing the curvature output moves the points")
Delete(fairing_on_curvatures)
fairing = ImplicitFairing(Input=reader)
check(fairing.Operator == "Least Estimated Error" and fairing.TimeStep == 0.0, "default smoothing operator and step")
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
# The OFF reader cannot split a file: with MPI the whole bunny is on one rank,
# and the filters treat it as in a serial run.
original = servermanager.Fetch(reader)
check(abs(volume(smoothed) / volume(original) - 1) < 1e-9, "volume preserved through the plugin")
# Taubin's lambda|mu through the panel: the thesis' values by default, and the
# panel's values reach the filter (a wider pass band keeps more of the noise).
taubin = ImplicitFairing(Input=reader, Integration="Taubin lambda|mu", NumberOfIterations=10)
check(abs(taubin.TaubinLambda - 0.6307) < 1e-12 and abs(taubin.TaubinMu + 0.6732) < 1e-12, "default Taubin lambda, mu")
taubin.UpdatePipeline()
narrow = vtk_to_numpy(servermanager.Fetch(taubin).GetPoints().GetData()).astype(float)
taubin.TaubinMu = -0.64  # pass band 1/0.6307 - 1/0.64 = 0.023
taubin.UpdatePipeline()
wide = vtk_to_numpy(servermanager.Fetch(taubin).GetPoints().GetData()).astype(float)
bunny_points = vtk_to_numpy(original.GetPoints().GetData()).astype(float)
check(np.abs(wide - narrow).max() > 1e-6 and np.abs(wide - bunny_points).mean() != np.abs(narrow - bunny_points).mean(),
      "Taubin mu set in the panel reaches the filter")
Delete(taubin)

mushroom = OpenDataFile(os.path.join(DATA, "mushroom.off"))
param = IntrinsicParameterization(Input=mushroom)
check(param.ConformalWeight == 1 and param.AuthalicWeight == 0, "default energy: DCP")
check(param.Boundary == "Circle" and param.BoundarySpacing == "Arc Length", "default boundary")
# (Also with MPI: the mushroom is whole on one rank.  Data split over ranks
# would pass through with a warning: a parameterization needs the whole surface.)
param.UpdatePipeline()
flat = servermanager.Fetch(param)
uv = vtk_to_numpy(flat.GetPointData().GetTCoords())
check(uv.shape == (2337, 2) and np.isfinite(uv).all(), "UV texture coordinates on every point")
mean_angle = flat.GetFieldData().GetArray("MeanAngleDistortion").GetValue(0)
check(abs(mean_angle - 3.48) < 0.01, "DCP mean angle distortion as CGAL's (%.3f)" % mean_angle)
# Boundary handles and a line constraint from the panel's properties: the
# handles' points and the line's ends land on their targets, no flips, and
# (in this process) moving the handles again costs no new solve.
handled = IntrinsicParameterization(Input=mushroom)
right, left = int(np.argmax(uv[:, 0])), int(np.argmin(uv[:, 0]))
centre = int(np.argmin(np.linalg.norm(uv - [0.5, 0.5], axis=1)))
near = int(np.argmin(np.linalg.norm(uv - [0.5, 0.8], axis=1)))
handled.LineConstraints = [centre, near, 0.5, 0.5, 0.5, 0.75]
for shift in (0.1, 0.2):
    handled.BoundaryHandles = [right, uv[right, 0] + shift, uv[right, 1], left, uv[left, 0], uv[left, 1] - shift]
    handled.UpdatePipeline()
    moved = servermanager.Fetch(handled)
    moved_uv = vtk_to_numpy(moved.GetPointData().GetTCoords())
    targets = [[uv[right, 0] + shift, uv[right, 1]], [uv[left, 0], uv[left, 1] - shift], [0.5, 0.5], [0.5, 0.75]]
    check(np.abs(moved_uv[[right, left, centre, near]] - targets).max() < 1e-9
          and moved.GetFieldData().GetArray("FlippedTriangles").GetValue(0) == 0,
          "boundary handles and line constraint land on their targets (shift %g)" % shift)
    local = handled.GetClientSideObject()
    check(local is None or local.GetNumberOfSolves() <= 1,
          "moving the handles again solves nothing (%d solves)" % local.GetNumberOfSolves())
Delete(handled)
param.Boundary = "Natural"
param.UpdatePipeline()
natural_map = servermanager.Fetch(param)
natural = natural_map.GetFieldData().GetArray("MeanAngleDistortion").GetValue(0)
check(natural < 1.73, "natural conformal map below LSCM's 1.73 degrees (%.3f)" % natural)
# The mushroom split over the ranks (RedistributeDataSet): the pieces are
# gathered on rank 0 and every rank gets the map of its points, as in serial.
split_param = IntrinsicParameterization(Input=ExtractSurface(Input=RedistributeDataSet(Input=mushroom)))
split_param.Boundary = "Natural"
split_param.UpdatePipeline()
split_map = servermanager.Fetch(split_param)
matched = matching_points(split_map, natural_map, "split mushroom")
uv_difference = np.abs(vtk_to_numpy(split_map.GetPointData().GetTCoords())
                       - vtk_to_numpy(natural_map.GetPointData().GetArray("UV"))[matched]).max()
angles = vtk_to_numpy(split_map.GetCellData().GetArray("AngleDistortion"))
check(uv_difference < 1e-9 and angles.shape == (natural_map.GetNumberOfCells(),) and np.isfinite(angles).all()
      and abs(split_map.GetFieldData().GetArray("MeanAngleDistortion").GetValue(0) - natural) < 1e-9,
      "split mushroom over %d partition(s): the natural conformal map of serial (UV difference %g)"
      % (partitions, uv_difference))

# The atlas of a closed surface (section 4.2), split over the ranks: gathered
# and cut on rank 0, the other ranks' pieces empty; the whole cut surface as
# in serial.
elephant_surface = OpenDataFile(os.path.join(DATA, "elephant.off"))
atlas = SurfaceAtlas(Input=ExtractSurface(Input=RedistributeDataSet(Input=elephant_surface)))
check(atlas.ChartBoundary == "Square" and atlas.NumberOfCharts == 0 and atlas.MarginTexels == 2.0,
      "atlas defaults")
atlas.UpdatePipeline()
cut = servermanager.Fetch(atlas)
atlas_uv = vtk_to_numpy(cut.GetPointData().GetTCoords())
atlas_charts = cut.GetFieldData().GetArray("AtlasCharts").GetValue(0)
check(cut.GetNumberOfCells() == elephant_surface.GetDataInformation().GetNumberOfCells() and atlas_charts >= 2 and (atlas_uv >= 0).all() and (atlas_uv <= 1).all(),
      "atlas of the elephant over %d partition(s): %d charts, UV in [0,1]^2" % (partitions, atlas_charts))
atlas.SplitAtFeatures = 1
atlas.FeatureAngle = 75.0
atlas.UpdatePipeline()
sharp_cut = servermanager.Fetch(atlas)
check(list(atlas.SeamLabelsArray)[-1] == "None" and sharp_cut.GetFieldData().GetArray("AtlasCutEdges").GetValue(0) == 45
      and sharp_cut.GetFieldData().GetArray("AtlasCharts").GetValue(0) > atlas_charts,
      "atlas keeping the elephant's 45 edges sharper than 75 degrees as chart boundaries")

# The remesher (chapter 4) on the split elephant: gathered on rank 0, which
# holds the whole remesh with exactly the requested vertices.
remesher = SurfaceRemeshing(Input=ExtractSurface(Input=RedistributeDataSet(Input=elephant_surface)))
check(remesher.NumberOfVertices == 10000 and remesher.Importance == "Uniform" and remesher.Iterations == 25,
      "remesher defaults")
remesher.NumberOfVertices = 4000
remesher.UpdatePipeline()
remeshed = servermanager.Fetch(remesher)
elephant_info = elephant_surface.GetDataInformation()
same_genus = 2 * 4000 + elephant_info.GetNumberOfCells() - 2 * elephant_info.GetNumberOfPoints()  # F = 2V - 2 chi
check(remeshed.GetNumberOfPoints() == 4000 and remeshed.GetNumberOfCells() == same_genus
      and remeshed.GetFieldData().GetArray("RemeshMeanMinimumAngle").GetValue(0) > 48.0,
      "remesh of the elephant (genus 3) over %d partition(s): 4000 vertices, the same Euler characteristic" % partitions)
# The edited transfer function and the gradation through the panel's
# properties: a flat function gives the uniform remesh again, point for
# point; a steep one adapts it, and a gradation far wider than the elephant
# evens the importance out again.  (The density alone: the fidelity rounds,
# which move vertices onto the input's far vertices where a remesh leaves
# them, vary its edge lengths by a tenth to a quarter more where they are
# kept, and they are kept on some of these remeshes and not on others.)
remesher.FidelityRounds = 0
remesher.UpdatePipeline()
remeshed = servermanager.Fetch(remesher)
uniform_points = vtk_to_numpy(remeshed.GetPoints().GetData()).copy()
uniform_variation = remeshed.GetFieldData().GetArray("RemeshEdgeLengthVariation").GetValue(0)
remesher.Importance = "Maximum curvature max|k|"
remesher.TransferFunction = [0.0, 1.0, 5.0, 1.0]
remesher.UpdatePipeline()
flat = servermanager.Fetch(remesher)
check(flat.GetNumberOfPoints() == 4000 and np.allclose(vtk_to_numpy(flat.GetPoints().GetData()), uniform_points),
      "a flat transfer function remeshes as uniform")
remesher.TransferFunction = [0.0, 0.3, 3.0, 4.0]
remesher.UpdatePipeline()
adapted = servermanager.Fetch(remesher).GetFieldData().GetArray("RemeshEdgeLengthVariation").GetValue(0)
remesher.Gradation = 100.0
remesher.UpdatePipeline()
graded = servermanager.Fetch(remesher).GetFieldData().GetArray("RemeshEdgeLengthVariation").GetValue(0)
check(adapted > 1.3 * uniform_variation and graded < 1.2 * uniform_variation,
      "an edited transfer function adapts the remesh (edge-length variation %.3f -> %.3f), a wide gradation "
      "evens it out (%.3f)" % (uniform_variation, adapted, graded))
# The anisotropic mode through the panel's properties, on the split elephant.
remesher.Gradation = 0.0
remesher.FidelityRounds = 3
remesher.TransferFunction = []
remesher.Importance = "Uniform"
remesher.Anisotropy = "Principal curvatures"
remesher.UpdatePipeline()
anisotropic = servermanager.Fetch(remesher)
figures = anisotropic.GetFieldData().GetArray("RemeshMetricQuality")
check(anisotropic.GetNumberOfPoints() == 4000 and anisotropic.GetNumberOfCells() == same_genus
      and figures is not None and 0.8 < figures.GetValue(0) < 1.2
      and anisotropic.GetPointData().GetArray("Metric").GetNumberOfComponents() == 6,
      "anisotropic remesh of the elephant over %d partition(s): 4000 vertices, the same Euler characteristic, "
      "median edge %.2f in the metric" % (partitions, figures.GetValue(0) if figures else -1))

# Image denoising: the camera picture (8-bit greyscale) through the plugin.
image = PNGSeriesReader(FileNames=[os.path.join(DATA, "camera.png")])
image.UpdatePipeline()  # as in the GUI: the array lists need the data information
denoise = ImageBeltramiDenoising(Input=image)
check(denoise.ContrastScale == 0 and denoise.EdgeContrast == 1, "default alpha (automatic), gamma (Beltrami flow)")
check(denoise.StoppingRule == "Least Estimated Error" and denoise.NoiseLevel == 0,
      "default stop: least estimated error, noise level estimated")
check(denoise.Integration == "Explicit" and denoise.ColorSpace == "Automatic", "default integration, colours")
check(denoise.BoundaryHandling == "Linear" and denoise.NumberOfIterations == 10, "default boundary, iterations")
check(denoise.UseFixedPointsArray == 0, "no mask by default")
from beltrami import vtkImageBeltramiDenoising  # noqa: E402
from configure import configured  # noqa: E402
from vtkmodules.vtkIOImage import vtkPNGReader  # noqa: E402
from vtkmodules.vtkIOXML import vtkXMLPImageDataReader, vtkXMLPUnstructuredGridReader  # noqa: E402
png = vtkPNGReader()
png.SetFileName(os.path.join(DATA, "camera.png"))
png.Update()
original_image = vtk_to_numpy(png.GetOutput().GetPointData().GetScalars())
# Local flow (fixed explicit steps: each piece asks for ghost rings) and global
# flow (noise-level stop: each piece asks for the whole image); with MPI every
# rank computes its piece, and the pieces written as .pvti are the serial image.
for settings in (dict(ContrastScale=0.06, StoppingRule=0, NumberOfIterations=8),
                 dict(ContrastScale=0.06, StoppingRule=1, NumberOfIterations=50, NoiseLevel=10.0),
                 dict(ContrastScale=0.0, StoppingRule=2, NoiseLevel=0.0)):
    for key, value in settings.items():
        setattr(denoise, key, value)
    denoise.UpdatePipeline()
    serial = configured(vtkImageBeltramiDenoising(), png, NumberOfThreads=1, **settings)
    reference = vtk_to_numpy(serial.GetOutput().GetPointData().GetScalars())
    ours = vtk_to_numpy(saved_pieces(denoise).GetPointData().GetArray(0))
    check(ours.shape == reference.shape and np.array_equal(ours, reference),
          "image denoising through the plugin over %d partition(s) equals the serial VTK filter (%s): "
          "%d pixels differ" % (partitions, settings,
                                int(np.sum(ours != reference)) if ours.shape == reference.shape else -1))
    # The automatic settings find the photo's own noise (about 0.5 grey
    # levels) and smooth little; the others were set for noise of 10 levels.
    check(np.abs(ours.astype(float) - original_image).mean() > (0.03 if settings["StoppingRule"] == 2 else 0.5),
          "the image was smoothed")

# Beltrami Operators on the camera image: with MPI every rank computes its
# piece (one ring of neighbours with a given contrast scale; the whole image
# for the automatic one), and the pieces are the serial VTK filter's arrays.
from beltrami import vtkBeltramiOperators  # noqa: E402
operators = BeltramiOperators(Input=image)
check(operators.ContrastScale == 0 and operators.NoiseLevel == 0 and operators.BoundaryHandling == "Linear",
      "Beltrami operators defaults: automatic contrast, estimated noise, linear continuation")
for contrast in (0.05, 0.0):
    operators.ContrastScale = contrast
    operators.UpdatePipeline()
    serial = configured(vtkBeltramiOperators(), png, ContrastScale=contrast)
    pieces = saved_pieces(operators)
    for name in ("MeanCurvatureNormal", "BeltramiOperator", "GaussianCurvature", "EdgeIndicator"):
        ours = vtk_to_numpy(pieces.GetPointData().GetArray(name))
        reference = vtk_to_numpy(serial.GetOutput().GetPointData().GetArray(name))
        check(ours.shape == reference.shape and np.abs(ours - reference).max() <= 1e-12 * np.abs(reference).max(),
              "Beltrami operators over %d partition(s) equal the serial filter (%s, contrast %g)"
              % (partitions, name, contrast))

sphere = Sphere(ThetaResolution=64, PhiResolution=64)
elevation = Elevation(Input=sphere)
elevation.LowPoint = [0.0, 0.0, -0.5]
elevation.HighPoint = [0.0, 0.0, 0.5]
elevation.UpdatePipeline()
surface = SurfaceDataDenoising(Input=elevation)
check(surface.Units == "Mean Edge Length" and surface.TimeStep == 0.1, "surface denoising defaults")
check(surface.Integration == "Semi-Implicit" and surface.UseFixedPointsArray == 0,
      "surface denoising: semi-implicit, no mask by default")
surface.ArrayToSmooth = ["POINTS", "Elevation"]
surface.UpdatePipeline()
check(surface.PointData["Elevation"] is not None, "surface denoising writes the array")
# The sphere source splits into pieces: with MPI the pieces are smoothed whole
# on rank 0 and each rank gets its points' values, those of a serial run.
from beltrami import vtkSurfaceDataDenoising  # noqa: E402
from vtkmodules.vtkFiltersCore import vtkElevationFilter  # noqa: E402


def serial_denoised(source, flow, **settings):
    """`flow` (a Beltrami denoising filter) in this process on the elevation
    (z from -0.5 to 0.5, as the Elevation proxies here) of `source`."""
    elevation = vtkElevationFilter()
    elevation.SetInputConnection(source.GetOutputPort())
    elevation.SetLowPoint(0.0, 0.0, -0.5)
    elevation.SetHighPoint(0.0, 0.0, 0.5)
    elevation.Update()
    configured_flow = configured(flow, elevation.GetOutput(), update=False, **settings)
    configured_flow.SetInputArrayToProcess(0, 0, 0, 0, "Elevation")
    configured_flow.Update()
    return elevation.GetOutput(), configured_flow.GetOutput()


serial_sphere = vtkSphereSource()
serial_sphere.SetThetaResolution(64)
serial_sphere.SetPhiResolution(64)
_, serial_surface = serial_denoised(serial_sphere, vtkSurfaceDataDenoising())
split_surface = servermanager.Fetch(surface)
matched = matching_points(split_surface, serial_surface, "denoised sphere", 9)
difference = np.abs(vtk_to_numpy(split_surface.GetPointData().GetArray("Elevation"))
                    - vtk_to_numpy(serial_surface.GetPointData().GetArray("Elevation"))[matched]).max()
check(difference < 1e-9, "surface denoising over %d partition(s) equals the serial result (difference %g)"
      % (partitions, difference))

# Fairing of the bunny split over the ranks: solved over the ranks, the
# serial points to the solver tolerance (test_distributed_fairing.py checks
# more; the volume is kept exactly, as in serial).
split_bunny = ExtractSurface(Input=RedistributeDataSet(Input=reader))
split_fairing = ImplicitFairing(Input=split_bunny)
split_fairing.TimeStep = 2.0
split_fairing.UpdatePipeline()
matched = matching_points(servermanager.Fetch(split_bunny), original, "faired bunny")
difference = np.abs(vtk_to_numpy(servermanager.Fetch(split_fairing).GetPoints().GetData())
                    - vtk_to_numpy(smoothed.GetPoints().GetData())[matched]).max()
serial_move = np.abs(vtk_to_numpy(smoothed.GetPoints().GetData()) - vtk_to_numpy(original.GetPoints().GetData())).max()
check(difference < 1e-2 * serial_move,
      "fairing over %d partition(s) equals the serial result (difference %g, move %g)"
      % (partitions, difference, serial_move))

filled = TetGenTetrahedralize(Input=OpenDataFile(os.path.join(DATA, "elephant.off")))
check(filled.RadiusEdgeRatio == 2.0 and filled.PreserveSurface == 1, "TetGen defaults")
filled.UpdatePipeline()
check(filled.GetDataInformation().GetNumberOfCells() > 8000, "TetGen tetrahedra through the plugin")


def tetrahedra_volume(grid):
    p = vtk_to_numpy(grid.GetPoints().GetData()).astype(float)
    t = vtk_to_numpy(grid.GetCells().GetConnectivityArray()).reshape(-1, 4)
    return float(np.abs(np.einsum("ij,ij->i", p[t[:, 1]] - p[t[:, 0]],
                                  np.cross(p[t[:, 2]] - p[t[:, 0]], p[t[:, 3]] - p[t[:, 0]]))).sum()) / 6


# The elephant's surface split over the ranks (open pieces): gathered on rank
# 0 and meshed whole there; the same enclosed volume as in serial.
split_filled = TetGenTetrahedralize(Input=ExtractSurface(Input=RedistributeDataSet(Input=filled.Input)))
split_filled.UpdatePipeline()
check(abs(tetrahedra_volume(servermanager.Fetch(split_filled)) / tetrahedra_volume(servermanager.Fetch(filled)) - 1)
      < 1e-9, "TetGen over %d partition(s): the whole elephant's volume" % partitions)

wavelet = Wavelet(WholeExtent=[0, 9, 0, 9, 0, 9])
if partitions == 1:
    with tempfile.TemporaryDirectory() as tmp:
        vdb = os.path.join(tmp, "wavelet.vdb")
        SaveData(vdb, proxy=wavelet)
        opened = OpenDataFile(vdb)
        check(opened is not None and opened.GetXMLName() == "OpenVDBReader", "OpenDataFile picks the OpenVDB reader")
        opened.UpdatePipeline()  # the array lists need the data information
        smoothed_vdb = ImageBeltramiDenoising(Input=opened)
        smoothed_vdb.ContrastScale = 0.1
        smoothed_vdb.StoppingRule = "Fixed Number Of Iterations"  # the wavelet has no noise to find
        smoothed_vdb.NumberOfIterations = 3
        smoothed_vdb.TimeStep = 0.05
        smoothed_vdb.UpdatePipeline()
        before_vdb = vtk_to_numpy(servermanager.Fetch(opened).GetPointData().GetScalars())
        after_vdb = vtk_to_numpy(servermanager.Fetch(smoothed_vdb).GetPointData().GetScalars())
        check(after_vdb.shape == (1000,) and np.std(after_vdb) < np.std(before_vdb), "a .vdb volume denoised in ParaView")
        sparse = OpenVDBSparseReader(FileName=vdb)
        sparse.UpdatePipeline()
        check(sparse.GetDataInformation().GetNumberOfPoints() == 1000
              and sparse.GetDataInformation().GetNumberOfCells() == 729, "the active-voxel reader through the plugin")
tets = Tetrahedralize(Input=wavelet)
tets.UpdatePipeline()
volume_denoise = TetrahedralBeltramiDenoising(Input=tets)
check(volume_denoise.Integration == "Semi-Implicit" and volume_denoise.UseFixedPointsArray == 0,
      "tetrahedral denoising defaults")
volume_denoise.ContrastScale = 0.1
volume_denoise.UpdatePipeline()
smoothed_volume = servermanager.Fetch(volume_denoise)
if partitions == 1:
    before = vtk_to_numpy(servermanager.Fetch(tets).GetPointData().GetArray("RTData"))
    after = vtk_to_numpy(smoothed_volume.GetPointData().GetArray("RTData"))
    check(after.shape == before.shape and np.std(after) < np.std(before), "tetrahedral denoising smooths")
# The elephant's tetrahedra (meshed on the rank that read the surface) split
# over the ranks: with MPI smoothed over the ranks (each its piece), the
# values of a serial run at every point.
from beltrami import vtkOFFReader, vtkTetGenTetrahedralizer, vtkTetrahedralBeltramiDenoising  # noqa: E402
elephant_elevation = Elevation(Input=filled)
elephant_elevation.LowPoint = [0.0, 0.0, -0.5]
elephant_elevation.HighPoint = [0.0, 0.0, 0.5]
split_volume = TetrahedralBeltramiDenoising(Input=RedistributeDataSet(Input=elephant_elevation))
split_volume.ArrayToSmooth = ["POINTS", "Elevation"]
split_volume.ContrastScale = 5.0
with tempfile.TemporaryDirectory() as tmp:  # every rank's piece
    path = os.path.join(tmp, "denoised.pvtu")
    SaveData(path, proxy=split_volume)
    all_pieces = vtkXMLPUnstructuredGridReader()
    all_pieces.SetFileName(path)
    all_pieces.Update()
    split_values = all_pieces.GetOutput()
elephant = vtkOFFReader()
elephant.SetFileName(os.path.join(DATA, "elephant.off"))
serial_tetgen = vtkTetGenTetrahedralizer()
serial_tetgen.SetInputConnection(elephant.GetOutputPort())
serial_elevation, serial_volume = serial_denoised(serial_tetgen, vtkTetrahedralBeltramiDenoising(),
                                                  ContrastScale=5.0)
matched = matching_points(split_values, serial_volume, "denoised elephant volume")
before = vtk_to_numpy(serial_elevation.GetPointData().GetArray("Elevation"))
after = vtk_to_numpy(split_values.GetPointData().GetArray("Elevation"))
reference = vtk_to_numpy(serial_volume.GetPointData().GetArray("Elevation"))[matched]
# (The conjugate-gradient solves see the unknowns in another order: equal
# within their tolerance.)
check(np.abs(reference - before[matched]).max() > 1e-3 and np.abs(after - reference).max() < 1e-7,
      "tetrahedral denoising over %d partition(s) smooths as in serial (difference %g)"
      % (partitions, np.abs(after - reference).max()))

# Surface Line Drawing following a view's camera (beltrami_paraview): a
# sphere's contour is the circle where p.(c - p) = 0, i.e. p.c = R^2, for the
# camera c, wherever the camera goes.  (No rendering here: the test runs
# without a display; setting the view's camera properties moves its
# vtkCamera as interaction does.)
import beltrami_paraview  # noqa: E402
sphere = Sphere(Radius=1.0, ThetaResolution=128, PhiResolution=128)
drawing = SurfaceLineDrawing(Input=sphere)
check(drawing.SuggestiveContourThreshold == 0.1 and drawing.CreaseAngle == 40 and drawing.Contours == 1,
      "line drawing defaults")
view = CreateRenderView()
stop = beltrami_paraview.follow_camera(drawing, view)
for position in ((0.0, 0.0, 5.0), (3.0, -4.0, 2.0)):
    view.CameraPosition = list(position)
    view.CameraFocalPoint = [0.0, 0.0, 0.0]
    check(np.allclose(list(drawing.CameraPosition), position), "the drawing follows the camera to %s" % (position,))
    lines = servermanager.Fetch(drawing)
    if partitions == 1:
        p = vtk_to_numpy(lines.GetPoints().GetData())
        kinds = vtk_to_numpy(lines.GetCellData().GetArray("LineType"))
        residual = np.abs(p @ np.array(position) - 1.0).max()
        check(lines.GetNumberOfCells() >= 1 and set(kinds) == {0} and residual < 0.02,
              "the sphere's contour for the camera at %s (p.c - 1 up to %.4f)" % (position, residual))
stop()
view.CameraPosition = [0.0, 5.0, 0.0]
check(np.allclose(list(drawing.CameraPosition), (3.0, -4.0, 2.0)), "the drawing stops following")
Delete(drawing)
Delete(view)

with tempfile.TemporaryDirectory() as tmp:
    path = os.path.join(tmp, "bunny.off")
    SaveData(path, proxy=reader)
    again = OpenDataFile(path)
    again.UpdatePipeline()
    check(again.GetDataInformation().GetNumberOfPoints() == 37706, "OFF writer round trip")
print("pvpython plugin test passed")
