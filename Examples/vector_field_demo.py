#!/usr/bin/python3
"""Beltrami demo: the Helmholtz-Hodge decomposition of a vector field on a
surface (vtkSurfaceVectorFieldDecomposition, thesis section 6.3).

On the bundled genus-2 "eight" (Loop-subdivided twice), a field made of a
flow around the figure (rotation about the axis through both holes), a
source and a vortex is split into its curl-free, divergence-free and
harmonic parts.  Prints the parts' shares of the energy and their
orthogonality, and writes the surface with every array (.vtp) and a picture
of the four fields as arrows: the input coloured by its divergence, the
curl-free part by the potential, the divergence-free part by the stream
function, the harmonic part by its length.

    source build/beltrami-env.sh
    xvfb-run -a /usr/bin/python3 Examples/vector_field_demo.py [output-dir]
"""
import os
import sys
import time

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkFiltersCore import vtkGlyph3D, vtkMaskPoints
from vtkmodules.vtkFiltersModeling import vtkLoopSubdivisionFilter
from vtkmodules.vtkFiltersSources import vtkArrowSource
from vtkmodules.vtkRenderingCore import vtkActor, vtkColorTransferFunction, vtkPolyDataMapper

from beltrami import vtkOFFReader, vtkSurfaceVectorFieldDecomposition
from beltrami.pipelines import capture, curvature_range, framed_renderer, read_png, write_png, write_vtp

HERE = os.path.dirname(os.path.abspath(__file__))
MESH = os.path.join(HERE, "..", "Testing", "Data", "eight.off")
PANELS = (("TangentField", "Divergence"), ("CurlFreePart", "Potential"),
          ("DivergenceFreePart", "StreamFunction"), ("HarmonicPart", None))


def eight_with_wind():
    reader = vtkOFFReader()
    reader.SetFileName(MESH)
    loop = vtkLoopSubdivisionFilter()
    loop.SetInputConnection(reader.GetOutputPort())
    loop.SetNumberOfSubdivisions(2)
    loop.Update()
    surface = loop.GetOutput()
    p = vtk_to_numpy(surface.GetPoints().GetData()).astype(float)
    around = np.cross([0.0, 1.0, 0.0], p)  # about y, the axis through the holes
    source = np.exp(-60 * np.sum((p - [0.2, 0.0, 0.0]) ** 2, axis=1))[:, None] * (p - [0.2, 0.0, 0.0]) * 8
    vortex = np.exp(-60 * np.sum((p - [-0.2, 0.0, 0.25]) ** 2, axis=1))[:, None] * \
        np.cross([1.0, 0.0, 0.0], p - [-0.2, 0.0, 0.25]) * 8
    wind = numpy_to_vtk(np.ascontiguousarray(around + source + vortex), deep=True)
    wind.SetName("Wind")
    surface.GetPointData().AddArray(wind)
    return surface


def colours(values):
    """Blue-grey-red about 0 for signed values, grey-red for lengths."""
    signed = np.nanmin(values) < 0
    low, high = curvature_range(values) if signed else (0.0, float(np.nanpercentile(values, 98)))
    lut = vtkColorTransferFunction()
    lut.SetColorSpaceToDiverging()
    if signed:
        lut.AddRGBPoint(low, 0.23, 0.30, 0.75)
    lut.AddRGBPoint(0.5 * (low + high) if signed else low, 0.87, 0.87, 0.87)
    lut.AddRGBPoint(high, 0.71, 0.02, 0.15)
    return lut, low, high


def panel(out, vectors, colour, png):
    """The surface coloured by `colour` (or the length of `vectors`) with arrows of `vectors`."""
    out.GetPointData().SetActiveVectors(vectors)
    if colour is None:
        length = numpy_to_vtk(np.linalg.norm(vtk_to_numpy(out.GetPointData().GetArray(vectors)), axis=1), deep=True)
        length.SetName("Length")
        out.GetPointData().AddArray(length)
        colour = "Length"
    lut, low, high = colours(vtk_to_numpy(out.GetPointData().GetArray(colour)))
    surface = vtkPolyDataMapper()
    surface.SetInputData(out)
    surface.SetScalarModeToUsePointFieldData()
    surface.SelectColorArray(colour)
    surface.SetLookupTable(lut)
    surface.SetScalarRange(low, high)
    mask = vtkMaskPoints()
    mask.SetInputData(out)
    mask.SetOnRatio(7)
    mask.RandomModeOff()
    arrows = vtkGlyph3D()
    arrows.SetInputConnection(mask.GetOutputPort())
    arrow = vtkArrowSource()
    arrows.SetSourceConnection(arrow.GetOutputPort())
    arrows.SetVectorModeToUseVector()
    arrows.SetScaleModeToScaleByVector()
    arrows.SetScaleFactor(0.12)
    arrows.OrientOn()
    glyphs = vtkPolyDataMapper()
    glyphs.SetInputConnection(arrows.GetOutputPort())
    glyphs.ScalarVisibilityOff()
    actors = [vtkActor(), vtkActor()]
    actors[0].SetMapper(surface)
    actors[1].SetMapper(glyphs)
    actors[1].GetProperty().SetColor(0.1, 0.1, 0.1)
    capture(framed_renderer(actors, view_up=(0, 0, 1), direction=(0.25, -1, 0.15), zoom=1.25), png, (400, 640))


def main(argv):
    out_dir = argv[1] if len(argv) > 1 else "demo-output"
    os.makedirs(out_dir, exist_ok=True)
    decomposition = vtkSurfaceVectorFieldDecomposition()
    decomposition.SetInputData(eight_with_wind())
    decomposition.SetInputArrayToProcess(0, 0, 0, 0, "Wind")
    start = time.perf_counter()
    decomposition.Update()
    seconds = time.perf_counter() - start
    out = decomposition.GetOutput()
    fd = out.GetFieldData()
    if fd.GetArray("TangentEnergy") is None:
        print("error: no decomposition (see the error above)", file=sys.stderr)
        return 1
    energy = {k: fd.GetArray(k + "Energy").GetValue(0) for k in ("Tangent", "CurlFree", "DivergenceFree", "Harmonic")}
    inner = max(abs(fd.GetArray(k).GetValue(0)) for k in ("CurlFreeDivergenceFreeInnerProduct",
                                                         "CurlFreeHarmonicInnerProduct",
                                                         "DivergenceFreeHarmonicInnerProduct"))
    print("decomposition of a field on the eight (%d points, genus 2) in %.3f s: energy shares curl-free %.3f, "
          "divergence-free %.3f, harmonic %.3f; largest inner product %.1e of the energy"
          % (out.GetNumberOfPoints(), seconds, energy["CurlFree"] / energy["Tangent"],
             energy["DivergenceFree"] / energy["Tangent"], energy["Harmonic"] / energy["Tangent"],
             inner / energy["Tangent"]))
    stem = os.path.join(out_dir, "eight_vector_field")
    write_vtp(out, stem + ".vtp")
    pictures = []
    for k, (vectors, colour) in enumerate(PANELS):
        png = "%s_%d.png" % (stem, k)
        panel(out, vectors, colour, png)
        pictures.append(read_png(png)[..., :3])
        os.remove(png)
    gap = np.full((pictures[0].shape[0], 8, 3), 255, np.uint8)
    write_png(np.concatenate(sum(([p, gap] for p in pictures), [])[:-1], axis=1), stem + "_parts.png")
    print("wrote %s.vtp\nwrote %s_parts.png" % (stem, stem))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
