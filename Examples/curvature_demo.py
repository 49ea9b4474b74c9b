#!/usr/bin/python3
"""Beltrami demo: discrete curvatures of a real mesh.

Reads an OFF mesh (default: the bundled Stanford bunny scan), runs
vtkDiscreteCurvatures, writes a .vtp with all the arrays and a PNG of the
mean curvature, and prints a short report (ranges, Gauss-Bonnet check).

    source build/beltrami-env.sh
    xvfb-run -a /usr/bin/python3 Examples/curvature_demo.py [mesh.off] [output-dir]
"""
import math
import os
import sys
import time

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkIOXML import vtkXMLPolyDataWriter
from vtkmodules.vtkIOImage import vtkPNGWriter
from vtkmodules.vtkRenderingCore import (vtkActor, vtkColorTransferFunction, vtkPolyDataMapper,
                                         vtkRenderer, vtkRenderWindow, vtkWindowToImageFilter)
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401  (rendering backend)

from beltrami import vtkDiscreteCurvatures, vtkOFFReader

HERE = os.path.dirname(os.path.abspath(__file__))
DEFAULT_MESH = os.path.join(HERE, "..", "Testing", "Data", "bunny00.off")


def curvature_range(values, percentile=98.0):
    """Symmetric colour range that ignores NaN and the noisiest 2% of points."""
    finite = np.abs(values[np.isfinite(values)])
    limit = float(np.percentile(finite, percentile)) if finite.size else 1.0
    return -limit, limit


def render_mean_curvature(polydata, png_path, size=(800, 800)):
    """Renders MeanCurvature with a diverging colour map (blue concave, red convex)."""
    values = vtk_to_numpy(polydata.GetPointData().GetArray("MeanCurvature"))
    low, high = curvature_range(values)
    lut = vtkColorTransferFunction()
    lut.SetColorSpaceToDiverging()
    lut.AddRGBPoint(low, 0.23, 0.30, 0.75)
    lut.AddRGBPoint(0.5 * (low + high), 0.87, 0.87, 0.87)
    lut.AddRGBPoint(high, 0.71, 0.02, 0.15)
    lut.SetNanColor(1.0, 1.0, 0.0)

    mapper = vtkPolyDataMapper()
    mapper.SetInputData(polydata)
    mapper.SetScalarModeToUsePointFieldData()
    mapper.SelectColorArray("MeanCurvature")
    mapper.SetLookupTable(lut)
    mapper.SetColorModeToMapScalars()
    mapper.ScalarVisibilityOn()
    mapper.SetScalarRange(low, high)
    actor = vtkActor()
    actor.SetMapper(mapper)

    return snapshot(actor, png_path, size, view_up=(0, 1, 0), zoom=1.3)


def snapshot(actor, png_path, size, view_up=(0, 1, 0), direction=(0, 0, 1), zoom=1.0):
    """Renders one actor off screen on white, writes the PNG, returns the image."""
    renderer = vtkRenderer()
    renderer.AddActor(actor)
    renderer.SetBackground(1.0, 1.0, 1.0)
    camera = renderer.GetActiveCamera()
    camera.SetPosition(*direction)
    camera.SetFocalPoint(0, 0, 0)
    camera.SetViewUp(*view_up)
    renderer.ResetCamera()
    camera.Zoom(zoom)

    window = vtkRenderWindow()
    window.SetOffScreenRendering(1)
    window.SetMultiSamples(0)
    window.AddRenderer(renderer)
    window.SetSize(*size)
    window.Render()
    grab = vtkWindowToImageFilter()
    grab.SetInput(window)
    grab.ReadFrontBufferOff()
    grab.Update()
    writer = vtkPNGWriter()
    writer.SetFileName(png_path)
    writer.SetInputConnection(grab.GetOutputPort())
    writer.Write()
    return grab.GetOutput()


def write_vtp(polydata, path):
    writer = vtkXMLPolyDataWriter()
    writer.SetFileName(path)
    writer.SetInputData(polydata)
    writer.Write()


def compute_curvatures(mesh_path):
    reader = vtkOFFReader()
    reader.SetFileName(mesh_path)
    curvatures = vtkDiscreteCurvatures()
    curvatures.SetInputConnection(reader.GetOutputPort())
    reader.Update()
    start = time.perf_counter()
    curvatures.Update()
    elapsed = time.perf_counter() - start
    return curvatures.GetOutput(), elapsed


def main(argv):
    mesh_path = argv[1] if len(argv) > 1 else DEFAULT_MESH
    out_dir = argv[2] if len(argv) > 2 else "demo-output"
    os.makedirs(out_dir, exist_ok=True)
    output, elapsed = compute_curvatures(mesh_path)
    if output.GetNumberOfPoints() == 0:
        print("error: could not read %s" % mesh_path, file=sys.stderr)
        return 1
    name = os.path.splitext(os.path.basename(mesh_path))[0]
    vtp = os.path.join(out_dir, name + "_curvatures.vtp")
    png = os.path.join(out_dir, name + "_mean_curvature.png")
    write_vtp(output, vtp)
    render_mean_curvature(output, png)

    pd = output.GetPointData()
    print("mesh: %s (%d points, %d cells), curvatures in %.3f s"
          % (mesh_path, output.GetNumberOfPoints(), output.GetNumberOfCells(), elapsed))
    for array in ("MeanCurvature", "GaussianCurvature", "MaximumCurvature", "MinimumCurvature"):
        values = vtk_to_numpy(pd.GetArray(array))
        print("  %-18s median %+.4g, 2%%-98%% range [%+.4g, %+.4g]"
              % (array, np.nanmedian(values), np.nanpercentile(values, 2),
                 np.nanpercentile(values, 98)))
    status = vtk_to_numpy(pd.GetArray("VertexStatus"))
    gauss = vtk_to_numpy(pd.GetArray("GaussianCurvature"))
    area = vtk_to_numpy(pd.GetArray("MixedArea"))
    regular = status == 0
    print("  regular points: %d of %d" % (regular.sum(), status.size))
    if regular.all():
        total = float(np.sum(gauss * area))
        print("  Gauss-Bonnet: sum(K_G * A) = %.12f = %.6f * 2 pi (Euler characteristic)"
              % (total, total / (2 * math.pi)))
    print("wrote %s\nwrote %s" % (vtp, png))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
