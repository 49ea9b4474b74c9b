"""Benchmark (on demand): vtkSurfaceVectorFieldDecomposition against the
same decomposition written the way a Python user would write it without
us: NumPy for the cotangent and nonconforming matrices, SciPy's sparse
direct solver (SuperLU) for the two Poisson systems.  No VTK, ParaView or
TTK filter decomposes a field on a surface; the peer is also an independent
check of our numbers (the parts of both must agree to the solvers'
accuracy).  Bunny scan Loop-subdivided 0 to 2 times, fandisk_large 3 times
(1.01M vertices, from the shared corpus) and fandisk 4 times (1.66M; both
ours alone), the genus-2 eight 5 times, the mushroom (a disk)
4 times and a 720 x 360 latitude-longitude sphere (a rotation plus a source
as cell data), 2 threads; writes the table
for the guide's benchmarks page (results.py).
Run:  source build/beltrami-env.sh && /usr/bin/python3 Testing/Benchmarks/benchmark_vector_fields.py [levels]"""
import os
import sys

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkFiltersModeling import vtkLoopSubdivisionFilter
from vtkmodules.vtkFiltersSources import vtkSphereSource

import results
from timing import timed

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "Python"))
import inputs  # noqa: E402
from beltrami import vtkOFFReader, vtkSurfaceVectorFieldDecomposition  # noqa: E402

THREADS = 2
PEER_VERTICES = 700000  # SciPy's SuperLU beyond: minutes


def subdivided(name, levels):
    """Testing/Data's mesh, or the shared corpus's, Loop-subdivided `levels` times."""
    path = os.path.join(HERE, "..", "Data", name + ".off")
    reader = vtkOFFReader()
    reader.SetFileName(path if os.path.exists(path) else os.path.join(inputs.SHARED_MESHES, name + ".off"))
    loop = vtkLoopSubdivisionFilter()
    loop.SetInputConnection(reader.GetOutputPort())
    loop.SetNumberOfSubdivisions(levels)
    loop.Update()
    return loop.GetOutput() if levels else reader.GetOutput()


def latitude_longitude(longitudes, latitudes):
    """A unit sphere of `latitudes` rings of `longitudes` points and two poles (vtkSphereSource)."""
    source = vtkSphereSource()
    source.SetThetaResolution(longitudes)
    source.SetPhiResolution(latitudes)
    source.Update()
    return source.GetOutput()


def with_field(mesh):
    """A rotation about the vertical axis plus a source, per triangle (cell data "Field")."""
    p, t = inputs.arrays_of(mesh)
    c = p[t].mean(axis=1)
    c0 = c - c.mean(axis=0)
    source = np.exp(-np.sum(c0 ** 2, axis=1) / (0.1 * np.ptp(c0, axis=0).max()) ** 2)[:, None] * c0
    field = np.cross([0.0, 1.0, 0.0], c0) + 5 * source
    array = numpy_to_vtk(np.ascontiguousarray(field), deep=True)
    array.SetName("Field")
    mesh.GetCellData().AddArray(array)
    return p, t, field


def ours(mesh):
    f = vtkSurfaceVectorFieldDecomposition()
    f.SetInputData(mesh)
    f.SetInputArrayToProcess(0, 0, 0, 1, "Field")
    f.SetNumberOfThreads(THREADS)
    f.Update()
    cd = f.GetOutput().GetCellData()
    return [vtk_to_numpy(cd.GetArray(k)) for k in ("CurlFreePart", "DivergenceFreePart", "HarmonicPart")], \
        f.GetOutput().GetFieldData()


def scipy_decomposition(p, t, x):
    """The same discretization with NumPy and SciPy (one unknown pinned per system; on open surfaces the
    stream function held at 0 on the boundary edges, the filter's default)."""
    a, b, c = p[t[:, 0]], p[t[:, 1]], p[t[:, 2]]
    cross = np.cross(b - a, c - a)
    twice = np.linalg.norm(cross, axis=1)
    n = cross / twice[:, None]
    x = x - (x * n).sum(1)[:, None] * n
    corners = [a, b, c]
    sides = [corners[(k + 2) % 3] - corners[(k + 1) % 3] for k in range(3)]  # opposite vertex k
    cot = [-(sides[(k + 1) % 3] * sides[(k + 2) % 3]).sum(1) / twice for k in range(3)]  # angle at vertex k
    nv = len(p)
    # Conforming: S_ij = -cot(angle opposite ij) / 2.
    rows, cols, vals = [], [], []
    for k in range(3):
        i, j = t[:, (k + 1) % 3], t[:, (k + 2) % 3]
        w = 0.5 * cot[k]
        rows += [i, j, i, j]
        cols += [j, i, i, j]
        vals += [-w, -w, w, w]
    s = sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(nv, nv))
    rhs = np.zeros(nv)
    for k in range(3):
        np.add.at(rhs, t[:, k], 0.5 * (x * np.cross(n, sides[k])).sum(1))
    u = pinned_solve(s, rhs)
    gradient = sum(u[t[:, k]][:, None] * np.cross(n, sides[k]) for k in range(3)) / twice[:, None]
    # Nonconforming: edges of the triangles, opposite each vertex.
    pairs = np.sort(np.stack([np.stack([t[:, (k + 1) % 3], t[:, (k + 2) % 3]], 1) for k in range(3)], 1), axis=2)
    edges, index, uses = np.unique(pairs.reshape(-1, 2), axis=0, return_inverse=True, return_counts=True)
    index = index.reshape(-1, 3)
    rows, cols, vals = [], [], []
    for k in range(3):  # edges opposite k+1 and k+2 meet at vertex k: -2 cot(theta_k)
        e, f = index[:, (k + 1) % 3], index[:, (k + 2) % 3]
        w = 2.0 * cot[k]
        rows += [e, f, e, f]
        cols += [f, e, e, f]
        vals += [-w, -w, w, w]
    ne = len(edges)
    s = sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(ne, ne))
    rhs = np.zeros(ne)
    for k in range(3):
        np.add.at(rhs, index[:, k], (x * sides[k]).sum(1))
    v = pinned_solve(s, rhs, uses == 1)
    rotated = sum(v[index[:, k]][:, None] * sides[k] for k in range(3)) / (0.5 * twice)[:, None]
    return [gradient, rotated, x - gradient - rotated]


def pinned_solve(s, rhs, fixed=None):
    """s x = rhs with the fixed rows at 0 (none: the first row)."""
    keep = np.flatnonzero(~fixed) if fixed is not None and fixed.any() else np.arange(1, s.shape[0])
    out = np.zeros(s.shape[0])
    out[keep] = spla.spsolve(s[keep][:, keep].tocsc(), rhs[keep])
    return out


def main(argv):
    levels = int(argv[1]) if len(argv) > 1 else 2
    rows = []
    # The bunny and fandisk: closed, genus 0, and the mushroom: a disk (the stream function integrated);
    # the eight: genus 2 (solved).
    # The latitude-longitude grid of a global climate model (0.5 degrees): long thin triangles at the poles.
    # A million points: the shared corpus's fandisk_large, three times (1.01M).
    meshes = [("bunny00", k) for k in range(levels + 1)] + [("eight", 3 + levels), ("mushroom", 2 + levels),
                                                             ("latitude-longitude", 0), ("fandisk_large", 1 + levels),
                                                             ("fandisk", 2 + levels)]
    for name, level in meshes:
        mesh = latitude_longitude(720, 360) if name == "latitude-longitude" else subdivided(name, level)
        p, t, field = with_field(mesh)
        (parts, fd), seconds = timed(lambda: ours(mesh), repeats=3 if len(p) < 1100000 else 1)
        if len(p) > PEER_VERTICES:
            peer, differ = float("nan"), float("nan")
        else:
            reference, peer = timed(lambda: scipy_decomposition(p, t, field), repeats=1)
            area = 0.5 * np.linalg.norm(np.cross(p[t[:, 1]] - p[t[:, 0]], p[t[:, 2]] - p[t[:, 0]]), axis=1)
            norm = np.sqrt((area[:, None] * field ** 2).sum())
            differ = max(np.sqrt((area[:, None] * (a - b) ** 2).sum()) / norm for a, b in zip(parts, reference))
        energy = fd.GetArray("TangentEnergy").GetValue(0)
        inner = max(abs(fd.GetArray(k).GetValue(0)) for k in ("CurlFreeDivergenceFreeInnerProduct",
                                                             "CurlFreeHarmonicInnerProduct",
                                                             "DivergenceFreeHarmonicInnerProduct")) / energy
        print("%d vertices: ours %.2f s (%d iterations), NumPy + SciPy %.2f s (%.1fx); parts differ by %.1e, "
              "largest inner product %.1e of the energy"
              % (len(p), seconds, fd.GetArray("SolverIterations").GetValue(0), peer, peer / seconds, differ, inner),
              flush=True)
        skipped = "skipped (over %dk vertices)" % (PEER_VERTICES // 1000)
        rows.append([name + (" Loop x%d" % level if level else ""), len(p), round(seconds, 3),
                     round(peer, 3) if peer == peer else skipped, round(peer / seconds, 1) if peer == peer else "-",
                     float("%.2g" % differ) if differ == differ else "-", float("%.2g" % inner)])
    results.save("vector_fields", "Vector fields", "Helmholtz-Hodge decomposition",
                 "the same discretization in NumPy with SciPy's sparse direct solver (SuperLU)",
                 "bunny00 Loop-subdivided 0 to %d times, fandisk_large %d times and fandisk %d times (closed, "
                 "genus 0), eight %d times (genus 2), mushroom %d times (a disk), a 720 x 360 latitude-longitude "
                 "sphere; a rotation plus a source per triangle"
                 % (levels, 1 + levels, 2 + levels, 3 + levels, 2 + levels),
                 ["mesh", "vertices", "ours s (%d threads)" % THREADS, "NumPy + SciPy s", "SciPy / ours",
                  "parts differ (L2, of the field)", "largest inner product (of the energy)"], rows,
                 "Ours, one field per run: the vertices' system by conjugate gradients on the surface's "
                 "geometric multigrid from 50k vertices on (a sparse Cholesky factorization in nested-dissection "
                 "order below, and where the same surface comes again: time steps), the edges' system "
                 "factorized; relative residual at most 1e-10. On closed genus-0 surfaces and disks one solve "
                 "(the stream function integrated), on the eight two. On the latitude-longitude "
                 "sphere the multigrid converges slowly (its triangles are long and thin at the poles) and gives "
                 "way to the factorization after 30 iterations. "
                 "The two implementations are independent: their parts agree to the solvers' accuracy.")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
