"""Demo: the default smoothing step on a noisy scan split over the
ranks of pvbatch, each rank smoothing its own piece and every solve running
over all ranks.  Writes the result coloured by the rank that owns each point
(<out>/bunny00_distributed_ranks.png) and prints each rank's share, the error
against the clean scan and the largest difference to a serial run.  Then
denoises noisy point data on the split bunny at the defaults (noise
estimated over the ranks, least-risk stop), prints the error and the
difference to a serial run, and writes noisy | denoised
(<out>/bunny00_distributed_denoised.png).  Last, denoises a real MRI volume
at the defaults, each rank reading its piece and a ring, prints the
difference to a serial run and writes the middle slice noisy | denoised
(<out>/mri_distributed_denoised.png).  And parameterizes the mushroom (a
disk) split over the ranks, the conformal system solved over them, prints the
iterations and the difference to a serial run and writes its checkerboard
(<out>/mushroom_distributed_checkerboard.png).  And draws the split bunny
(contours, suggestive contours, ridges, valleys), each rank on its piece and
rank 0 chaining the segments, prints the line counts against a serial run and
writes the drawing (<out>/bunny00_distributed_line_drawing.png).

Run:  mpirun -np 2 pvbatch Examples/distributed_smoothing_demo.py [mesh.off] [out_dir]
(as root add --allow-run-as-root --oversubscribe; xvfb-run -a in front
where there is no display)."""
import os
import sys
import tempfile

import numpy as np
from paraview import servermanager, simple
from paraview.simple import ExtractSurface, ProgrammableFilter, RedistributeDataSet, XMLPolyDataReader
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkLookupTable
from vtkmodules.vtkIOXML import vtkXMLPolyDataWriter
from vtkmodules.vtkRenderingCore import vtkActor, vtkPolyDataMapper

from beltrami import (vtkImplicitFairing, vtkIntrinsicParameterization, vtkOFFReader, vtkSurfaceDataDenoising,
                      vtkSurfaceLineDrawing)
from beltrami.pipelines import (capture, framed_renderer, line_type_actor, noisy_along_normals, render_checkerboard,
                                rms_distance, snapshot, white_surface_actor, write_vtp)

HERE = os.path.dirname(os.path.abspath(__file__))
DEFAULT_MESH = os.path.join(HERE, "..", "Testing", "Data", "bunny00.off")


def split_over_ranks(polydata, path):
    """`polydata` written to `path`, read whole on rank 0 and cut into one
    piece per rank (the pipeline; `path` must last until it has run)."""
    writer = vtkXMLPolyDataWriter()
    writer.SetInputData(polydata)
    writer.SetFileName(path)
    writer.Write()
    return ExtractSurface(Input=RedistributeDataSet(Input=XMLPolyDataReader(FileName=[path])))


def main(argv):
    mesh_path = argv[1] if len(argv) > 1 else DEFAULT_MESH
    out_dir = argv[2] if len(argv) > 2 else "demo-output"
    os.makedirs(out_dir, exist_ok=True)
    if not hasattr(simple, "ImplicitFairing"):  # (loaded at start where PV_PLUGIN_PATH names its folder)
        simple.LoadPlugin(os.environ["BELTRAMI_PLUGIN"])
    ranks = servermanager.ActiveConnection.GetNumberOfDataPartitions()
    reader = vtkOFFReader()
    reader.SetFileName(mesh_path)
    reader.Update()
    clean = vtk_to_numpy(reader.GetOutput().GetPoints().GetData()).astype(float)
    diagonal = float(np.linalg.norm(clean.max(0) - clean.min(0)))
    noisy = noisy_along_normals(reader.GetOutput(), 0.003 * diagonal, seed=1)
    serial = vtkImplicitFairing()
    serial.SetInputData(noisy)
    serial.Update()
    with tempfile.TemporaryDirectory() as tmp:
        split = split_over_ranks(noisy, os.path.join(tmp, "noisy.vtp"))
        faired = simple.ImplicitFairing(Input=split)
        ranked = ProgrammableFilter(Input=faired)
        ranked.Script = """
import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk
from vtkmodules.vtkParallelCore import vtkMultiProcessController
out = self.GetOutput()
out.ShallowCopy(self.GetInput())
rank = numpy_to_vtk(np.full(out.GetNumberOfPoints(), vtkMultiProcessController.GetGlobalController()
                            .GetLocalProcessId(), dtype=np.int32), deep=1)
rank.SetName("Rank")
out.GetPointData().AddArray(rank)
shares = self.GetInput().GetFieldData().GetArray("FairingDistribution")
owned = numpy_to_vtk(np.full(out.GetNumberOfPoints(), shares.GetValue(0) if shares else out.GetNumberOfPoints(),
                             dtype=np.int64), deep=1)
owned.SetName("OwnedOnRank")
out.GetPointData().AddArray(owned)
"""
        result = servermanager.Fetch(ranked)  # the pieces appended on rank 0
    points = vtk_to_numpy(result.GetPoints().GetData()).astype(float)
    index = {tuple(x): i for i, x in enumerate(vtk_to_numpy(noisy.GetPoints().GetData()))}
    noisy_pieces = np.array([index[tuple(x)] for x in vtk_to_numpy(servermanager.Fetch(split).GetPoints().GetData())])
    reference = vtk_to_numpy(serial.GetOutput().GetPoints().GetData()).astype(float)[noisy_pieces]
    rank = vtk_to_numpy(result.GetPointData().GetArray("Rank"))
    owned = vtk_to_numpy(result.GetPointData().GetArray("OwnedOnRank"))
    print("mesh: %s (%d points), noise 0.3%% of the diagonal, split over %d ranks" % (
        mesh_path, len(clean), ranks))
    for r in range(ranks):
        held = rank == r
        print("  rank %d: owns %d points (%.1f%%)" % (r, owned[held][0] if held.any() else 0,
                                                      100.0 * (owned[held][0] if held.any() else 0) / len(clean)))
    print("  RMS distance to the clean mesh / diagonal: noisy %.5f, smoothed over the ranks %.5f" % (
        rms_distance(noisy, clean) / diagonal, np.sqrt(np.mean(np.sum((points - clean[noisy_pieces]) ** 2, 1)))
        / diagonal))
    print("  largest difference to the serial run / diagonal: %.2e (the solver tolerance's reach)" % (
        np.abs(points - reference).max() / diagonal))
    name = os.path.splitext(os.path.basename(mesh_path))[0]
    write_vtp(result, os.path.join(out_dir, name + "_distributed.vtp"))
    colours = ranks if ranks > 2 else 2  # (not max(): the plugin's namespace has numpy_interface's)
    lut = vtkLookupTable()
    lut.SetNumberOfTableValues(colours)
    palette = [(0.12, 0.47, 0.71), (1.0, 0.5, 0.05), (0.17, 0.63, 0.17), (0.84, 0.15, 0.16)]
    for r in range(colours):
        lut.SetTableValue(r, *palette[r % len(palette)], 1.0)
    lut.Build()
    result.GetPointData().SetActiveScalars("Rank")
    mapper = vtkPolyDataMapper()
    mapper.SetInputData(result)
    mapper.SetLookupTable(lut)
    mapper.SetScalarRange(0, colours - 1)
    actor = vtkActor()
    actor.SetMapper(mapper)
    png = os.path.join(out_dir, name + "_distributed_ranks.png")
    snapshot(actor, png, (800, 800), zoom=1.3)
    print("wrote %s" % png)
    denoise(reader.GetOutput(), os.path.join(out_dir, name + "_distributed_denoised.png"))
    denoise_volume(os.path.join(HERE, "..", "Testing", "Data", "mri_s0_10slices.vti"),
                   os.path.join(out_dir, "mri_distributed_denoised.png"))
    parameterize(os.path.join(HERE, "..", "Testing", "Data", "mushroom.off"),
                 os.path.join(out_dir, "mushroom_distributed_checkerboard.png"))
    draw_lines(reader.GetOutput(), os.path.join(out_dir, name + "_distributed_line_drawing.png"))
    return 0


def draw_lines(mesh, png):
    """The mesh split over the ranks drawn from a camera (each rank finds the
    segments of its piece, rank 0 chains them), against a serial drawing."""
    renderer = framed_renderer([white_surface_actor(mesh)], (0, 1, 0), (0.8, 0.2, 1), 1.2)
    settings = dict(Ridges=1, Valleys=1, CameraPosition=list(renderer.GetActiveCamera().GetPosition()))
    serial = vtkSurfaceLineDrawing()
    serial.SetInputData(mesh)
    for key, value in settings.items():
        getattr(serial, "Set" + key)(value)
    serial.Update()
    with tempfile.TemporaryDirectory() as tmp:
        drawing = simple.SurfaceLineDrawing(Input=split_over_ranks(mesh, os.path.join(tmp, "drawn.vtp")), **settings)
        lines = servermanager.Fetch(drawing)
        split = servermanager.Fetch(drawing, idx=1).GetFieldData().GetArray("LineDrawingDistribution") is not None

    def counts(polydata):
        return np.bincount(vtk_to_numpy(polydata.GetCellData().GetArray("LineType")), minlength=5)[:5].tolist()
    print("line drawing of the mesh %s: contours, suggestive contours, highlights, ridges, valleys: %s polylines, "
          "%d points (serial %s, %d points)" % ("split over the ranks" if split else "on one rank (serial)",
                                               counts(lines), lines.GetNumberOfPoints(), counts(serial.GetOutput()),
                                               serial.GetOutput().GetNumberOfPoints()))
    renderer.AddActor(line_type_actor(lines))
    capture(renderer, png, (800, 800))
    print("wrote %s" % png)


def parameterize(path, png):
    """The disk at `path` split over the ranks (with global point ids, so the
    outer loop starts where a serial run's does) and parameterized at the
    defaults over them, against serial."""
    from vtkmodules.util.numpy_support import numpy_to_vtk
    from vtkmodules.vtkCommonCore import VTK_ID_TYPE
    reader = vtkOFFReader()
    reader.SetFileName(path)
    reader.Update()
    mesh = reader.GetOutput()
    ids = numpy_to_vtk(np.arange(mesh.GetNumberOfPoints()), deep=1, array_type=VTK_ID_TYPE)
    ids.SetName("Ids")
    mesh.GetPointData().SetGlobalIds(ids)
    serial = vtkIntrinsicParameterization()
    serial.SetInputData(mesh)
    serial.Update()
    with tempfile.TemporaryDirectory() as tmp:
        mapped = simple.IntrinsicParameterization(Input=split_over_ranks(mesh, os.path.join(tmp, "disk.vtp")))
        result = servermanager.Fetch(mapped)
    index = {tuple(x): i for i, x in enumerate(vtk_to_numpy(mesh.GetPoints().GetData()))}
    at = np.array([index[tuple(x)] for x in vtk_to_numpy(result.GetPoints().GetData())])
    ours = vtk_to_numpy(result.GetPointData().GetArray("UV"))
    theirs = vtk_to_numpy(serial.GetOutput().GetPointData().GetArray("UV"))[at]
    iterations = result.GetFieldData().GetArray("ParameterizationIterations")
    print("conformal map of %s split over the ranks: %s; mean angle distortion %.3f deg (serial %.3f); largest "
          "difference to the serial map %.1e" % (
              os.path.basename(path), "%d CG iterations over the ranks" % iterations.GetValue(0) if iterations
              else "one rank: the serial solve", result.GetFieldData().GetArray("MeanAngleDistortion").GetValue(0),
              serial.GetMeanAngleDistortion(), np.abs(ours - theirs).max()))
    render_checkerboard(result, png)
    print("wrote %s" % png)


def denoise(mesh, png):
    """Point data f = sin(40 x) cos(30 y) plus Gaussian noise of 0.15 on the
    mesh split over the ranks, denoised at the defaults, against serial."""
    from vtkmodules.util.numpy_support import numpy_to_vtk
    from vtkmodules.vtkCommonDataModel import vtkPolyData
    p = vtk_to_numpy(mesh.GetPoints().GetData()).astype(float)
    clean = np.sin(40 * p[:, 0]) * np.cos(30 * p[:, 1])
    data = vtkPolyData()
    data.ShallowCopy(mesh)
    f = numpy_to_vtk(clean + np.random.default_rng(3).normal(0.0, 0.15, len(clean)), deep=1)
    f.SetName("f")
    data.GetPointData().SetScalars(f)
    serial = vtkSurfaceDataDenoising()
    serial.SetInputData(data)
    serial.Update()
    with tempfile.TemporaryDirectory() as tmp:
        split = split_over_ranks(data, os.path.join(tmp, "noisy_data.vtp"))
        denoised = simple.SurfaceDataDenoising(Input=split)
        denoised.ArrayToSmooth = ["POINTS", "f"]
        result = servermanager.Fetch(denoised)
    index = {tuple(x): i for i, x in enumerate(p)}
    ids = np.array([index[tuple(x)] for x in vtk_to_numpy(result.GetPoints().GetData()).astype(float)])
    ours = vtk_to_numpy(result.GetPointData().GetArray("f"))
    theirs = vtk_to_numpy(serial.GetOutput().GetPointData().GetArray("f"))[ids]
    fd = result.GetFieldData()
    print("point data on the split mesh, noise 0.15: estimated %.4f over the ranks, %d steps; RMS error noisy "
          "%.4f, denoised over the ranks %.4f; largest difference to the serial run %.1e" % (
              fd.GetArray("EstimatedNoiseLevel").GetValue(0), fd.GetArray("FlowIterations").GetValue(0),
              np.sqrt(np.mean((vtk_to_numpy(f) - clean) ** 2)), np.sqrt(np.mean((ours - clean[ids]) ** 2)),
              np.abs(ours - theirs).max()))
    actors = []
    width = float(p[:, 0].max() - p[:, 0].min())
    for k, shown in enumerate((data, result)):
        shown.GetPointData().SetActiveScalars("f")
        mapper = vtkPolyDataMapper()
        mapper.SetInputData(shown)
        mapper.SetScalarRange(-1.0, 1.0)
        actor = vtkActor()
        actor.SetMapper(mapper)
        actor.SetPosition(1.15 * width * k, 0.0, 0.0)
        actors.append(actor)
    capture(framed_renderer(actors, zoom=1.8), png, (1200, 600))
    print("wrote %s" % png)


def denoise_volume(path, png):
    """An MRI volume denoised at the defaults over the ranks, each rank
    reading its piece and a ring (not the whole volume), against serial;
    writes the middle slice noisy | denoised."""
    from vtkmodules.vtkIOXML import vtkXMLImageDataReader, vtkXMLPImageDataReader
    from beltrami import vtkImageBeltramiDenoising
    from beltrami.pipelines import write_side_by_side
    reader = vtkXMLImageDataReader()
    reader.SetFileName(path)
    serial = vtkImageBeltramiDenoising()
    serial.SetInputConnection(reader.GetOutputPort())
    serial.Update()
    denoised = simple.ImageBeltramiDenoising(Input=simple.XMLImageDataReader(FileName=[path]))
    denoised.ArrayToSmooth = ["POINTS", "MRI"]
    with tempfile.TemporaryDirectory() as tmp:  # every rank's piece, joined
        pieces = os.path.join(tmp, "mri.pvti")
        simple.SaveData(pieces, proxy=denoised)
        joined = vtkXMLPImageDataReader()
        joined.SetFileName(pieces)
        joined.Update()
        result = joined.GetOutput()
    ours = vtk_to_numpy(result.GetPointData().GetArray("MRI")).astype(float)
    theirs = vtk_to_numpy(serial.GetOutput().GetPointData().GetArray("MRI")).astype(float)
    noisy = vtk_to_numpy(reader.GetOutput().GetPointData().GetArray("MRI")).astype(float)
    fd = result.GetFieldData()
    nx, ny, nz = reader.GetOutput().GetDimensions()
    print("MRI volume %d x %d x %d split over the ranks (each reads its piece and a ring): noise estimated %.4f, "
          "%d steps, largest change %.4f; largest difference to the serial run %.1e" % (
              nx, ny, nz, fd.GetArray("EstimatedNoiseLevel").GetValue(0), fd.GetArray("FlowIterations").GetValue(0),
              np.abs(theirs - noisy).max(), np.abs(ours - theirs).max()))
    scale = 255.0 / np.percentile(noisy, 99.5)  # (a few bright voxels would darken the rest)

    def middle(values):  # the middle slice, top row first, 3x larger
        plane = values.reshape(nz, ny, nx)[nz // 2][::-1] * scale
        return np.kron(np.clip(plane, 0, 255), np.ones((3, 3))).astype(np.uint8)[:, :, None]
    write_side_by_side(middle(noisy), middle(ours), png)
    print("wrote %s" % png)


if __name__ == "__main__":
    main(sys.argv)  # (no sys.exit: pvbatch must finalize MPI on every rank)
