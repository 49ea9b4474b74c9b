"""The inputs every filter is tried on, shared by the corpus sweep, the
hostile-input runs and the remeshing checks: the real meshes (every OFF file
of the shared corpus and of Testing/Data), shapes generated to break a
filter (thin spikes and limbs, tiny components, thin plates, huge and tiny
coordinates), hostile data sets (non-finite coordinates, non-manifold and
non-orientable surfaces, soups, degenerate images and grids), and the
measures the checks read (topology, manifoldness, two-sided deviation)."""
import glob
import math
import os

import numpy as np
from vtkmodules.util.misc import calldata_type
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.util.vtkConstants import VTK_STRING
from vtkmodules.vtkCommonCore import reference, vtkCommand, vtkIdTypeArray, vtkPoints
from vtkmodules.vtkCommonDataModel import (VTK_HEXAHEDRON, VTK_POLYHEDRON, VTK_TETRA, VTK_TRIANGLE, VTK_WEDGE,
                                           vtkCellArray, vtkImageData, vtkPolyData, vtkStaticCellLocator,
                                           vtkUnstructuredGrid)

HERE = os.path.dirname(os.path.abspath(__file__))
DATA = os.path.normpath(os.path.join(HERE, "..", "Data"))
SHARED_MESHES = os.path.normpath(os.path.join(HERE, "..", "..", "..", "shared", "data", "meshes"))


def filter_with(cls, **settings):
    """A maker of `cls` filters with Set<Key>(value) for every setting."""
    def make():
        f = cls()
        for key, value in settings.items():
            getattr(f, "Set" + key)(value)
        return f
    return make


# ---------------------------------------------------------------- real meshes

def corpus_paths():
    """Every real mesh: the shared corpus (where it exists, as in CI) and the
    meshes of Testing/Data, one path per file name (the shared copy first)."""
    paths = {}
    for folder in (SHARED_MESHES, DATA):
        for path in sorted(glob.glob(os.path.join(folder, "*.off"))):
            paths.setdefault(os.path.basename(path), path)
    return [paths[name] for name in sorted(paths)]


def read_off(path):
    from beltrami import vtkOFFReader
    reader = vtkOFFReader()
    reader.SetFileName(path)
    reader.Update()
    out = vtkPolyData()
    out.DeepCopy(reader.GetOutput())
    return out


# ------------------------------------------------------ arrays <-> poly data

def polydata(points, triangles):
    """A vtkPolyData of points (n x 3) and triangles (m x 3, any ids: bad
    ids are the caller's intent)."""
    points = np.ascontiguousarray(points, dtype=np.float64).reshape(-1, 3)
    triangles = np.ascontiguousarray(triangles, dtype=np.int64).reshape(-1, 3)
    out = vtkPolyData()
    p = vtkPoints()
    p.SetDataTypeToDouble()
    p.SetData(numpy_to_vtk(points, deep=True))
    out.SetPoints(p)
    cells = vtkCellArray()
    offsets = numpy_to_vtk(np.arange(0, 3 * len(triangles) + 1, 3, dtype=np.int64), deep=True,
                           array_type=vtkIdTypeArray().GetDataType())
    connectivity = numpy_to_vtk(triangles.ravel(), deep=True, array_type=vtkIdTypeArray().GetDataType())
    cells.SetData(offsets, connectivity)
    out.SetPolys(cells)
    return out


def arrays_of(mesh):
    """(points n x 3, triangles m x 3) of a poly data's polygons (triangulated)."""
    points = vtk_to_numpy(mesh.GetPoints().GetData()).astype(np.float64) if mesh.GetPoints() else np.zeros((0, 3))
    polys = mesh.GetPolys()
    if polys is None or polys.GetNumberOfCells() == 0:
        return points, np.zeros((0, 3), dtype=np.int64)
    offsets = vtk_to_numpy(polys.GetOffsetsArray()).astype(np.int64)
    connectivity = vtk_to_numpy(polys.GetConnectivityArray()).astype(np.int64)
    if np.all(np.diff(offsets) == 3):
        return points, connectivity.reshape(-1, 3)
    # Polygons: fans, n - 2 triangles each, as the filters triangulate them
    # at the least (vtkTriangleFilter drops the degenerate ones, which
    # opens closed surfaces).
    triangles = [(connectivity[a], connectivity[a + k], connectivity[a + k + 1])
                 for a, b in zip(offsets[:-1], offsets[1:]) for k in range(1, b - a - 1)]
    return points, np.array(triangles, dtype=np.int64).reshape(-1, 3)


def triangulated(mesh):
    """(points, triangles) of a poly data's polygons as the filters
    triangulate them (vtkBeltramiSurface): quads along the shorter diagonal,
    larger polygons by VTK's ear cutting, a fan where that fails."""
    from vtkmodules.vtkCommonCore import vtkIdList
    from vtkmodules.vtkCommonDataModel import vtkPolygon
    points, _ = arrays_of(mesh)
    polys = mesh.GetPolys()
    if polys is None or polys.GetNumberOfCells() == 0:
        return arrays_of(mesh)
    offsets = vtk_to_numpy(polys.GetOffsetsArray()).astype(np.int64)
    connectivity = vtk_to_numpy(polys.GetConnectivityArray()).astype(np.int64)
    triangles = []
    polygon, scratch = vtkPolygon(), vtkIdList()
    for a, b in zip(offsets[:-1], offsets[1:]):
        ids = connectivity[a:b]
        if len(ids) == 4:
            shorter = np.sum((points[ids[0]] - points[ids[2]]) ** 2) <= np.sum((points[ids[1]] - points[ids[3]]) ** 2)
            triangles += [ids[[0, 1, 2]], ids[[0, 2, 3]]] if shorter else [ids[[0, 1, 3]], ids[[1, 2, 3]]]
            continue
        if len(ids) > 4:
            polygon.Initialize(len(ids), [int(i) for i in ids], mesh.GetPoints())
            scratch.Reset()
            if polygon.Triangulate(scratch) and scratch.GetNumberOfIds() == 3 * (len(ids) - 2):
                local = [scratch.GetId(k) for k in range(scratch.GetNumberOfIds())]
                triangles += [ids[local[k:k + 3]] for k in range(0, len(local), 3)]
                continue
        triangles += [ids[[0, k, k + 1]] for k in range(1, len(ids) - 1)]
    return points, np.array(triangles, dtype=np.int64).reshape(-1, 3)


def with_scalars(mesh, name="Scalars"):
    """mesh with a point array (a smooth function of the position plus a
    little deterministic noise): what the data filters smooth."""
    n = mesh.GetNumberOfPoints()
    values = np.zeros(n)
    if n:
        p = vtk_to_numpy(mesh.GetPoints().GetData()).astype(np.float64)
        with np.errstate(all="ignore"):
            values = np.sin(p[:, 0]) + 0.05 * np.cos(37.0 * np.arange(n))
    array = numpy_to_vtk(values, deep=True)
    array.SetName(name)
    mesh.GetPointData().AddArray(array)
    mesh.GetPointData().SetActiveScalars(name)
    return mesh


# ---------------------------------------------------------- generated shapes

def with_vectors(mesh, name="Vectors"):
    """A shallow copy of mesh with a point vector array (a rotation about z
    plus a gradient-like part, not tangent), the active vectors: what the
    vector-field decomposition takes."""
    from vtkmodules.vtkCommonDataModel import vtkPolyData
    out = vtkPolyData()
    out.ShallowCopy(mesh)
    n = mesh.GetNumberOfPoints()
    values = np.zeros((n, 3))
    if n:
        p = vtk_to_numpy(mesh.GetPoints().GetData()).astype(np.float64)
        with np.errstate(all="ignore"):
            c = p - np.nanmean(np.where(np.isfinite(p), p, np.nan), axis=0)
            values = np.stack([-c[:, 1] + 0.3 * c[:, 0], c[:, 0] + 0.3 * c[:, 1], 0.2 * np.sin(c[:, 2])], axis=1)
    array = numpy_to_vtk(values, deep=True)
    array.SetName(name)
    out.GetPointData().AddArray(array)
    out.GetPointData().SetActiveVectors(name)
    return out


def _mobius(n=24):
    pts, tris = [], []
    for i in range(n):
        u = 2.0 * math.pi * i / n
        for s in (-0.3, 0.3):
            pts.append(((1 + s * math.cos(u / 2)) * math.cos(u), (1 + s * math.cos(u / 2)) * math.sin(u),
                        s * math.sin(u / 2)))
    for i in range(n):
        a, b = 2 * i, 2 * i + 1
        c, d = (2 * (i + 1), 2 * (i + 1) + 1) if i + 1 < n else (1, 0)  # the half twist
        tris += [(a, c, b), (b, c, d)]
    return np.array(pts), np.array(tris)


def unwelded_grid_sphere(columns=24, rows=12):
    """A unit sphere as a parametric source gives it unwelded: a grid of
    (columns + 1) x (rows + 1) points, its seam column repeated and each
    pole one point per column, so that welding it leaves the triangles at
    the poles with two corners on one point (degenerate, dropped)."""
    u, v = np.meshgrid(np.linspace(0.0, 2.0 * np.pi, columns + 1), np.linspace(0.0, np.pi, rows + 1), indexing="ij")
    points = np.stack([np.sin(v) * np.cos(u), np.sin(v) * np.sin(u), np.cos(v)], axis=-1).reshape(-1, 3)
    points[np.isclose(np.abs(points[:, 2]), 1.0), :2] = 0.0  # (the poles exactly on one point)
    ids = np.arange(len(points)).reshape(columns + 1, rows + 1)
    a, b, c, d = ids[:-1, :-1].ravel(), ids[1:, :-1].ravel(), ids[1:, 1:].ravel(), ids[:-1, 1:].ravel()
    return points, np.concatenate([np.stack([a, d, c], axis=1), np.stack([a, c, b], axis=1)])


def hostile_surfaces():
    """name -> vtkPolyData, each a way a real surface goes wrong."""
    from shapes import sphere, sphere_with_speck
    p, t = sphere(12)
    cases = {}
    cases["empty"] = vtkPolyData()
    only_points = polydata(p, np.zeros((0, 3)))
    cases["points-only"] = only_points
    cases["one-triangle"] = polydata([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]])
    for name, value in (("nan", np.nan), ("inf", np.inf)):
        q = p.copy()
        q[5, 1] = value
        cases[name + "-coordinate"] = polydata(q, t)
    cases["1e300-two-triangles"] = polydata([[0, 0, 0], [1e300, 0, 0], [0, 1e300, 0], [1e300, 1e300, 0]],
                                            [[0, 1, 2], [1, 3, 2]])
    cases["1e300-sphere"] = polydata(p * 1e300, t)
    cases["1e-300-sphere"] = polydata(p * 1e-300, t)
    cases["1e6-offset-sphere"] = polydata(p * 1e-3 + 1e6, t)
    cases["all-points-equal"] = polydata(np.zeros_like(p), t)
    line = np.zeros((10, 3))
    line[:, 0] = np.arange(10)
    cases["collinear"] = polydata(line, [[k, k + 1, k + 2] for k in range(8)])
    cases["non-manifold-fan"] = polydata([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1]],
                                         [[0, 1, 2], [1, 0, 3], [0, 1, 4]])
    cases["bowtie"] = polydata([[0, 0, 0], [1, 0, 0], [0, 1, 0], [-1, 0, 0], [0, -1, 0]],
                               [[0, 1, 2], [0, 3, 4]])
    cases["mobius"] = polydata(*_mobius())
    flipped = t.copy()
    flipped[::2] = flipped[::2, ::-1]
    cases["half-flipped-sphere"] = polydata(p, flipped)
    cases["tiny-far-component"] = polydata(*sphere_with_speck(12))
    soup = p[t].reshape(-1, 3)
    cases["unwelded-soup"] = polydata(soup, np.arange(len(soup)).reshape(-1, 3))
    cases["unwelded-grid"] = polydata(*unwelded_grid_sphere())
    cases["repeated-triangles"] = polydata(p, np.vstack([t, t[:20], t[20:30, ::-1]]))
    repeated = t.copy()
    repeated[3] = (repeated[3][0], repeated[3][0], repeated[3][1])
    cases["repeated-indices"] = polydata(p, repeated)
    rng = np.random.default_rng(7)
    cases["random-soup"] = polydata(rng.random((60, 3)), rng.integers(0, 60, (80, 3)))
    bad = t.copy()
    bad[0, 0] = len(p) + 10
    cases["index-out-of-range"] = polydata(p, bad)
    for mesh in cases.values():
        with_scalars(mesh)
    return cases


def image(dims, values=None, spacing=(1.0, 1.0, 1.0)):
    img = vtkImageData()
    img.SetDimensions(*dims)
    img.SetSpacing(*spacing)
    n = int(np.prod(dims))
    if values is None:
        values = np.sin(np.arange(n) * 0.37) + 0.1 * np.cos(np.arange(n) * 3.1)
    array = numpy_to_vtk(np.asarray(values, dtype=np.float64).ravel(), deep=True)
    array.SetName("Scalars")
    img.GetPointData().SetScalars(array)
    return img


def hostile_images():
    cases = {"image-0-samples": vtkImageData(), "image-1-sample": image((1, 1, 1)),
             "image-3-samples": image((3, 1, 1))}
    v = np.sin(np.arange(64 * 64) * 0.1)
    v[100] = np.nan
    cases["image-nan-value"] = image((64, 64, 1), v)
    v = np.sin(np.arange(64 * 64) * 0.1)
    v[100] = np.inf
    cases["image-inf-value"] = image((64, 64, 1), v)
    cases["image-constant"] = image((32, 32, 1), np.ones(32 * 32))
    cases["volume-2x2x2"] = image((2, 2, 2))
    cases["image-huge-values"] = image((32, 32, 1), 1e300 * np.sin(np.arange(32 * 32)))
    return cases


def grid(points, cells):
    """A vtkUnstructuredGrid of points and (cell type, ids) pairs."""
    out = vtkUnstructuredGrid()
    p = vtkPoints()
    p.SetDataTypeToDouble()
    p.SetData(numpy_to_vtk(np.ascontiguousarray(points, dtype=np.float64), deep=True))
    out.SetPoints(p)
    out.Allocate(len(cells))
    for kind, ids in cells:
        out.InsertNextCell(kind, len(ids), list(ids))
    n = len(points)
    array = numpy_to_vtk(np.sin(np.arange(n, dtype=np.float64)), deep=True)
    array.SetName("Scalars")
    out.GetPointData().SetScalars(array)
    return out


def hostile_grids():
    cube = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]],
                    dtype=float)
    points = np.vstack([cube, cube + [1, 0, 0]])
    mixed = [(VTK_HEXAHEDRON, range(8)), (VTK_TETRA, (8, 9, 10, 12)), (VTK_WEDGE, (1, 9, 10, 5, 13, 14)),
             (VTK_TRIANGLE, (0, 1, 2))]
    nan_points = points.copy()
    nan_points[3, 2] = np.nan
    cases = {"grid-empty": vtkUnstructuredGrid(), "grid-mixed-cells": grid(points, mixed),
             "grid-unknown-cell": grid(points, [(VTK_TETRA, (0, 1, 3, 4)), (VTK_POLYHEDRON, ())]),
             "grid-nan-point": grid(nan_points, [(VTK_TETRA, (0, 1, 3, 4)), (VTK_TETRA, (1, 2, 3, 6))]),
             "grid-degenerate-tets": grid(np.zeros((4, 3)), [(VTK_TETRA, (0, 1, 2, 3))])}
    return cases


# -------------------------------------------------------------- measurements

def edge_counts(triangles):
    """(unique edges as (a, b) with a < b, how many faces each has)."""
    if len(triangles) == 0:
        return np.zeros((0, 2), dtype=np.int64), np.zeros(0, dtype=np.int64)
    e = np.sort(np.vstack([triangles[:, [0, 1]], triangles[:, [1, 2]], triangles[:, [2, 0]]]), axis=1)
    unique, counts = np.unique(e, axis=0, return_counts=True)
    return unique, counts


def smallest_angles(points, triangles):
    """Each triangle's smallest angle, in degrees."""
    p = points[triangles]
    smallest = np.full(len(triangles), 180.0)
    for k in range(3):
        u, v = p[:, (k + 1) % 3] - p[:, k], p[:, (k + 2) % 3] - p[:, k]
        angle = np.degrees(np.arctan2(np.linalg.norm(np.cross(u, v), axis=1), np.einsum("ij,ij->i", u, v)))
        smallest = np.minimum(smallest, angle)
    return smallest


def components(n, edges):
    parent = np.arange(n)

    def find(x):
        while parent[x] != x:
            parent[x] = parent[parent[x]]
            x = parent[x]
        return x
    for a, b in edges:
        ra, rb = find(a), find(b)
        if ra != rb:
            parent[ra] = rb
    return np.array([find(x) for x in range(n)])


def topology(points, triangles):
    """Euler characteristic, components, boundary loops, and whether every
    edge has one or two faces and every vertex one fan (manifold) with
    consistent orientation (each directed edge at most once)."""
    used = np.unique(triangles) if len(triangles) else np.zeros(0, dtype=np.int64)
    edges, counts = edge_counts(triangles)
    v, e, f = len(used), len(edges), len(triangles)
    label = components(len(points), edges) if len(points) else np.zeros(0, dtype=np.int64)
    comps = len(np.unique(label[used])) if len(used) else 0
    boundary = edges[counts == 1]
    loops = len(np.unique(components(len(points), boundary)[np.unique(boundary)])) if len(boundary) else 0
    directed = np.vstack([triangles[:, [0, 1]], triangles[:, [1, 2]], triangles[:, [2, 0]]]) if f else \
        np.zeros((0, 2), dtype=np.int64)
    oriented = len(np.unique(directed, axis=0)) == len(directed)
    manifold_edges = bool(np.all(counts <= 2))
    return {"euler": v - e + f, "components": comps, "loops": loops,
            "manifold": manifold_edges and vertex_fans_are_disks(triangles, len(points)), "oriented": oriented}


def vertex_fans(triangles):
    """vertex -> its faces in fans (lists of face ids linked by the edges of
    two faces through the vertex), for every used vertex."""
    from collections import defaultdict
    around = defaultdict(list)
    for f, t in enumerate(triangles):
        for k in range(3):
            around[t[k]].append(f)
    fans = {}
    for vertex, faces in around.items():
        # Faces around `vertex` linked by the edges through it.
        link = defaultdict(list)
        for f in faces:
            for x in triangles[f]:
                if x != vertex:
                    link[x].append(f)
        parent = {f: f for f in faces}

        def find(x):
            while parent[x] != x:
                x = parent[x]
            return x
        for fs in link.values():
            if len(fs) == 2:  # (an edge of three or more faces joins none)
                parent[find(fs[1])] = find(fs[0])
        groups = defaultdict(list)
        for f in faces:
            groups[find(f)].append(f)
        fans[vertex] = sorted(groups.values())
    return fans


def vertex_fans_are_disks(triangles, n):
    """Every vertex's faces form one fan (no bowtie)."""
    return all(len(groups) == 1 for groups in vertex_fans(triangles).values())


def split_pinched(points, triangles):
    """(points, triangles) with every pinched vertex (several fans) split:
    one copy of its point per fan after the first (cut along edges of three
    or more faces)."""
    points, triangles = np.array(points, dtype=np.float64), np.array(triangles)
    copies = []
    for vertex, groups in vertex_fans(triangles).items():
        for fan in groups[1:]:
            copies.append(points[vertex])
            for f in fan:
                triangles[f][triangles[f] == vertex] = len(points) + len(copies) - 1
    return (np.vstack([points] + [np.array(copies)]) if copies else points), triangles


def diagonal(points):
    return float(np.linalg.norm(points.max(0) - points.min(0))) if len(points) else 0.0


def distances_to(mesh, query):
    """Distance of each query point (k x 3) to the surface `mesh`."""
    locator = vtkStaticCellLocator()
    locator.SetDataSet(mesh)
    locator.BuildLocator()
    closest = [0.0, 0.0, 0.0]
    cell, sub, dist2 = reference(0), reference(0), reference(0.0)
    out = np.empty(len(query))
    for i, q in enumerate(query):
        locator.FindClosestPoint(q, closest, cell, sub, dist2)
        out[i] = math.sqrt(float(dist2))
    return out


def surface_samples(points, triangles):
    """The vertices, edge midpoints and centroids of a mesh: where a
    deviation from it is measured (a two-sided Hausdorff estimate)."""
    t = triangles
    mids = (points[t[:, [0, 1, 2]]] + points[t[:, [1, 2, 0]]]) / 2
    return np.vstack([points[np.unique(t)], mids.reshape(-1, 3), points[t].mean(axis=1)])


def hausdorff(a_mesh, b_mesh):
    """(a to b, b to a) as fractions of a's bounding-box diagonal."""
    pa, ta = arrays_of(a_mesh)
    pb, tb = arrays_of(b_mesh)
    d = diagonal(pa)
    ab = distances_to(b_mesh, surface_samples(pa, ta)).max() if len(ta) else 0.0
    ba = distances_to(a_mesh, surface_samples(pb, tb)).max() if len(tb) else 0.0
    return ab / d, ba / d


def remesh_deviation(mesh, remesh):
    """(to the input, from the input) in the units of the points, as
    vtkSurfaceRemeshing's RemeshDeviation measures them: the largest
    distance to `mesh` (its polygons triangulated as the filters do) of the
    remesh's triangle centres and edge midpoints, and to `remesh` of the
    input's vertices, triangle centres and points along its edges (the
    midpoint of an edge at most two spacings long, else the points between
    parts of at most a spacing: that of equilateral triangles covering the
    input with the remesh's count); of those only where it could exceed the
    vertices' largest (a point's distance exceeds a vertex's by at most the
    way to it)."""
    p, t = arrays_of(remesh)
    mesh = polydata(*triangulated(mesh))
    edges = np.unique(np.sort(np.vstack([t[:, [0, 1]], t[:, [1, 2]], t[:, [2, 0]]]), axis=1), axis=0)
    to_input = distances_to(mesh, np.vstack([p[t].mean(axis=1), p[edges].mean(axis=1)])).max() if len(t) else 0.0
    pin, tin = arrays_of(mesh)
    used = np.unique(tin)
    at = np.zeros(len(pin))
    at[used] = distances_to(remesh, pin[used])
    most = at[used].max() if len(used) else 0.0
    corners = pin[tin]                                  # triangles x 3 x 3
    area = 0.5 * np.linalg.norm(np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]), axis=1).sum()
    spacing = math.sqrt(2.0 * area / (math.sqrt(3.0) * max(1, len(p))))
    centres = corners.mean(axis=1)
    bound = np.min(at[tin] + np.linalg.norm(centres[:, None, :] - corners, axis=2), axis=1)
    candidates = [centres[bound > most]]
    ends = np.unique(np.sort(np.vstack([tin[:, [0, 1]], tin[:, [1, 2]], tin[:, [2, 0]]]), axis=1), axis=0)
    length = np.linalg.norm(pin[ends[:, 1]] - pin[ends[:, 0]], axis=1)
    parts = np.where(length > 2.0 * spacing, np.ceil(length / spacing), 2).astype(np.int64)
    for m in np.unique(parts):
        e = ends[parts == m]
        along = np.arange(1, m) / m
        a, b = pin[e[:, 0]][:, None, :], pin[e[:, 1]][:, None, :]
        q = a + along[None, :, None] * (b - a)          # edges x (m - 1) x 3
        bound = np.minimum(at[e[:, 0]][:, None] + np.linalg.norm(q - a, axis=2),
                           at[e[:, 1]][:, None] + np.linalg.norm(q - b, axis=2))
        candidates.append(q[bound > most])
    candidates = np.vstack(candidates)
    from_input = max(most, distances_to(remesh, candidates).max() if len(candidates) else 0.0)
    return to_input, from_input


class Messages:
    """Collects the errors and warnings a VTK object reports (its
    ErrorEvent and WarningEvent) instead of printing them."""

    def __init__(self, *objects):
        self.errors, self.warnings = [], []
        for o in objects:
            o.AddObserver(vtkCommand.ErrorEvent, self._error)
            o.AddObserver(vtkCommand.WarningEvent, self._warning)

    @calldata_type(VTK_STRING)
    def _error(self, obj, event, data=None):
        self.errors.append(str(data) if data is not None else event)

    @calldata_type(VTK_STRING)
    def _warning(self, obj, event, data=None):
        self.warnings.append(str(data) if data is not None else event)


# The generated surfaces, kept in their own module (it reads the helpers above).
from shapes import *  # noqa: E402,F401,F403


def variants_of(name, data):
    """(name, polydata) of shapes no setting was tuned on, made of one real
    mesh: stretched 6 times along x, flattened to 0.15 of its height, and
    quadric-decimated to a tenth of its triangles (where that stays manifold
    and oriented): the benchmarks' --variants."""
    points, triangles = arrays_of(data)
    points = points - points.mean(axis=0)
    out = [(name + " stretched x6", polydata(points * [6.0, 1.0, 1.0], triangles)),
           (name + " flattened 0.15", polydata(points * [1.0, 1.0, 0.15], triangles))]
    p, t = decimated(polydata(points, triangles), 0.1)
    top = topology(p, t)
    if top["manifold"] and top["oriented"]:
        out.append((name + " decimated 0.1", polydata(p, t)))
    return out
