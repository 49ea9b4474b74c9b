"""Denoising without tuning: the noise level estimated from the data
alone, and the defaults (automatic contrast scale, least-estimated-error stop)
against the flow's own oracle (best contrast scale and stopping step chosen with
the clean data) and against Gaussian smoothing at its oracle width, on
photographs and on two real MRI volumes (Testing/Data, from dipy's test data)."""
import os
import unittest

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkCommand
from vtkmodules.vtkCommonDataModel import vtkImageData
from vtkmodules.vtkImagingGeneral import vtkImageGaussianSmooth
from vtkmodules.vtkIOXML import vtkXMLImageDataReader

from vtkmodules.vtkFiltersGeneral import vtkDataSetTriangleFilter

from beltrami import (pipelines, vtkImageBeltramiDenoising, vtkOFFReader, vtkSurfaceDataDenoising,
                      vtkTetrahedralBeltramiDenoising)

DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "Data")
SIGMAS = (0.02, 0.05, 0.1, 0.2)


def load_png(name):
    a = pipelines.read_png(os.path.join(DATA, name + ".png"))[::-1].astype(float) / 255.0
    return a[..., :1] if name == "camera" else a[..., :3]


def load_volume(name):
    """(z, y, x, 1) values in [0, 1] and the spacing."""
    r = vtkXMLImageDataReader()
    r.SetFileName(os.path.join(DATA, name + ".vti"))
    r.Update()
    d = r.GetOutput().GetDimensions()
    a = vtk_to_numpy(r.GetOutput().GetPointData().GetArray("MRI")).astype(float)
    return a.reshape(d[2], d[1], d[0], 1), r.GetOutput().GetSpacing()


def to_image(a, spacing):
    """(h, w, c) or (d, h, w, c) array -> vtkImageData with the point array 'v'."""
    shape = a.shape[:-1]
    img = vtkImageData()
    img.SetDimensions(*(tuple(reversed(shape)) + (1,) * (3 - len(shape))))
    img.SetSpacing(*(tuple(spacing) + (1.0,) * (3 - len(spacing))))
    arr = numpy_to_vtk(np.ascontiguousarray(a.reshape(-1, a.shape[-1])), deep=1)
    arr.SetName("v")
    img.GetPointData().SetScalars(arr)
    return img


def denoise(a, spacing, **settings):
    f = vtkImageBeltramiDenoising()
    f.SetInputData(to_image(a, spacing))
    for key, value in settings.items():
        getattr(f, "Set" + key)(value)
    f.Update()
    out = f.GetOutput()
    fd = out.GetFieldData()
    return vtk_to_numpy(out.GetPointData().GetArray("v")).reshape(a.shape), fd


def psnr(a, b):
    return 10 * np.log10(1.0 / np.mean((a - b) ** 2))


def flow_oracle(noisy, clean, spacing, sigma):
    """The flow's best PSNR over contrast scales c h / sigma, c in {0.75, 1, 1.5,
    2}, and every stopping step: explicit steps at the automatic step size,
    one step per run (the flow has no other state, so chained runs are its
    trajectory), each scale followed until its PSNR has fallen 0.2 dB below its
    best."""
    h = np.prod(spacing[:noisy.ndim - 1]) ** (1.0 / (noisy.ndim - 1))
    best = -np.inf
    for c in (0.75, 1.0, 1.5, 2.0):  # the best c was 1-2 on all of them in a wider sweep (0.25-5)
        state, top = noisy, psnr(noisy, clean)
        for _ in range(400):
            state, _ = denoise(state, spacing, ContrastScale=c * h / sigma, StoppingRule=0, NumberOfIterations=1)
            quality = psnr(state, clean)
            top = max(top, quality)
            if quality < top - 0.2:
                break
        best = max(best, top)
    return best


def gaussian_oracle(noisy, clean, spacing):
    best = -np.inf
    for std in (0.5, 0.7, 0.85, 1.0, 1.2, 1.5, 2.0, 2.5):
        g = vtkImageGaussianSmooth()
        g.SetInputData(to_image(noisy, spacing))
        g.SetDimensionality(noisy.ndim - 1)
        g.SetStandardDeviations(std, std, std)  # in pixels
        g.SetRadiusFactors(3, 3, 3)
        g.Update()
        out = vtk_to_numpy(g.GetOutput().GetPointData().GetArray("v")).reshape(noisy.shape)
        best = max(best, psnr(out, clean))
    return best


def cases():
    for name in ("camera", "coffee", "astronaut"):
        yield name, load_png(name), (1.0, 1.0)
    for name in ("mri_piesno", "mri_s0_10slices"):
        a, spacing = load_volume(name)
        yield name, a, spacing


class NoiseEstimates(unittest.TestCase):
    def test_volumes_and_mesh_and_tetrahedral_point_data_within_10_percent(self):
        worst = {}
        for name in ("mri_piesno", "mri_s0_10slices"):
            clean, spacing = load_volume(name)
            for sigma in SIGMAS:
                noisy = clean + np.random.default_rng(7).normal(0.0, sigma, clean.shape)
                _, fd = denoise(noisy, spacing, StoppingRule=0, NumberOfIterations=0)
                worst[(name, sigma)] = fd.GetArray("EstimatedNoiseLevel").GetValue(0) / sigma - 1
        # A real mesh (the bunny scan) with a smooth field and a jump across it.
        reader = vtkOFFReader()
        reader.SetFileName(os.path.join(DATA, "bunny00.off"))
        reader.Update()
        mesh = reader.GetOutput()
        p = vtk_to_numpy(mesh.GetPoints().GetData()).astype(float)
        p = (p - p.mean(0)) / np.ptp(p, axis=0).max()
        field = np.where(p[:, 0] > 0.05, 0.7, 0.2) + 0.3 * np.sin(6 * p[:, 1]) * np.cos(4 * p[:, 2])
        for sigma in SIGMAS:
            arr = numpy_to_vtk(field + np.random.default_rng(8).normal(0.0, sigma, field.shape), deep=1)
            arr.SetName("f")
            mesh.GetPointData().SetScalars(arr)
            f = vtkSurfaceDataDenoising()
            f.SetInputData(mesh)
            f.SetStoppingRule(f.FIXED_ITERATIONS)
            f.SetNumberOfIterations(0)
            f.Update()
            worst[("bunny00", sigma)] = f.GetOutput().GetFieldData().GetArray("EstimatedNoiseLevel").GetValue(0) / sigma - 1
        # Tetrahedral point data: a crop of an MRI volume split into tetrahedra.
        crop = load_volume("mri_piesno")[0][:, 20:68, 20:68]
        for sigma in SIGMAS:
            noisy = crop + np.random.default_rng(9).normal(0.0, sigma, crop.shape)
            tets = vtkDataSetTriangleFilter()
            tets.SetInputData(to_image(noisy, (1.0, 1.0, 1.0)))
            f = vtkTetrahedralBeltramiDenoising()
            f.SetInputConnection(tets.GetOutputPort())
            f.SetStoppingRule(f.FIXED_ITERATIONS)
            f.SetNumberOfIterations(0)
            f.Update()
            worst[("tetrahedra", sigma)] = f.GetOutput().GetFieldData().GetArray("EstimatedNoiseLevel").GetValue(0) / sigma - 1
        print("estimated noise, relative error:", " ".join("%s/%.2f %+.1f%%" % (k[0], k[1], 100 * v)
                                                          for k, v in worst.items()))
        for key, error in worst.items():
            # The 1-ring residual cancels linear data only: at noise 0.02 the
            # MRI's curvature adds about 12% on the Kuhn tetrahedra (the image
            # estimator's mask cancels more: 2%); 20% allowed there.
            self.assertLess(abs(error), 0.20 if key == ("tetrahedra", 0.02) else 0.10, key)


class Defaults(unittest.TestCase):
    def test_flat_backgrounds_neither_hide_the_noise_nor_stop_the_defaults(self):
        # A skull-stripped-like MRI volume (noise only where the clean volume is
        # above 5% of its maximum, exactly 0 elsewhere: 74-76% of the voxels)
        # and 8-bit photographs, noisy, rounded and clipped, with a black
        # border (26% of the pixels).  The flat samples made the estimate 0
        # (the defaults then left the data as they were); now it is that of the
        # samples away from them.
        for name in ("mri_piesno", "mri_s0_10slices"):
            clean, spacing = load_volume(name)
            inside = clean > 0.05 * clean.max()
            for sigma in (0.05, 0.1):
                noisy = np.where(inside, clean + np.random.default_rng(5).normal(0, sigma, clean.shape), 0.0)
                out, fd = denoise(noisy, spacing)
                estimate = fd.GetArray("EstimatedNoiseLevel").GetValue(0)
                masked = np.where(inside, clean, 0.0)
                before, after = (10 * np.log10(1 / np.mean((a - masked)[inside] ** 2)) for a in (noisy, out))
                print("%s masked (%.0f%% flat), sigma %.2f: estimated %.4f, %.2f -> %.2f dB inside"
                      % (name, 100 * (1 - inside.mean()), sigma, estimate, before, after))
                self.assertLess(abs(estimate / sigma - 1), 0.1)
                self.assertGreater(after, before + 4.0)
        for name in ("camera", "coffee"):
            clean8 = pipelines.read_png(os.path.join(DATA, name + ".png"))
            clean8 = clean8[..., :1] if name == "camera" else clean8[..., :3]
            noisy8 = pipelines.noisy_version(clean8, sigma=0.05)
            framed8 = noisy8.copy()
            framed8[:80] = 0
            framed8[:, :60] = 0
            estimates = [pipelines.denoise(a)[1].GetArray("EstimatedNoiseLevel").GetValue(0) / (255.0 if name == "camera" else 1.0)
                         for a in (noisy8, framed8)]
            print("%s 8-bit, sigma 0.05: estimated %.4f, with a black border %.4f" % (name, *estimates))
            self.assertLess(abs(estimates[1] / estimates[0] - 1), 0.05)  # (other samples: 2-4% apart)
            for estimate in estimates:
                self.assertLess(abs(estimate / 0.05 - 1), 0.1)

    def test_camera_at_sigma_0_1_with_no_setting(self):
        clean = load_png("camera")
        noisy = clean + np.random.default_rng(1234).normal(0, 0.1, clean.shape)
        out, fd = denoise(noisy, (1.0, 1.0))
        quality = psnr(out, clean)
        true_error = np.sqrt(np.mean((out - clean) ** 2))
        estimated = fd.GetArray("FlowEstimatedError").GetValue(1)
        print("camera sigma 0.1 at the defaults: %.2f dB in %d steps, estimated noise %.4f, contrast scale %.2f, "
              "estimated RMS error %.4f (true %.4f)" % (
                  quality, fd.GetArray("FlowIterations").GetValue(0), fd.GetArray("EstimatedNoiseLevel").GetValue(0),
                  fd.GetArray("FlowContrastScale").GetValue(0), estimated, true_error))
        self.assertGreaterEqual(quality, 28.0)
        # The estimated error is as good as the noise level it is given: with
        # the estimated one (1.6% high here) within 15%, with the true one 3%.
        self.assertAlmostEqual(estimated, true_error, delta=0.15 * true_error)
        out, fd = denoise(noisy, (1.0, 1.0), NoiseLevel=0.1)
        true_error = np.sqrt(np.mean((out - clean) ** 2))
        self.assertAlmostEqual(fd.GetArray("FlowEstimatedError").GetValue(1), true_error, delta=0.03 * true_error)
        self.assertAlmostEqual(fd.GetArray("FlowEstimatedError").GetValue(0), 0.1, delta=1e-9)  # SURE of the input

    def test_the_iteration_limit_never_ends_a_rule_silently(self):
        clean = load_png("camera")[200:328, 200:328]
        noisy = clean + np.random.default_rng(3).normal(0, 0.1, clean.shape)
        for rule, limit in ((2, "MaximumNumberOfIterations"), (1, "NumberOfIterations")):
            f = vtkImageBeltramiDenoising()
            f.SetInputData(to_image(noisy, (1.0, 1.0)))
            f.SetStoppingRule(rule)
            f.SetNoiseLevel(0.1 if rule == 1 else 0.0)
            f.SetMaximumNumberOfIterations(3)
            if rule == 1:
                f.SetStoppingRule(0)  # the legacy form: a noise level with a fixed count as its bound
                f.SetNumberOfIterations(3)
            seen = []
            tag = f.AddObserver(vtkCommand.WarningEvent, lambda obj, event: seen.append(1))
            f.Update()
            f.RemoveObserver(tag)
            self.assertEqual(len(seen), 1, limit)
            self.assertEqual(f.GetOutput().GetFieldData().GetArray("FlowIterations").GetValue(0), 3)
        f.SetNumberOfIterations(400)  # enough: the rule ends the run, no warning
        seen = []
        tag = f.AddObserver(vtkCommand.WarningEvent, lambda obj, event: seen.append(1))
        f.Update()
        f.RemoveObserver(tag)
        self.assertEqual(len(seen), 0)

    def test_near_the_flows_oracle_and_above_gaussian_smoothing(self):
        rows = []
        for name, clean, spacing in cases():
            for sigma in (0.05, 0.1):
                noisy = clean + np.random.default_rng(5).normal(0, sigma, clean.shape)
                out, fd = denoise(noisy, spacing)
                ours = psnr(out, clean)
                oracle = flow_oracle(noisy, clean, spacing, sigma)
                gaussian = gaussian_oracle(noisy, clean, spacing)
                rows.append((name, sigma, ours, oracle, gaussian, fd.GetArray("FlowIterations").GetValue(0)))
        for row in rows:
            print("%-16s sigma %.2f: defaults %.2f dB (%d steps), flow oracle %.2f dB, Gaussian oracle %.2f dB"
                  % (row[0], row[1], row[2], row[5], row[3], row[4]))
        for name, sigma, ours, oracle, gaussian, _ in rows:
            self.assertGreater(ours, oracle - 0.5, (name, sigma))
            self.assertGreater(ours, gaussian, (name, sigma))

    def test_voxel_spacing_does_not_change_the_result(self):
        clean, _ = load_volume("mri_s0_10slices")
        noisy = clean + np.random.default_rng(9).normal(0, 0.05, clean.shape)
        results = {}
        for spacing in ((1.0, 1.0, 1.0), (2.0, 2.0, 2.0), (2.0, 2.0, 2.2), (0.5, 0.5, 0.5)):
            out, fd = denoise(noisy, spacing)
            results[spacing] = psnr(out, clean)
        print("MRI S0 at sigma 0.05, defaults by spacing:", ", ".join("%s %.3f dB" % (s, q) for s, q in results.items()))
        self.assertLess(max(results.values()) - min(results.values()), 0.1)


if __name__ == "__main__":
    unittest.main(verbosity=2)
