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

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy

from beltrami.pipelines import compute_curvatures, render_mean_curvature, write_vtp

HERE = os.path.dirname(os.path.abspath(__file__))
DEFAULT_MESH = os.path.join(HERE, "..", "Testing", "Data", "bunny00.off")


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
