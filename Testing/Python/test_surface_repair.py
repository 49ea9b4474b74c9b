"""The repairs every surface filter makes (coincident points merged,
orientation made consistent) give the numbers of the surface as it should
have been: an STL-like soup of a sphere and the same sphere with half its
triangles turned must give the clean sphere's curvatures, fairing,
remeshing and tetrahedra, each with a warning that says what was repaired.
Prints "surface repair test passed"."""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import beltrami as b  # noqa: E402
import inputs  # noqa: E402
from vtkmodules.util.numpy_support import vtk_to_numpy  # noqa: E402

failures = []


def check(ok, what):
    print(("ok      " if ok else "FAILED  ") + what)
    if not ok:
        failures.append(what)


def run(cls, data, **settings):
    f = inputs.filter_with(cls, **settings)()
    said = inputs.Messages(f, f.GetExecutive())
    f.SetInputData(data)
    f.Update()
    return f.GetOutputDataObject(0), said


def signed_volume(points, triangles):
    a, b_, c = (points[triangles[:, k]] for k in range(3))
    return float(np.einsum("ij,ij->i", a, np.cross(b_, c)).sum() / 6.0)


p, t = inputs.sphere(16)
clean = inputs.polydata(p, t)
soup_points = p[t].reshape(-1, 3)
soup = inputs.polydata(soup_points, np.arange(len(soup_points)).reshape(-1, 3))
of_soup = t.reshape(-1)  # soup point k is clean point of_soup[k]
turned = t.copy()
turned[::2] = turned[::2, ::-1]
half_flipped = inputs.polydata(p, turned)

# Curvatures: the soup's and the half-flipped sphere's are the clean sphere's, sign included.
reference, _ = run(b.vtkDiscreteCurvatures, clean)
H = vtk_to_numpy(reference.GetPointData().GetArray("MeanCurvature"))
for name, data, index in (("soup", soup, of_soup), ("half-flipped sphere", half_flipped, np.arange(len(p)))):
    out, said = run(b.vtkDiscreteCurvatures, data)
    h = vtk_to_numpy(out.GetPointData().GetArray("MeanCurvature"))
    check(np.allclose(h, H[index], atol=1e-12, rtol=0), "curvatures of the %s equal the clean sphere's "
          "(largest difference %.2e, mean curvature %.3f)" % (name, np.abs(h - H[index]).max(), H.mean()))
    repaired = [line for w in said.warnings for line in w.splitlines() if "was repaired" in line]
    check(bool(repaired) and not said.errors, "curvatures of the %s: a repair warning (%s)"
          % (name, repaired[0].split("): ", 1)[-1] if repaired else "none"))

# Fairing: the soup stays closed (coincident points move together) and
# moves as the clean sphere does (to the iterative solver's tolerance).
faired, _ = run(b.vtkImplicitFairing, clean)
q = vtk_to_numpy(faired.GetPoints().GetData())
out, _ = run(b.vtkImplicitFairing, soup)
s = vtk_to_numpy(out.GetPoints().GetData())
check(np.allclose(s, q[of_soup], atol=1e-4 * np.abs(q - p).max(), rtol=0),
      "fairing of the soup moves its points as the clean sphere's (largest difference %.2e, largest move %.2e)"
      % (np.abs(s - q[of_soup]).max(), np.abs(q - p).max()))

# Remeshing and TetGen: a closed surface facing outwards, of the sphere's volume.
volume = signed_volume(p, t)
for name, data in (("soup", soup), ("half-flipped sphere", half_flipped)):
    out, said = run(b.vtkSurfaceRemeshing, data, NumberOfVertices=800)
    rp, rt = inputs.arrays_of(out)
    topo = inputs.topology(rp, rt)
    v = signed_volume(rp, rt) if len(rt) else 0.0
    check(len(rp) == 800 and topo["euler"] == 2 and topo["manifold"] and topo["oriented"]
          and abs(v / volume - 1.0) < 0.02, "remeshing the %s: 800 vertices, a sphere, volume %.4f of %.4f"
          % (name, v, volume))
    grid, said = run(b.vtkTetGenTetrahedralizer, data)
    cells = grid.GetNumberOfCells()
    total = 0.0
    if cells:
        x = vtk_to_numpy(grid.GetPoints().GetData())
        tets = vtk_to_numpy(grid.GetCells().GetConnectivityArray()).reshape(-1, 4)
        a, b_, c, d = (x[tets[:, k]] for k in range(4))
        signed = np.einsum("ij,ij->i", b_ - a, np.cross(c - a, d - a)) / 6.0
        total = float(np.abs(signed).sum())
    check(cells > 0 and abs(total / volume - 1.0) < 1e-9,
          "TetGen on the %s: %d tetrahedra, volume %.6f of %.6f" % (name, cells, total, volume))

if failures:
    print("%d FAILED" % len(failures))
    sys.exit(1)
print("surface repair test passed")
