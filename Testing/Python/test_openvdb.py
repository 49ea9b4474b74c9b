"""OpenVDB I/O from /usr/bin/python3: exact write/read round trips (float,
double, vec3; extent, origin, spacing), grid selection by name, a denoising
path from a .vdb file, and 200 truncated or corrupted files that must give an
error (or a valid image), never a crash or a hang."""
import os
import random
import re
import tempfile
import unittest

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkOutputWindow, vtkStringOutputWindow
from vtkmodules.vtkCommonDataModel import vtkImageData

from beltrami import vtkImageBeltramiDenoising, vtkOpenVDBReader, vtkOpenVDBWriter

TMP = tempfile.mkdtemp()


def image(values, extent=(-3, 12, 2, 20, 0, 7), spacing=(0.5, 0.25, 2.0), origin=(1.0, -2.0, 3.5),
          name="density"):
    img = vtkImageData()
    img.SetExtent(*extent)
    img.SetSpacing(*spacing)
    img.SetOrigin(*origin)
    arr = numpy_to_vtk(values.reshape(img.GetNumberOfPoints(), -1), deep=1)
    arr.SetName(name)
    img.GetPointData().SetScalars(arr)
    return img


def write(img, path, grid_name=None):
    w = vtkOpenVDBWriter()
    w.SetInputData(img)
    w.SetFileName(path)
    if grid_name:
        w.SetGridName(grid_name)
    w.Write()


def read(path, grid_name=None):
    r = vtkOpenVDBReader()
    r.SetFileName(path)
    r.SetTimeout(20)
    if grid_name:
        r.SetGridName(grid_name)
    r.Update()
    return r.GetOutput()


class RoundTrip(unittest.TestCase):
    def test_types_extent_origin_spacing(self):
        n = 16 * 19 * 8
        rng = np.random.default_rng(1)
        for dtype, nc in ((np.float32, 1), (np.float64, 1), (np.float32, 3), (np.float64, 3)):
            values = rng.normal(0, 1, (n, nc)).astype(dtype)
            img = image(values)
            path = os.path.join(TMP, "rt.vdb")
            write(img, path)
            self.assertTrue(vtkOpenVDBReader.CanReadFile(path))
            out = read(path)
            self.assertEqual(out.GetExtent(), img.GetExtent())
            self.assertEqual(out.GetSpacing(), img.GetSpacing())
            self.assertEqual(out.GetOrigin(), img.GetOrigin())
            got = vtk_to_numpy(out.GetPointData().GetScalars()).reshape(n, nc)
            self.assertEqual(got.dtype, values.dtype)
            self.assertTrue(np.array_equal(got, values), (dtype, nc))
            self.assertEqual(out.GetPointData().GetScalars().GetName(), "density")
            self.assertEqual(out.GetFieldData().GetAbstractArray("ActiveVoxelCount").GetValue(0), n)

    def test_grid_by_name_and_errors(self):
        path = os.path.join(TMP, "named.vdb")
        write(image(np.zeros(16 * 19 * 8, np.float32)), path, grid_name="pressure")
        self.assertEqual(read(path, "pressure").GetNumberOfPoints(), 16 * 19 * 8)
        log = vtkStringOutputWindow()
        vtkOutputWindow.SetInstance(log)
        self.assertEqual(read(path, "velocity").GetNumberOfPoints(), 0)
        self.assertIn("no grid named 'velocity'", log.GetOutput())
        self.assertEqual(read(os.path.join(TMP, "missing.vdb")).GetNumberOfPoints(), 0)
        self.assertIn("no such file", log.GetOutput())
        self.assertFalse(vtkOpenVDBReader.CanReadFile(os.path.join(TMP, "missing.vdb")))

    def test_denoising_a_vdb_volume(self):
        z, y, x = np.mgrid[0:24, 0:24, 0:24] / 23.0
        clean = ((x - 0.5) ** 2 + (y - 0.5) ** 2 + (z - 0.5) ** 2 < 0.1).astype(np.float32)
        noisy = clean + np.random.default_rng(2).normal(0, 0.1, clean.shape).astype(np.float32)
        path = os.path.join(TMP, "noisy.vdb")
        write(image(noisy.ravel(), extent=(0, 23, 0, 23, 0, 23), spacing=(1, 1, 1), origin=(0, 0, 0)), path)
        r = vtkOpenVDBReader()
        r.SetFileName(path)
        f = vtkImageBeltramiDenoising()
        f.SetInputConnection(r.GetOutputPort())
        f.SetContrastScale(15.0)
        f.SetNoiseLevel(0.1)
        f.SetIntegration(1)
        f.SetTimeStep(0.1)
        f.SetNumberOfIterations(100)
        f.Update()
        out = vtk_to_numpy(f.GetOutput().GetPointData().GetArray("density")).reshape(clean.shape)
        rms = lambda v: np.sqrt(np.mean((v - clean) ** 2))  # noqa: E731
        print("vdb volume: RMS error noisy %.3f -> denoised %.3f" % (rms(noisy), rms(out)))
        self.assertLess(rms(out), 0.5 * rms(noisy))


class Corrupt(unittest.TestCase):
    def test_truncated_and_mutated_files(self):
        path = os.path.join(TMP, "good.vdb")
        write(image(np.random.default_rng(5).normal(0, 1, 16 * 19 * 8).astype(np.float32)), path)
        with open(path, "rb") as f:
            data = f.read()
        log = vtkStringOutputWindow()
        vtkOutputWindow.SetInstance(log)
        valid = 0
        for n in range(200):
            rng = random.Random(n)
            b = bytearray(data)
            if n % 3 == 0:
                b = b[:rng.randrange(len(b))]
            else:
                for _ in range(rng.randint(1, 8)):
                    b[rng.randrange(len(b))] = rng.randrange(256)
            bad = os.path.join(TMP, "bad.vdb")
            with open(bad, "wb") as f:
                f.write(b)
            out = read(bad)
            if out.GetNumberOfPoints() > 0:
                valid += 1  # a mutation the format does not notice: still a consistent image
                self.assertEqual(vtk_to_numpy(out.GetPointData().GetScalars()).shape[0], out.GetNumberOfPoints())
        errors = len(re.findall("Cannot read", log.GetOutput()))
        print("200 damaged files: %d errors, %d read as images, crashes caught: %d"
              % (errors, valid, log.GetOutput().count("parser crashed")))
        self.assertGreater(errors, 150)


if __name__ == "__main__":
    unittest.main()
