"""Demo (issue 28): the default smoothing step on a noisy scan split over the
ranks of pvbatch, each rank smoothing its own piece and every solve running
over all ranks.  Writes the result coloured by the rank that owns each point
(<out>/bunny00_distributed_ranks.png) and prints each rank's share, the error
against the clean scan and the largest difference to a serial run.

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

from beltrami import vtkImplicitFairing, vtkOFFReader
from beltrami.pipelines import noisy_along_normals, rms_distance, snapshot, write_vtp

HERE = os.path.dirname(os.path.abspath(__file__))
DEFAULT_MESH = os.path.join(HERE, "..", "Testing", "Data", "bunny00.off")


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
        path = os.path.join(tmp, "noisy.vtp")
        writer = vtkXMLPolyDataWriter()
        writer.SetInputData(noisy)
        writer.SetFileName(path)
        writer.Write()
        # Read whole on rank 0, cut into one piece per rank, smoothed in place.
        split = ExtractSurface(Input=RedistributeDataSet(Input=XMLPolyDataReader(FileName=[path])))
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
    return 0


if __name__ == "__main__":
    main(sys.argv)  # (no sys.exit: pvbatch must finalize MPI on every rank)
