"""OpenVDB I/O from /usr/bin/python3: exact write/read round trips (float,
double, vec3; extent, origin, spacing), grid selection by name, a denoising
path from a .vdb file, sparse grids (written with SparseOutput, read back
densely and as active voxels only, denoised on their voxels), and 200 truncated or corrupted files that must give an
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

from beltrami import (vtkImageBeltramiDenoising, vtkOpenVDBActiveVoxelReader, vtkOpenVDBReader, vtkOpenVDBWriter,
                      vtkTetrahedralBeltramiDenoising)

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


def denoiser(f, source):
    """f on source's output, the settings for noise sigma = 0.1 on values of order 1, updated."""
    f.SetInputConnection(source.GetOutputPort())
    f.SetContrastScale(15.0)
    f.SetNoiseLevel(0.1)
    f.SetIntegration(1)
    f.SetTimeStep(0.1)
    f.SetStoppingRule(1)  # the noise level: the same steps on the dense and the sparse path
    f.SetNumberOfIterations(100)
    f.Update()
    return f


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
        f = denoiser(vtkImageBeltramiDenoising(), r)
        out = vtk_to_numpy(f.GetOutput().GetPointData().GetArray("density")).reshape(clean.shape)
        rms = lambda v: np.sqrt(np.mean((v - clean) ** 2))  # noqa: E731
        print("vdb volume: RMS error noisy %.3f -> denoised %.3f" % (rms(noisy), rms(out)))
        self.assertLess(rms(out), 0.5 * rms(noisy))


class Sparse(unittest.TestCase):
    def test_active_voxels_without_densifying(self):
        # A noisy spherical shell (values around 1) in a 40^3 box of exact
        # zeros: written sparse, only the shell is active.
        n = 40
        z, y, x = np.mgrid[0:n, 0:n, 0:n]
        r = np.sqrt((x - 20.0) ** 2 + (y - 19.0) ** 2 + (z - 21.0) ** 2)
        shell = np.abs(r - 13.0) < 3.0
        noisy = np.where(shell, 1.0 + np.random.default_rng(7).normal(0, 0.1, shell.shape), 0.0).astype(np.float32)
        path = os.path.join(TMP, "sparse.vdb")
        w = vtkOpenVDBWriter()
        w.SetInputData(image(noisy.ravel(), extent=(0, n - 1, 0, n - 1, 0, n - 1), spacing=(0.5, 0.5, 0.5),
                             origin=(1.0, 2.0, 3.0)))
        w.SetFileName(path)
        w.SparseOutputOn()
        w.Write()
        active = int(shell.sum())
        dense = read(path)
        self.assertEqual(dense.GetFieldData().GetAbstractArray("ActiveVoxelCount").GetValue(0), active)

        reader = vtkOpenVDBActiveVoxelReader()
        reader.SetFileName(path)
        reader.Update()
        voxels = reader.GetOutput()
        # One point per active voxel (never the 64,000 of the box), at the
        # dense image's positions with the same values.
        self.assertEqual(voxels.GetNumberOfPoints(), active)
        pts = vtk_to_numpy(voxels.GetPoints().GetData())
        vals = vtk_to_numpy(voxels.GetPointData().GetArray("density"))
        ijk = np.rint((pts - np.array([1.0, 2.0, 3.0])) / 0.5).astype(int)
        self.assertTrue(np.array_equal(vals, noisy[ijk[:, 2], ijk[:, 1], ijk[:, 0]]))
        self.assertTrue(shell[ijk[:, 2], ijk[:, 1], ijk[:, 0]].all())
        # A voxel cell wherever all eight corners are active.
        complete = np.ones((n - 1,) * 3, bool)
        for c in range(8):
            complete &= shell[(c >> 2) & 1:n - 1 + ((c >> 2) & 1), (c >> 1) & 1:n - 1 + ((c >> 1) & 1),
                              c & 1:n - 1 + (c & 1)]
        self.assertEqual(voxels.GetNumberOfCells(), int(complete.sum()))
        self.assertEqual(voxels.GetCellType(0), 11)  # VTK_VOXEL

        # Denoised on its voxels (six Kuhn tetrahedra each).
        f = denoiser(vtkTetrahedralBeltramiDenoising(), reader)
        out = vtk_to_numpy(f.GetOutput().GetPointData().GetArray("density"))
        rms = lambda v: np.sqrt(np.mean((v - 1.0) ** 2))  # noqa: E731
        print("sparse vdb: %d active voxels of %d, %d voxel cells; RMS error noisy %.3f -> denoised %.3f"
              % (active, n ** 3, voxels.GetNumberOfCells(), rms(vals), rms(out)))
        self.assertLess(rms(out), 0.5 * rms(vals))


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
            if n % 4 == 0:  # the active-voxel answer of the same helper on a quarter of them
                sparse = vtkOpenVDBActiveVoxelReader()
                sparse.SetFileName(bad)
                sparse.SetTimeout(20)
                sparse.Update()
                voxels = sparse.GetOutput()
                if voxels.GetNumberOfPoints() > 0:
                    self.assertEqual(vtk_to_numpy(voxels.GetPointData().GetScalars()).shape[0],
                                     voxels.GetNumberOfPoints())
        errors = len(re.findall("Cannot read", log.GetOutput()))
        print("200 damaged files (+50 read as active voxels): %d errors, %d read as images, crashes caught: %d"
              % (errors, valid, log.GetOutput().count("parser crashed")))
        self.assertGreater(errors, 180)


if __name__ == "__main__":
    unittest.main()
