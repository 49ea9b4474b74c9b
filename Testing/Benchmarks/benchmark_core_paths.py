"""Times and checksums the main paths of the core on fixed data (on demand, not
a test): fairing at the filter's defaults, the image, volume and surface-data
flows, the three parameterizations (DCP, DAP, natural conformal map) and the
curvatures.  Run it under two builds to compare a change that must not alter
behaviour: the checksums (a hash of every output value's bits) must be equal,
the times equal within noise.

    source build/beltrami-env.sh
    /usr/bin/python3 Testing/Benchmarks/benchmark_core_paths.py [repeats]
"""
import hashlib
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from timing import timed  # noqa: E402
from benchmark_parameterization import mesh  # noqa: E402  (bundled mesh, Loop-subdivided)

from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy  # noqa: E402
from vtkmodules.vtkCommonDataModel import vtkImageData  # noqa: E402
from vtkmodules.vtkIOImage import vtkPNGReader  # noqa: E402

import beltrami  # noqa: E402

DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "Data")


def digest(*arrays):
    h = hashlib.sha256()
    for a in arrays:
        h.update(np.ascontiguousarray(vtk_to_numpy(a), dtype=np.float64).tobytes())
    return h.hexdigest()[:16]


def run(make, outputs, repeats):
    def once():
        filt = make()
        filt.Update()
        return filt

    filt, t = timed(once, repeats)
    return t, digest(*outputs(filt.GetOutput()))


def main():
    repeats = int(sys.argv[1]) if len(sys.argv) > 1 else 3
    rng = np.random.default_rng(1)
    bunny = mesh("bunny00.off", 1)  # ~300k triangles, ~150k points
    pts = vtk_to_numpy(bunny.GetPoints().GetData())
    noisy = type(bunny)()
    noisy.DeepCopy(bunny)
    noisy.GetPoints().SetData(numpy_to_vtk(pts + 1e-3 * rng.standard_normal(pts.shape), deep=True))
    patch = mesh("patch-01.off", 3)  # ~45k vertices, a disk
    png = vtkPNGReader()
    png.SetFileName(os.path.join(DATA, "camera.png"))
    png.Update()
    image = png.GetOutput()
    camera = vtk_to_numpy(image.GetPointData().GetScalars()).astype(np.float64) / 255.0
    image.GetPointData().SetScalars(numpy_to_vtk(camera + 0.1 * rng.standard_normal(camera.shape), deep=True))
    image.GetPointData().GetScalars().SetName("f")
    n = 64
    volume = vtkImageData()
    volume.SetDimensions(n, n, n)
    z, y, x = np.mgrid[0:n, 0:n, 0:n] / n
    blob = ((x - 0.5) ** 2 + (y - 0.5) ** 2 + (z - 0.5) ** 2 < 0.09).astype(float)
    volume.GetPointData().SetScalars(numpy_to_vtk((blob + 0.1 * rng.standard_normal(blob.shape)).ravel(), deep=True))
    volume.GetPointData().GetScalars().SetName("f")
    surface = type(bunny)()
    surface.DeepCopy(bunny)
    f = numpy_to_vtk(np.sin(20 * pts[:, 0]) + 0.1 * rng.standard_normal(len(pts)), deep=True)
    f.SetName("f")
    surface.GetPointData().SetScalars(f)

    def fairing():
        s = beltrami.vtkImplicitFairing()
        s.SetInputData(noisy)
        return s

    def flow(cls, data, **settings):
        def make():
            s = cls()
            s.SetInputData(data)
            s.SetInputArrayToProcess(0, 0, 0, 0, "f")
            for k, v in settings.items():
                getattr(s, "Set" + k)(v)
            return s
        return make

    def param(boundary, authalic):
        def make():
            p = beltrami.vtkIntrinsicParameterization()
            p.SetInputData(patch)
            p.SetBoundary(boundary)
            if authalic:
                p.SetConformalWeight(0.0)
                p.SetAuthalicWeight(1.0)
            return p
        return make

    def curvatures():
        c = beltrami.vtkDiscreteCurvatures()
        c.SetInputData(bunny)
        return c

    P = beltrami.vtkIntrinsicParameterization
    cases = [
        ("fairing, defaults, 300k triangles", fairing, lambda o: [o.GetPoints().GetData()]),
        ("image flow, camera 512^2, 20 steps", flow(beltrami.vtkImageBeltramiDenoising, image, ContrastScale=15.0,
                                                   StoppingRule=0, NumberOfIterations=20), lambda o: [o.GetPointData().GetArray("f")]),
        ("image flow, semi-implicit, 10 steps", flow(beltrami.vtkImageBeltramiDenoising, image, ContrastScale=15.0,
                                                    Integration=1, StoppingRule=0, NumberOfIterations=10),
         lambda o: [o.GetPointData().GetArray("f")]),
        ("volume flow 64^3, 10 steps", flow(beltrami.vtkImageBeltramiDenoising, volume, ContrastScale=15.0,
                                            StoppingRule=0, NumberOfIterations=10), lambda o: [o.GetPointData().GetArray("f")]),
        ("surface-data flow, 150k points", flow(beltrami.vtkSurfaceDataDenoising, surface, ContrastScale=10.0,
                                                StoppingRule=0, NumberOfIterations=10), lambda o: [o.GetPointData().GetArray("f")]),
        ("DCP, 45k vertices", param(P.CIRCLE, False), lambda o: [o.GetPointData().GetArray("UV")]),
        ("DAP, 45k vertices", param(P.CIRCLE, True), lambda o: [o.GetPointData().GetArray("UV")]),
        ("natural conformal map, 45k vertices", param(P.NATURAL, False), lambda o: [o.GetPointData().GetArray("UV")]),
        ("curvatures, 300k triangles", curvatures, lambda o: [o.GetPointData().GetArray("MeanCurvature"),
                                                             o.GetPointData().GetArray("GaussianCurvature")]),
    ]
    for name, make, outputs in cases:
        t, d = run(make, outputs, repeats)
        print("%-40s %8.3f s   %s" % (name, t, d), flush=True)


if __name__ == "__main__":
    main()
