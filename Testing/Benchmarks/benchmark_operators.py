"""vtkBeltramiOperators (the operators of section 2.8 as edge and
feature maps) against what a user would otherwise take for an edge map and a
Laplacian, same run, same data, best of 3:
 - the camera image (512 x 512, and 4x upsampled to 2048 x 2048): ours (all
   five arrays; a given contrast scale, and the automatic one with its noise
   estimate) vs VTK's vtkImageGradientMagnitude + vtkImageLaplacian and
   scikit-image's sobel + laplace;
 - point data on the bunny (37k points) and on its Loop subdivision (603k):
   ours vs VTK's vtkGradientFilter (the point data's gradient over the mesh).
Prints the times and the ratios (peer time / ours; > 1: ours faster).  The
peers compute less (a gradient magnitude and a Laplacian, no graph geometry):
the ratios say what the graph operators cost on top of the usual maps.
Run on demand:  source build/beltrami-env.sh && /usr/bin/python3 Testing/Benchmarks/benchmark_operators.py"""
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "Python"))
from timing import timed  # noqa: E402
from configure import configured  # noqa: E402
from beltrami import vtkBeltramiOperators, vtkOFFReader  # noqa: E402
from beltrami.pipelines import read_png, to_image  # noqa: E402
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy  # noqa: E402
from vtkmodules.vtkFiltersGeneral import vtkGradientFilter  # noqa: E402
from vtkmodules.vtkFiltersModeling import vtkLoopSubdivisionFilter  # noqa: E402
from vtkmodules.vtkImagingGeneral import vtkImageGradientMagnitude  # noqa: E402
from vtkmodules.vtkImagingGeneral import vtkImageLaplacian  # noqa: E402

try:
    from skimage.filters import laplace, sobel
except ImportError:
    sobel = laplace = None
    print("scikit-image not installed: its filters skipped")

DATA = os.path.join(HERE, "..", "Data")


def ours(data, contrast):
    return lambda: configured(vtkBeltramiOperators(), data, ContrastScale=contrast)


def vtk_image_maps(image):
    def run():
        g = configured(vtkImageGradientMagnitude(), image, Dimensionality=2)
        return g, configured(vtkImageLaplacian(), image, Dimensionality=2)
    return run


def row(label, reference, peers):
    text = "  %-34s ours %8.4f s" % (label, reference)
    for name, seconds in peers:
        text += " | %s %8.4f s (%.2fx)" % (name, seconds, seconds / reference)
    print(text)


def images():
    camera = read_png(os.path.join(DATA, "camera.png"))[:, :, :1].astype(np.float64) / 255.0
    print("Images (greyscale, 2 threads for ours, VTK's default threads):")
    for label, a in (("camera 512^2", camera), ("camera 2048^2 (4x upsampled)",
                                                np.kron(camera, np.ones((4, 4, 1))))):
        image = to_image(a)
        image.GetPointData().GetScalars().SetName("values")
        _, given = timed(ours(image, 0.05))
        _, automatic = timed(ours(image, 0.0))
        peers = [("VTK gradient+Laplacian", timed(vtk_image_maps(image))[1])]
        if sobel is not None:
            peers.append(("skimage sobel+laplace", timed(lambda: (sobel(a[:, :, 0]), laplace(a[:, :, 0])))[1]))
        row(label + ", alpha given", given, peers)
        row(label + ", automatic alpha", automatic, peers)


def surfaces():
    reader = vtkOFFReader()
    reader.SetFileName(os.path.join(DATA, "bunny00.off"))
    reader.Update()
    loop = configured(vtkLoopSubdivisionFilter(), reader, NumberOfSubdivisions=2)
    print("Point data on surfaces (f = sin(40 x) cos(30 y) + noise of 0.05):")
    for label, mesh in (("bunny 37k points", reader.GetOutput()), ("bunny 603k points", loop.GetOutput())):
        p = vtk_to_numpy(mesh.GetPoints().GetData())
        f = numpy_to_vtk(np.sin(40 * p[:, 0]) * np.cos(30 * p[:, 1])
                         + np.random.default_rng(1).normal(0.0, 0.05, len(p)), deep=1)
        f.SetName("f")
        mesh.GetPointData().SetScalars(f)
        _, automatic = timed(ours(mesh, 0.0))
        gradient = timed(lambda: configured(vtkGradientFilter(), mesh))[1]
        row(label + ", automatic alpha", automatic, [("VTK vtkGradientFilter", gradient)])


if __name__ == "__main__":
    images()
    surfaces()
