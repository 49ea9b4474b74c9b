#!/usr/bin/python3
"""Beltrami demo: intrinsic parameterizations of a disk-like mesh (thesis ch. 5).

Reads an OFF mesh (default: the bundled mushroom), computes the discrete
conformal map (circle boundary), the discrete authalic map and the natural
conformal map with vtkIntrinsicParameterization, prints their distortion,
writes a .vtp with UV and the distortion arrays, and renders the surface with
a checkerboard texture mapped by the natural conformal map.  Then the
interactive use of the conformal map: two boundary handles dragged apart and a
line constraint, the map recomputed from the kept boundary basis without a
new solve (the flat meshes before and after, side by side).  Then the atlas
of a closed mesh (thesis section 4.2; default: the bundled bunny) and of a
CAD part (fandisk, its sharp edges kept as chart boundaries), rendered with a
checkerboard through their packed UV; the closed mesh's mean curvature
baked into its atlas texture (the geometry maps as one atlas image), written
as an image and rendered back onto the surface through UV.

    source build/beltrami-env.sh
    xvfb-run -a /usr/bin/python3 Examples/parameterization_demo.py [mesh.off] [output-dir] [closed.off]
"""
import os
import sys
import time

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonDataModel import vtkPolyData

from beltrami import vtkIntrinsicParameterization
from beltrami.pipelines import (atlas_texture, parameterize, render_checkerboard, render_flat_meshes, render_textured,
                                run_on_off, surface_atlas, to_image, write_png, write_vtp)

HERE = os.path.dirname(os.path.abspath(__file__))
DEFAULT_MESH = os.path.join(HERE, "..", "Testing", "Data", "mushroom.off")
DEFAULT_CLOSED = os.path.join(HERE, "..", "Testing", "Data", "bunny00.off")
DEFAULT_CAD = os.path.join(HERE, "..", "Testing", "Data", "fandisk.off")

MAPS = (  # name, conformal weight, authalic weight, boundary
    ("conformal (DCP, circle)", 1.0, 0.0, vtkIntrinsicParameterization.CIRCLE),
    ("authalic (DAP, circle)", 0.0, 1.0, vtkIntrinsicParameterization.CIRCLE),
    ("natural conformal", 1.0, 0.0, vtkIntrinsicParameterization.NATURAL),
)


def main(argv):
    mesh_path = argv[1] if len(argv) > 1 else DEFAULT_MESH
    out_dir = argv[2] if len(argv) > 2 else "demo-output"
    os.makedirs(out_dir, exist_ok=True)
    name = os.path.splitext(os.path.basename(mesh_path))[0]
    print("parameterizations of %s" % mesh_path)
    for label, conformal, authalic, boundary in MAPS:
        f, elapsed = parameterize(mesh_path, conformal, authalic, boundary)
        out = f.GetOutput()
        if out.GetPointData().GetArray("UV") is None:
            print("error: no parameterization of %s (see the error above)" % mesh_path, file=sys.stderr)
            return 1
        print("  %-24s %.3f s: mean angle distortion %6.3f deg, mean |log area ratio| %.3f, "
              "flipped triangles %d" % (label, elapsed, f.GetMeanAngleDistortion(),
                                        f.GetMeanAreaDistortion(), f.GetNumberOfFlippedTriangles()))
    # The last one (natural conformal): data and picture.
    vtp = os.path.join(out_dir, name + "_natural_conformal.vtp")
    png = os.path.join(out_dir, name + "_checkerboard.png")
    write_vtp(out, vtp)
    render_checkerboard(out, png)
    print("wrote %s\nwrote %s" % (vtp, png))
    if handles(mesh_path, out_dir, name):
        return 1
    return atlas(argv[3] if len(argv) > 3 else DEFAULT_CLOSED, out_dir, bake=True) or \
        atlas(DEFAULT_CAD, out_dir, split_at_features=True, direction=(1, 0.6, 0.8))


def atlas(mesh_path, out_dir, split_at_features=False, direction=(0, 0.2, 1), bake=False):
    """The atlas of a closed mesh: charts, packing, a checkerboard picture;
    with `bake`, its mean curvature as an atlas texture."""
    name = os.path.splitext(os.path.basename(mesh_path))[0]
    f, elapsed = surface_atlas(mesh_path, split_at_features=split_at_features)
    out = f.GetOutput()
    fd = out.GetFieldData()
    if fd.GetArray("AtlasCharts") is None:
        print("error: no atlas of %s (see the error above)" % mesh_path, file=sys.stderr)
        return 1
    angles = fd.GetArray("AtlasChartAngleDistortion")
    mean_angle = sum(angles.GetValue(k) for k in range(angles.GetNumberOfTuples())) / angles.GetNumberOfTuples()
    print("atlas of %s: %d charts in %.3f s, packing efficiency %.1f%%, mean chart angle distortion %.2f deg, "
          "%d sharp edges kept as chart boundaries"
          % (mesh_path, fd.GetArray("AtlasCharts").GetValue(0), elapsed,
             100 * fd.GetArray("AtlasPackingEfficiency").GetValue(0), mean_angle,
             fd.GetArray("AtlasCutEdges").GetValue(0)))
    vtp = os.path.join(out_dir, name + "_atlas.vtp")
    png = os.path.join(out_dir, name + "_atlas_checkerboard.png")
    write_vtp(out, vtp)
    render_checkerboard(out, png, squares=64, view_up=(0, 1, 0), direction=direction)
    print("wrote %s\nwrote %s" % (vtp, png))
    if bake:
        texture = atlas_texture(f)
        flat = os.path.join(out_dir, name + "_atlas_mean_curvature_map.png")
        textured = os.path.join(out_dir, name + "_atlas_mean_curvature_texture.png")
        write_png(texture, flat)
        render_textured(f.GetOutput(), to_image(texture), textured, view_up=(0, 1, 0), direction=direction)
        print("mean curvature baked into a %dx%d atlas texture\nwrote %s\nwrote %s"
              % (texture.shape[1], texture.shape[0], flat, textured))
    return 0


def handles(mesh_path, out_dir, name):
    """Section 5.4.2, interactive use: the conformal map on the circle, then
    two boundary handles (the rightmost and leftmost boundary points) dragged
    apart and a line constraint from the centre upwards, the handles moved
    twice; only the first update solves."""
    f = vtkIntrinsicParameterization()
    f.SetOutputFlattenedMesh(True)
    _, solve_time = run_on_off(mesh_path, f)
    before = vtkPolyData()
    before.DeepCopy(f.GetOutput())  # the filter's output changes with the handles
    uv = vtk_to_numpy(before.GetPointData().GetArray("UV")).copy()
    right, left = int(np.argmax(uv[:, 0])), int(np.argmin(uv[:, 0]))
    centre = int(np.argmin(np.linalg.norm(uv - [0.5, 0.5], axis=1)))
    top = int(np.argmin(np.linalg.norm(uv - [0.5, 0.8], axis=1)))
    f.AddShortestPathLineConstraint(centre, top, 0.5, 0.5, 0.5, 0.8)
    for stretch in (0.15, 0.3):
        f.RemoveAllBoundaryHandles()
        f.AddBoundaryHandle(right, uv[right, 0] + stretch, uv[right, 1])
        f.AddBoundaryHandle(left, uv[left, 0] - stretch, uv[left, 1])
        start = time.perf_counter()
        f.Update()
        elapsed = time.perf_counter() - start
        print("  handles at +-%.2f: %.3f s, %d solve(s) so far, mean angle distortion %.3f deg, flipped %d"
              % (stretch, elapsed, f.GetNumberOfSolves(), f.GetMeanAngleDistortion(),
                 f.GetNumberOfFlippedTriangles()))
    print("  (the conformal map alone took %.3f s)" % solve_time)
    png = os.path.join(out_dir, name + "_boundary_handles.png")
    render_flat_meshes((before, f.GetOutput()), png)
    print("wrote %s" % png)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
