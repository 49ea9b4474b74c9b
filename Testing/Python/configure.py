"""The helpers the Python tests share: a VTK filter set up from keyword
settings, the way the tests and benchmarks describe their runs, and the
checks of the pvpython/pvbatch scripts."""
import sys


def configured(f, source=None, update=True, **settings):
    """f with Set<Key>(value) for every keyword, fed by source (a data
    object or an algorithm; None: left as it is), updated unless update is
    False.  Returns f."""
    if source is not None:
        if hasattr(source, "GetOutputPort"):
            f.SetInputConnection(source.GetOutputPort())
        else:
            f.SetInputData(source)
    for key, value in settings.items():
        getattr(f, "Set" + key)(value)
    if update:
        f.Update()
    return f


def check(condition, message, quiet=False):
    """A pvpython/pvbatch script's check: "FAILED: message" and exit 1 when
    `condition` fails (ctest's FAIL_REGULAR_EXPRESSION), else "ok: message"
    unless quiet."""
    if not condition:
        print("FAILED: " + message)
        sys.exit(1)
    if not quiet:
        print("ok: " + message)


def report(data, name):
    """The values of the field array `name` of `data`."""
    a = data.GetFieldData().GetArray(name)
    return [a.GetValue(k) for k in range(a.GetNumberOfTuples())]


def fetch_pieces(proxy):
    """Every rank's piece of a pvbatch proxy's output (unstructured grid or
    image), joined: written as a parallel XML file and read back
    (servermanager.Fetch gives rank 0's piece of those only)."""
    import os
    import tempfile
    from paraview.simple import SaveData
    from vtkmodules.vtkIOXML import vtkXMLPImageDataReader, vtkXMLPUnstructuredGridReader
    image = proxy.GetDataInformation().GetDataClassName() == "vtkImageData"
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "pieces.pvti" if image else "pieces.pvtu")
        SaveData(path, proxy=proxy)
        reader = vtkXMLPImageDataReader() if image else vtkXMLPUnstructuredGridReader()
        reader.SetFileName(path)
        reader.Update()
        return reader.GetOutput()


def rank_rows(proxy, array, names):
    """Per rank of a pvbatch run, the first len(names) values of the field
    array `array` of the proxy's output (-1 where it has none): a numpy
    array per name, one value per rank."""
    from paraview import servermanager
    from paraview.simple import ProgrammableFilter
    from vtkmodules.util.numpy_support import vtk_to_numpy
    rows = ProgrammableFilter(Input=proxy, OutputDataSetType="vtkPolyData")
    rows.Script = """
from vtkmodules.vtkCommonCore import vtkIdTypeArray, vtkPoints
d = self.GetInput().GetFieldData().GetArray(%r)
out = self.GetOutput()
p = vtkPoints()
p.InsertNextPoint(0.0, 0.0, 0.0)
out.SetPoints(p)
for k, name in enumerate(%r):
    a = vtkIdTypeArray()
    a.SetName(name)
    a.InsertNextValue(int(d.GetValue(k)) if d else -1)
    out.GetPointData().AddArray(a)
""" % (array, list(names))
    table = servermanager.Fetch(rows).GetPointData()
    return [vtk_to_numpy(table.GetArray(name)) for name in names]


def check_split_flow(label, ranks, result, whole, reference, array, tolerance, least_risk):
    """The checks of a graph flow split over `ranks` ranks of pvbatch
    (`result`: every rank's piece, joined) against the serial run
    (`reference`, of the `whole` input with its point array "mask"): the
    pieces cover the input (points matched by coordinates), the serial run
    smoothed, the values equal to `tolerance` of its largest change, the
    same steps, noise estimate and settings (and with the least-risk stop
    the same estimated errors), the masked points kept."""
    import numpy as np
    from vtkmodules.util.numpy_support import vtk_to_numpy
    index = {tuple(x): i for i, x in enumerate(vtk_to_numpy(whole.GetPoints().GetData()))}
    ids = np.array([index.get(tuple(x), -1) for x in vtk_to_numpy(result.GetPoints().GetData())])
    check(ids.min() >= 0 and len(set(ids)) == whole.GetNumberOfPoints(), "%s: the pieces cover the input" % label)
    ours = vtk_to_numpy(result.GetPointData().GetArray(array))
    theirs = vtk_to_numpy(reference.GetPointData().GetArray(array))[ids]
    before = vtk_to_numpy(whole.GetPointData().GetArray(array))
    moved = np.abs(vtk_to_numpy(reference.GetPointData().GetArray(array)) - before).max()
    difference = np.abs(ours - theirs).max()
    check(moved > 0.01, "%s: the serial run smoothed the data (largest change %.3g)" % (label, moved))
    check(difference <= tolerance * moved, "%s over %d rank(s) equals the serial result: difference %.3g <= %.0e x %.3g"
          % (label, ranks, difference, tolerance, moved))
    for name in ("FlowIterations", "EstimatedNoiseLevel", "FlowNoiseLevel", "FlowContrastScale"):
        a, b = report(result, name), report(reference, name)
        check(np.allclose(a, b, rtol=1e-9, atol=0), "%s: %s %s as serial %s" % (label, name, a, b))
    if least_risk:
        a, b = report(result, "FlowEstimatedError"), report(reference, "FlowEstimatedError")
        check(np.allclose(a, b, rtol=1e-6), "%s: estimated error %s as serial %s" % (label, a, b))
    kept = vtk_to_numpy(whole.GetPointData().GetArray("mask"))[ids] != 0
    check(np.array_equal(ours[kept], before[ids][kept]), "%s: fixed points kept" % label)
