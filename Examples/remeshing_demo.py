#!/usr/bin/python3
"""Beltrami demo: remeshing (thesis chapter 4) with vtkSurfaceRemeshing.

Remeshes the bundled bunny with exactly 5,000 vertices, uniformly and
adapted to its mean curvature, and to its maximum curvature through an
edited transfer function with a smooth gradation, and the CAD part fandisk uniformly with its
sharp edges kept; prints the quality figures and writes the remeshes (.vtp)
and pictures of their triangles.  Then fandisk within 0.1% of its diagonal
both ways (the error-driven mode), isotropic and anisotropic (triangles
stretched along the directions of least curvature, the thesis' future
work): the vertex counts, and the two side by side.

    source build/beltrami-env.sh
    xvfb-run -a /usr/bin/python3 Examples/remeshing_demo.py [output-dir]
"""
import os
import sys

from beltrami import vtkSurfaceRemeshing
from beltrami.pipelines import remesh, render_side_by_side, render_wireframe, write_vtp

HERE = os.path.dirname(os.path.abspath(__file__))
DATA = os.path.join(HERE, "..", "Testing", "Data")

# The graded run: max |kappa| through an edited transfer function (flat
# regions at 0.3 of the mean density, saturating at 4x for curvatures 3x the
# mean), low-pass filtered over the surface with a width of 0.03 (about two
# edge lengths of the remesh) for a smooth gradation.
GRADED = dict(gradation=0.03, transfer_function=((0.0, 0.3), (1.0, 1.0), (3.0, 4.0)))
RUNS = (  # mesh, label, importance, sharp edges, view direction, view up, other settings
    ("bunny00.off", "uniform", vtkSurfaceRemeshing.UNIFORM, False, (0, 0.2, 1), (0, 1, 0), {}),
    ("bunny00.off", "mean_curvature", vtkSurfaceRemeshing.MEAN_CURVATURE, False, (0, 0.2, 1), (0, 1, 0), {}),
    ("bunny00.off", "max_curvature_graded", vtkSurfaceRemeshing.MAXIMUM_CURVATURE, False, (0, 0.2, 1), (0, 1, 0),
     GRADED),
    ("fandisk.off", "uniform", vtkSurfaceRemeshing.UNIFORM, True, (1, 0.6, 0.8), (0, 1, 0), {}),
)


def main(argv):
    out_dir = argv[1] if len(argv) > 1 else "demo-output"
    os.makedirs(out_dir, exist_ok=True)
    for mesh, label, importance, sharp, direction, up, settings in RUNS:
        f, elapsed = remesh(os.path.join(DATA, mesh), 5000, importance, split_at_features=sharp, **settings)
        out = f.GetOutput()
        fd = out.GetFieldData()
        if fd.GetArray("RemeshMeanMinimumAngle") is None:
            print("error: no remesh of %s (see the error above)" % mesh, file=sys.stderr)
            return 1
        print("remesh of %s (%s%s): %d vertices, %d triangles in %.2f s; minimum angle mean %.1f deg, "
              "worst %.1f deg, below 30 deg %.2f%%, valence 6 %.1f%%, edge-length variation %.3f"
              % (mesh, label.replace("_", " "), ", sharp edges kept" if sharp else "", out.GetNumberOfPoints(),
                 out.GetNumberOfCells(), elapsed, fd.GetArray("RemeshMeanMinimumAngle").GetValue(0),
                 fd.GetArray("RemeshMinimumAngle").GetValue(0), 100 * fd.GetArray("RemeshFractionBelow30").GetValue(0),
                 100 * fd.GetArray("RemeshFractionValence6").GetValue(0),
                 fd.GetArray("RemeshEdgeLengthVariation").GetValue(0)))
        stem = os.path.join(out_dir, "%s_remesh_%s" % (os.path.splitext(mesh)[0], label))
        write_vtp(out, stem + ".vtp")
        render_wireframe(out, stem + ".png", view_up=up, direction=direction)
        print("wrote %s.vtp\nwrote %s.png" % (stem, stem))
    return equal_deviation(out_dir)


def equal_deviation(out_dir, bound=0.001):
    """fandisk within `bound` of its diagonal, isotropic and anisotropic."""
    remeshes = []
    for anisotropy in (vtkSurfaceRemeshing.ISOTROPIC, vtkSurfaceRemeshing.PRINCIPAL_CURVATURES):
        f, elapsed = remesh(os.path.join(DATA, "fandisk.off"), 0, split_at_features=True, anisotropy=anisotropy,
                            maximum_deviation=bound)
        out = f.GetOutput()
        deviation = out.GetFieldData().GetArray("RemeshDeviation")
        if deviation is None:
            print("error: no remesh of fandisk.off (see the error above)", file=sys.stderr)
            return 1
        print("fandisk within %.1f%% of its diagonal, %s: %d vertices in %.2f s (deviation %.3f%%)"
              % (100 * bound, "anisotropic" if anisotropy else "isotropic", out.GetNumberOfPoints(), elapsed,
                 100 * max(deviation.GetValue(0), deviation.GetValue(1))))
        remeshes.append(out)
    png = os.path.join(out_dir, "fandisk_remesh_isotropic_anisotropic.png")
    render_side_by_side(remeshes, png, size=(1600, 700), gap=0.3, direction=(1, 0.6, 0.8), zoom=2.1)
    print("wrote %s" % png)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
