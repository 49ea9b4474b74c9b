#!/usr/bin/python3
"""Beltrami demo: edge-preserving denoising of images (thesis section 3.8).

Adds Gaussian noise (sigma = 0.1 of the range, fixed seed) to the bundled
greyscale `camera` and colour `coffee` images (from scikit-image's data), smooths
them with vtkImageBeltramiDenoising at its defaults (the Beltrami flow, colours
coupled; no parameter set: the noise level is estimated from the image, the
contrast scale follows from it and the flow stops at the least estimated error,
Monte-Carlo SURE), prints the PSNR, the estimated noise and error and the
settings chosen, and writes noisy | denoised pictures side by side.  Then
feature maps of the denoised camera image with vtkBeltramiOperators (thesis
section 2.8: the image seen as the graph (x, y, alpha f) with the flow's final
contrast scale): the edge indicator 1 - 1/W and the Gaussian curvature of the
graph (corners and junctions), written beside the denoised image.

    source build/beltrami-env.sh
    /usr/bin/python3 Examples/denoising_demo.py [output-dir]
"""
import os
import sys
import time

import numpy as np

from vtkmodules.util.numpy_support import vtk_to_numpy

from beltrami import vtkBeltramiOperators
from beltrami.pipelines import SIGMA, denoise, noisy_version, psnr, read_png, to_image, write_png, write_side_by_side

HERE = os.path.dirname(os.path.abspath(__file__))
DATA = os.path.join(HERE, "..", "Testing", "Data")


def main(argv):
    out_dir = argv[1] if len(argv) > 1 else "demo-output"
    os.makedirs(out_dir, exist_ok=True)
    print("Beltrami denoising, Gaussian noise sigma = %.2f of the range" % SIGMA)
    for name in ("camera", "coffee"):
        clean = read_png(os.path.join(DATA, name + ".png"))
        if name == "camera":
            clean = clean[..., :1]
        noisy = noisy_version(clean)
        start = time.perf_counter()
        result, report = denoise(noisy)
        elapsed = time.perf_counter() - start
        png = os.path.join(out_dir, name + "_denoised.png")
        write_side_by_side(noisy, result, png)
        scale = 1.0 if clean.shape[2] >= 3 else 255.0  # grey levels are the values; colours in [0, 1]
        print("  %-7s %dx%d: noisy %.2f dB -> %.2f dB in %.3f s (%d steps)\n"
              "          estimated noise %.3f (added %.3f), contrast scale %.3g, estimated RMS error %.4f "
              "(true %.4f)\n  wrote %s"
              % (name, clean.shape[1], clean.shape[0], psnr(noisy, clean), psnr(result, clean), elapsed,
                 report.GetArray("FlowIterations").GetValue(0),
                 report.GetArray("EstimatedNoiseLevel").GetValue(0) / scale, SIGMA,
                 report.GetArray("FlowContrastScale").GetValue(0),
                 report.GetArray("FlowEstimatedError").GetValue(1) / scale,
                 np.sqrt(np.mean((result / 255.0 - clean / 255.0) ** 2)), png))
        if name == "camera":
            feature_maps(result, report.GetArray("FlowContrastScale").GetValue(0), out_dir)
    return 0


def feature_maps(image8, contrast, out_dir):
    """Edge indicator and Gaussian curvature of the graph of a greyscale image
    (top row first), written as a picture: image | 1 - 1/W | |K|."""
    start = time.perf_counter()
    f = vtkBeltramiOperators()
    f.SetInputData(to_image(image8))
    f.SetContrastScale(contrast)
    f.Update()
    elapsed = time.perf_counter() - start
    h, w = image8.shape[:2]
    pd = f.GetOutput().GetPointData()
    edge = 1.0 - vtk_to_numpy(pd.GetArray("EdgeIndicator")).reshape(h, w)[::-1]
    gauss = np.abs(vtk_to_numpy(pd.GetArray("GaussianCurvature")).reshape(h, w)[::-1])
    to8 = lambda a: np.clip(np.round(255.0 * a), 0, 255).astype(np.uint8)[..., None]
    gap = np.full((h, 8, 1), 255, np.uint8)
    png = os.path.join(out_dir, "camera_feature_maps.png")
    write_png(np.concatenate([image8[..., :1], gap, to8(edge), gap, to8(gauss / np.quantile(gauss, 0.99))], axis=1),
              png)
    print("  camera feature maps (Beltrami operators, contrast scale %.3g) in %.3f s: edge indicator 1 - 1/W "
          "from %.2f to %.2f, |Gaussian curvature| 99th percentile %.3g\n  wrote %s"
          % (contrast, elapsed, edge.min(), edge.max(), np.quantile(gauss, 0.99), png))


if __name__ == "__main__":
    sys.exit(main(sys.argv))
