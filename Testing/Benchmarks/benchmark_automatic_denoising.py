"""Denoising at the defaults (no parameter set) against the peers at
their oracle settings (the best of a sweep chosen with the clean data):
vtkImageAnisotropicDiffusion3D, vtkImageGaussianSmooth and scikit-image's TV
(Chambolle; skipped without python3-skimage), and our flow's own oracle
(contrast scale x stopping step), on the two MRI volumes, an MRI volume
upsampled to N^3 (default 256) and the photographs; Gaussian noise sigma 0.05
and 0.1 (fixed seed).  PSNR and seconds (the peers' time is that of their best
setting alone; best of 3 runs, 1 above 4M samples, freed memory kept in the process for every
method: Testing/Benchmarks/timing.py; above 4M samples then three more rounds of ours and VTK's
anisotropic diffusion in turn, with the ratio per round, and each one's first run in a fresh
process: there both fault in all their memory); threads: all.
Run on demand:  source build/beltrami-env.sh && /usr/bin/python3 Testing/Benchmarks/benchmark_automatic_denoising.py [N] [--large-only]"""
import os
import subprocess
import sys

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkImagingGeneral import vtkImageGaussianSmooth

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "Python"))
from timing import timed as best_of  # noqa: E402  (also keeps freed memory: the same for every method)
from peers import vtk_anisotropic_diffusion  # noqa: E402
import results  # noqa: E402
from test_automatic_denoising import denoise, flow_oracle, load_png, load_volume, psnr, to_image  # noqa: E402

try:
    from skimage.restoration import denoise_tv_chambolle
except ImportError:
    denoise_tv_chambolle = None


def timed(function, large=False):
    """(result, best wall time of 3 runs; 1 run for large data)."""
    return best_of(function, 1 if large else 3)


def vtk_filter(f, noisy, spacing):
    f.SetInputData(to_image(noisy, spacing))
    f.Update()
    return vtk_to_numpy(f.GetOutput().GetPointData().GetArray("v")).reshape(noisy.shape)


def anisotropic(noisy, spacing, k, iterations):
    return vtk_filter(vtk_anisotropic_diffusion(k, iterations, volume=noisy.ndim == 4), noisy, spacing)


def gaussian(noisy, spacing, std):
    f = vtkImageGaussianSmooth()
    f.SetDimensionality(noisy.ndim - 1)
    f.SetStandardDeviations(std, std, std)
    f.SetRadiusFactors(3, 3, 3)
    return vtk_filter(f, noisy, spacing)


def oracle(clean, run, settings, large):
    """(best PSNR, its setting, the time of that setting alone)."""
    best = max(((psnr(run(s), clean), s) for s in settings), key=lambda x: x[0])
    _, t = timed(lambda: run(best[1]), large)
    return best[0], best[1], t


def row(name, clean, spacing, sigma, with_flow_oracle):
    noisy = add_noise(clean, sigma)
    large = clean.size > 4e6
    (ours, fd), t_ours = timed(lambda: denoise(noisy, spacing), large)
    p_ours = psnr(ours, clean)
    p_ad, s_ad, t_ad = oracle(clean, lambda s: anisotropic(noisy, spacing, *s),
                              [(k * sigma, n) for k in (0.5, 1.0, 2.0, 3.0) for n in (2, 4, 8, 16)], large)
    p_g, s_g, t_g = oracle(clean, lambda s: gaussian(noisy, spacing, s), (0.5, 0.7, 0.85, 1.0, 1.2, 1.5, 2.0), large)
    text = ("%-18s sigma %.2f: defaults %.2f dB %.2f s (%d steps, est. noise %.4f) | VTK anisotropic diffusion oracle %.2f dB %.2f s "
            "(k %.3f, %d it) | Gaussian oracle %.2f dB (std %.2f)"
            % (name, sigma, p_ours, t_ours, fd.GetArray("FlowIterations").GetValue(0),
               fd.GetArray("EstimatedNoiseLevel").GetValue(0), p_ad, t_ad, s_ad[0], s_ad[1], p_g, s_g))
    if denoise_tv_chambolle is not None:
        channel = None if clean.shape[-1] == 1 else -1
        squeeze = (lambda a: a[..., 0]) if channel is None else (lambda a: a)
        p_tv, w_tv, t_tv = oracle(clean, lambda w: denoise_tv_chambolle(squeeze(noisy), weight=w, channel_axis=channel)
                                  .reshape(clean.shape), [sigma * f for f in (0.5, 0.7, 1.0, 1.4, 2.0)], large)
        text += " | TV oracle %.2f dB %.2f s (weight %.3f)" % (p_tv, t_tv, w_tv)
    if with_flow_oracle:
        text += " | our flow's oracle %.2f dB" % flow_oracle(noisy, clean, spacing, sigma)
    text += " | time ratio ours/VTK anisotropic %.2f" % (t_ours / t_ad)
    record = [name, sigma, p_ours, t_ours, p_ad, t_ad, p_g, p_tv if denoise_tv_chambolle is not None else "-",
              t_ours / t_ad]
    if large:
        # One run each is at the mercy of a noisy machine: three more rounds,
        # ours and VTK's best setting in turn.
        rounds = [(timed(lambda: denoise(noisy, spacing), True)[1],
                   timed(lambda: anisotropic(noisy, spacing, *s_ad), True)[1]) for _ in range(3)]
        ratios = sorted(o / a for o, a in rounds)
        text += (" | 3 more rounds in turn: ours %s s, VTK anisotropic %s s, ratio per round %.2f-%.2f (median %.2f)"
                 % ("/".join("%.2f" % o for o, _ in rounds), "/".join("%.2f" % a for _, a in rounds),
                    ratios[0], ratios[-1], ratios[1]))
        # The first run above is ours in a fresh process against VTK's after
        # its sweep: each one's first run in a process of its own instead.
        cold = [first_run(name, sigma, method) for method in ("ours", "vtk:%r:%d" % s_ad)]
        text += " | first run in a fresh process: ours %.2f s, VTK anisotropic %.2f s, ratio %.2f" % (
            cold[0], cold[1], cold[0] / cold[1])
    print(text, flush=True)
    return record


def first_run(name, sigma, method):
    """Seconds of the first run of `method` ("ours", or VTK's anisotropic
    diffusion at "vtk:k:iterations") on the row's noisy data, in a process
    of its own (this script with --first-run)."""
    out = subprocess.run([sys.executable, os.path.abspath(__file__), "--first-run", name, repr(sigma), method],
                         check=True, capture_output=True, text=True).stdout
    return float(out.split()[-1])


def noisy_data(name, sigma):
    """(noisy, clean, spacing) of a row: "MRI S0 at N^3" or a volume's name."""
    if name.startswith("MRI S0 at "):
        clean, spacing = upsampled(int(name.split()[-1].split("^")[0]))
    else:
        clean, spacing = load_volume(name)
    return add_noise(clean, sigma), clean, spacing


def add_noise(clean, sigma):
    return clean + np.random.default_rng(5).normal(0, sigma, clean.shape)


def upsampled(n):
    from vtkmodules.vtkImagingCore import vtkImageResample
    clean, spacing = load_volume("mri_s0_10slices")
    r = vtkImageResample()
    r.SetInputData(to_image(clean, spacing))
    r.SetInterpolationModeToCubic()
    for axis, size in enumerate(reversed(clean.shape[:3])):
        r.SetAxisMagnificationFactor(axis, n / size)
    r.Update()
    d = r.GetOutput().GetDimensions()
    a = vtk_to_numpy(r.GetOutput().GetPointData().GetScalars()).reshape(d[2], d[1], d[0], 1)
    return np.clip(a, 0.0, 1.0), (1.0, 1.0, 1.0)


def main(argv):
    if argv[1:2] == ["--first-run"]:
        noisy, _, spacing = noisy_data(argv[2], float(argv[3]))
        method = argv[4].split(":")
        run = (lambda: denoise(noisy, spacing)) if method == ["ours"] else \
            (lambda: anisotropic(noisy, spacing, float(method[1]), int(method[2])))
        print("%.4f" % timed(run, True)[1])
        return 0
    n = int(argv[1]) if len(argv) > 1 else 256
    rows = []
    for sigma in (0.05, 0.1) if "--large-only" not in argv else ():
        for name in ("mri_piesno", "mri_s0_10slices"):
            clean, spacing = load_volume(name)
            rows.append(row(name, clean, spacing, sigma, True))
        for name in ("camera", "coffee", "astronaut"):
            rows.append(row(name, load_png(name), (1.0, 1.0), sigma, False))
    clean, spacing = upsampled(n)
    rows.append(row("MRI S0 at %d^3" % n, clean, spacing, 0.05, False))
    if "--large-only" not in argv:
        results.save("denoising_images", "Denoising", "Images and volumes at the defaults",
                     "VTK's anisotropic diffusion and Gaussian smoothing, scikit-image's TV (Chambolle), "
                     "each at its best setting chosen with the clean data",
                     "two real MRI volumes, three photographs, an MRI volume upsampled to %d^3; "
                     "Gaussian noise of the given sigma (values in [0, 1])" % n,
                     ["data", "sigma", "ours dB", "ours s", "VTK aniso. dB", "VTK aniso. s", "Gaussian dB", "TV dB",
                      "time ours / VTK aniso."], rows,
                     "Ours: vtkImageBeltramiDenoising with no setting (noise estimated, stop at the least "
                     "estimated error). Times: best of 3 runs (1 above 4M samples), all threads.")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
