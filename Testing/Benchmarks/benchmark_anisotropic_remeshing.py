#!/usr/bin/python3
"""Benchmark (on demand, not a test): vtkSurfaceRemeshing's anisotropic mode
(a metric from the principal curvatures) against its isotropic modes, in the
same run, on the same shapes: the fewest vertices that keep the remesh within
a two-sided deviation of the input.

    source build/beltrami-env.sh
    /usr/bin/python3 Testing/Benchmarks/benchmark_anisotropic_remeshing.py [--big]

Shapes: an open cylinder (radius 1, length 4), fandisk (its edges sharper
than 60 degrees kept), a twisted, cambered turbine-blade-like sweep
(Testing/Python/inputs.blade) and the bunny scan (bunny00).  For each mode,
the smallest vertex count found within the bound over six tries (each count
the last one scaled by the deviation's ratio to the bound), and the count the
error-driven mode (MaximumDeviation, the count left to it) ends with.  The
isotropic reference is the best of the uniform mode and the curvature-
adapted ones (importance max |k| to the powers 1 and 0.5), MaximumSurfaceSag
at its default in all.  For the anisotropic remesh at its count: its edges
and angles in the metric (RemeshMetricQuality), and the mean angle of its
edges from the nearer principal direction where the principal curvatures'
ratio exceeds 3 (the directions of vtkDiscreteCurvatures on the input,
interpolated at the remesh's vertices), against the isotropic remesh's.
--big instead: the 1.2M-triangle bunny (bunny00 after two Loop
subdivisions) to 100k vertices, isotropic and anisotropic, with the stages'
seconds."""
import os
import sys
import time

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy

import results
import timing  # noqa: F401 (the shared allocator settings)
from beltrami import vtkDiscreteCurvatures, vtkSurfaceRemeshing
from benchmark_remeshing import remesher, smallest_count

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "Python"))
import inputs  # noqa: E402

MODES = [("uniform", {}),
         ("curvature", {"Importance": vtkSurfaceRemeshing.MAXIMUM_CURVATURE}),
         ("curvature 0.5", {"Importance": vtkSurfaceRemeshing.MAXIMUM_CURVATURE, "Gamma": 0.5}),
         ("anisotropic", {"Anisotropy": vtkSurfaceRemeshing.PRINCIPAL_CURVATURES})]


def shapes():
    """(name, surface with its principal curvatures and directions, sharp edges kept, bound)."""
    data = os.path.join(HERE, "..", "Data")
    cases = [("cylinder", inputs.polydata(*inputs.tube()), False, 5e-4),
             ("fandisk", inputs.read_off(os.path.join(data, "fandisk.off")), True, 1e-3),
             ("blade", inputs.polydata(*inputs.blade()), False, 5e-4),
             ("bunny00", inputs.read_off(os.path.join(data, "bunny00.off")), False, 2e-3)]
    for name, surface, features, bound in cases:
        c = vtkDiscreteCurvatures()
        c.SetInputData(surface)
        for what in ("PrincipalCurvatures", "PrincipalDirections", "Normals"):
            getattr(c, "SetCompute" + what)(True)
        c.Update()
        yield name, c.GetOutput(), features, bound


def alignment(remesh, ratio=3.0):
    """The mean angle (degrees) of the remesh's edges, in the tangent plane,
    from the nearer principal direction, at both ends where the principal
    curvatures' ratio exceeds `ratio`."""
    points, triangles = inputs.arrays_of(remesh)
    array = lambda name: vtk_to_numpy(remesh.GetPointData().GetArray(name)).astype(float)  # noqa: E731
    k1, k2, e1, normals = array("MaximumCurvature"), array("MinimumCurvature"), array("PrincipalDirection1"), \
        array("Normals")
    edges = np.concatenate([triangles[:, [k, (k + 1) % 3]] for k in range(3)])
    angles = []
    for end in (0, 1):
        v = edges[:, end]
        n = normals[v] / np.linalg.norm(normals[v], axis=1)[:, None]
        d = points[edges[:, 1]] - points[edges[:, 0]]
        d -= np.einsum("ij,ij->i", d, n)[:, None] * n
        e = e1[v] - np.einsum("ij,ij->i", e1[v], n)[:, None] * n
        length = np.linalg.norm(e, axis=1)
        cosine = np.abs(np.einsum("ij,ij->i", d, e)) / np.maximum(np.linalg.norm(d, axis=1) * length, 1e-300)
        angle = np.degrees(np.arccos(np.clip(cosine, 0.0, 1.0)))
        anisotropic = (np.maximum(np.abs(k1[v]), np.abs(k2[v])) > ratio * np.minimum(np.abs(k1[v]), np.abs(k2[v])))
        angles.append(np.minimum(angle, 90.0 - angle)[anisotropic & (length > 0.5)])
    return float(np.concatenate(angles).mean())


def big():
    """bunny00 after two Loop subdivisions (1.2M triangles) to 100k vertices,
    isotropic (uniform) and anisotropic: whole-filter seconds (a fresh
    filter), the stages' seconds and the two-sided deviation."""
    from benchmark_parameterization import mesh
    data = mesh("bunny00.off", 2)
    columns = ["mode", "input triangles", "vertices", "seconds", "sampling s", "triangulation s", "optimisation s",
               "deviation % diag."]
    rows = []
    for label, settings in (("isotropic", {}), ("anisotropic", {"Anisotropy": vtkSurfaceRemeshing.PRINCIPAL_CURVATURES})):
        f = remesher(data, False, NumberOfVertices=100000, **settings)
        start = time.perf_counter()
        f.Update()
        seconds = time.perf_counter() - start
        fields = f.GetOutput().GetFieldData()
        parts, d = fields.GetArray("RemeshSeconds"), fields.GetArray("RemeshDeviation")
        rows.append([label, data.GetNumberOfCells(), f.GetOutput().GetNumberOfPoints(), round(seconds, 2)] +
                    [round(parts.GetValue(k), 2) for k in range(3)] +
                    [round(100.0 * max(d.GetValue(0), d.GetValue(1)), 4)])
        print("| " + " | ".join(map(str, rows[-1])) + " |")
    results.save("remeshing_anisotropic_big", "Remeshing", "Anisotropic remeshing of a large mesh",
                 "our isotropic (uniform) mode", "bunny00 after two Loop subdivisions to 100,000 vertices",
                 columns, rows, "Whole filter on a fresh filter (atlas and metric included).")


def main(argv):
    if "--big" in argv:
        big()
        return 0
    columns = ["shape", "bound % diag.", "uniform", "curvature", "curvature 0.5", "anisotropic", "fewer than isotropic %",
               "error-driven isotropic", "error-driven anisotropic", "metric median edge", "metric edges within 20% %",
               "metric mean min angle", "alignment deg (isotropic)", "anisotropic seconds"]
    print("| " + " | ".join(columns) + " |")
    print("|" + "---|" * len(columns))
    rows = []
    for name, surface, features, bound in shapes():
        percent = 100.0 * bound
        found, kept = {}, {}
        for label, settings in MODES:
            f = remesher(surface, features, **settings)  # (its atlas kept between the counts)

            def run(count, f=f):
                f.SetNumberOfVertices(count)
                f.Update()
                out = f.GetOutput()
                if out.GetNumberOfPoints() == 0:
                    return 0, None
                d = out.GetFieldData().GetArray("RemeshDeviation")
                return out.GetNumberOfPoints(), 100.0 * max(d.GetValue(0), d.GetValue(1))
            found[label] = smallest_count(run, percent, 2000)
            if found[label]:  # the remesh at the count found, for its figures
                f.Modified()  # (timed even where the search's last run had that count: its atlas kept)
                start = time.perf_counter()
                run(found[label][0])
                kept[label] = (time.perf_counter() - start, type(f.GetOutput())())
                kept[label][1].DeepCopy(f.GetOutput())
        driven = []
        for settings in ({}, {"Anisotropy": vtkSurfaceRemeshing.PRINCIPAL_CURVATURES}):
            f = remesher(surface, features, NumberOfVertices=0, MaximumDeviation=bound, **settings)
            f.Update()
            driven.append(f.GetOutput().GetNumberOfPoints())
        isotropic = min(found[label][0] for label, _ in MODES[:3] if found[label])
        best = min((label for label, _ in MODES[:3] if found[label]), key=lambda label: found[label][0])
        anisotropic = found["anisotropic"][0] if found["anisotropic"] else None
        seconds, remesh = kept.get("anisotropic", (None, None))
        figures = remesh.GetFieldData().GetArray("RemeshMetricQuality") if remesh else None
        row = [name, percent] + [found[label][0] if found[label] else "not met" for label, _ in MODES] + [
            round(100.0 * (1.0 - anisotropic / isotropic), 1) if anisotropic else "",
            driven[0], driven[1],
            round(figures.GetValue(0), 3) if figures else "", round(100.0 * figures.GetValue(1), 1) if figures else "",
            round(figures.GetValue(3), 1) if figures else "",
            "%.1f (%.1f)" % (alignment(remesh), alignment(kept[best][1])) if remesh else "",
            round(seconds, 2) if seconds else ""]
        rows.append(row)
        print("| " + " | ".join(map(str, row)) + " |")
        sys.stdout.flush()
    results.save("remeshing_anisotropic", "Remeshing", "Anisotropic remeshing: vertices at equal deviation",
                 "our isotropic modes (uniform; curvature-adapted, importance max |k| to the powers 1 and 0.5)",
                 "an open cylinder, fandisk (sharp edges kept), a twisted turbine-blade-like sweep, the bunny scan",
                 columns, rows,
                 "Vertex counts: the fewest found within the two-sided bound (in % of the diagonal) over six "
                 "tries each; 'fewer than isotropic': against the best isotropic mode; error-driven: the count "
                 "MaximumDeviation ends with. Metric figures and alignment of the anisotropic remesh at its count "
                 "(alignment: mean angle of the edges from the nearer principal direction where the curvatures' "
                 "ratio exceeds 3; in brackets the best isotropic remesh's).")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
