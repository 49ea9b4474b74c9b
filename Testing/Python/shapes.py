"""Generated surfaces for the tests and benchmarks: analytic shapes and the
hard shapes that break remeshers (thin spikes and limbs, specks, slivers,
high genus, huge and tiny coordinates), with hard_shapes() naming them.
`inputs` re-exports all of them (callers write inputs.sphere, ...)."""
import math
import os

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk
from vtkmodules.vtkCommonDataModel import vtkImageData

from inputs import DATA, SHARED_MESHES, arrays_of, read_off, topology


def sphere(n=24, radius=1.0, center=(0.0, 0.0, 0.0)):
    """A closed UV sphere (poles shared): 2 + (n - 1) * 2n points."""
    rings, sectors = n, 2 * n
    pts = [(0.0, 0.0, radius)]
    for i in range(1, rings):
        t = math.pi * i / rings
        for j in range(sectors):
            f = 2.0 * math.pi * j / sectors
            pts.append((radius * math.sin(t) * math.cos(f), radius * math.sin(t) * math.sin(f), radius * math.cos(t)))
    pts.append((0.0, 0.0, -radius))
    south = len(pts) - 1
    tris = []
    ring = lambda i, j: 1 + (i - 1) * sectors + (j % sectors)  # noqa: E731
    for j in range(sectors):
        tris.append((0, ring(1, j), ring(1, j + 1)))
        tris.append((south, ring(rings - 1, j + 1), ring(rings - 1, j)))
    for i in range(1, rings - 1):
        for j in range(sectors):
            a, b, c, d = ring(i, j), ring(i, j + 1), ring(i + 1, j), ring(i + 1, j + 1)
            tris += [(a, c, b), (b, c, d)]
    return np.array(pts) + np.asarray(center), np.array(tris)


def torus(n=32, m=16, major=1.0, minor=0.3, center=(0.0, 0.0, 0.0)):
    pts, tris = [], []
    for i in range(n):
        u = 2.0 * math.pi * i / n
        for j in range(m):
            v = 2.0 * math.pi * j / m
            pts.append(((major + minor * math.cos(v)) * math.cos(u), (major + minor * math.cos(v)) * math.sin(u),
                        minor * math.sin(v)))
    at = lambda i, j: (i % n) * m + (j % m)  # noqa: E731
    for i in range(n):
        for j in range(m):
            tris += [(at(i, j), at(i + 1, j), at(i + 1, j + 1)), (at(i, j), at(i + 1, j + 1), at(i, j + 1))]
    return np.array(pts) + np.asarray(center), np.array(tris)


def merge(*parts):
    points, triangles, offset = [], [], 0
    for p, t in parts:
        points.append(np.asarray(p, dtype=np.float64))
        triangles.append(np.asarray(t, dtype=np.int64) + offset)
        offset += len(p)
    return np.vstack(points), np.vstack(triangles)


def displaced_sphere(n, radius_of):
    """A sphere whose radius in direction d is radius_of(d) (d: unit rows):
    spikes, limbs and necks as star-shaped surfaces, so always manifold."""
    p, t = sphere(n)
    d = p / np.linalg.norm(p, axis=1)[:, None]
    return d * radius_of(d)[:, None], t


def spiky_sphere(n=48, spikes=6, length=1.5, width=0.08):
    """A sphere with long thin spikes (tips a few triangles wide)."""
    axes = np.array([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1], [1, 1, 1], [-1, 1, -1]],
                    dtype=float)[:spikes]
    axes /= np.linalg.norm(axes, axis=1)[:, None]

    def radius(d):
        r = np.ones(len(d))
        for a in axes:
            angle = np.arccos(np.clip(d @ a, -1.0, 1.0))
            r += length * np.exp(-(angle / width) ** 2)
        return r
    return displaced_sphere(n, radius)


def comb(fingers=5, length=2.0, n=40):
    """A ball with thin fingers along one side (a hand, a comb)."""
    axes = []
    for k in range(fingers):
        f = -0.6 + 1.2 * k / max(1, fingers - 1)
        axes.append((math.sin(f), math.cos(f), 0.0))
    axes = np.array(axes)

    def radius(d):
        r = np.ones(len(d))
        for a in axes:
            angle = np.arccos(np.clip(d @ a, -1.0, 1.0))
            r += length * np.exp(-(angle / 0.07) ** 4)
        return r
    return displaced_sphere(n, radius)


def dumbbell(n=40, centre=1.5, neck=0.08):
    """Two unit balls joined by a thin tube: a surface of revolution about
    x (one surface, genus 0)."""
    p, t = sphere(n)
    x = p[:, 2]  # the sphere's axis becomes the dumbbell's
    s = x * (centre + 1.0)
    ball = np.sqrt(np.maximum(0.0, 1.0 - (np.abs(s) - centre) ** 2))
    rho = np.where(np.abs(s) >= centre, ball, np.maximum(neck, ball))
    ring = np.sqrt(np.maximum(1e-300, 1.0 - x * x))
    scale = np.where(ring > 0, rho / ring, 0.0)
    return np.stack([s, p[:, 0] * scale, p[:, 1] * scale], axis=1), t


def torus_with_thin_handle(n=48):
    """A torus whose tube is thin along a quarter of the ring (genus 1)."""
    p, t = torus(n=n, m=16, major=1.0, minor=0.3)
    u = np.arctan2(p[:, 1], p[:, 0])
    ring = np.stack([np.cos(u), np.sin(u), np.zeros_like(u)], axis=1)
    offset = p - ring
    thin = np.where(np.abs(u) < math.pi / 4, 0.15, 1.0)
    return ring + offset * thin[:, None], t


def punched(points, triangles, holes=60, seed=0, radii=(1.5, 4.0)):
    """A scan with small holes punched into it, as scanners leave them: the
    triangles within a random 1.5-4 mean edge lengths of `holes` random
    vertices removed, the largest piece kept (jagged rims, holes smaller
    than most remeshes' spacing); the first seed from `seed` on whose holes
    leave a manifold surface."""
    points, triangles = np.asarray(points, float), np.asarray(triangles)
    edge = np.linalg.norm(points[triangles[:, 0]] - points[triangles[:, 1]], axis=1).mean()
    centres = points[triangles].mean(axis=1)
    for attempt in range(seed, seed + 20):
        rng = np.random.default_rng(attempt)
        keep = np.ones(len(triangles), dtype=bool)
        for c in rng.choice(len(points), holes, replace=False):
            keep &= np.linalg.norm(centres - points[c], axis=1) > rng.uniform(*radii) * edge
        p, t = largest_piece(points, triangles[keep])
        if topology(p, t)["manifold"]:
            return p, t
    raise RuntimeError("no punched surface is manifold")


def largest_piece(points, triangles):
    """The largest edge-connected piece of a triangle list, compacted."""
    parent = np.arange(len(points))

    def root(a):
        while parent[a] != a:
            parent[a] = parent[parent[a]]
            a = parent[a]
        return a
    for a, b, c in triangles:
        for u, v in ((a, b), (b, c)):
            ru, rv = root(u), root(v)
            if ru != rv:
                parent[ru] = rv
    roots = np.array([root(a) for a in triangles[:, 0]])
    values, counts = np.unique(roots, return_counts=True)
    kept = triangles[roots == values[np.argmax(counts)]]
    used = np.unique(kept)
    index = np.full(len(points), -1)
    index[used] = np.arange(len(used))
    return points[used], index[kept]


def _segment(x, a, b, ra, rb=None):
    """Signed distance to the capsule from a to b, of radius ra at a and rb at b."""
    rb = ra if rb is None else rb
    a, b = np.asarray(a, float), np.asarray(b, float)
    s = np.clip((x - a) @ (b - a) / ((b - a) @ (b - a)), 0.0, 1.0)
    return np.linalg.norm(x - (a + s[..., None] * (b - a)), axis=-1) - (ra + (rb - ra) * s)


def _ellipsoid(x, centre, radii):
    q = (x - np.asarray(centre, float)) / np.asarray(radii, float)
    return (np.linalg.norm(q, axis=-1) - 1) * min(radii)


def _blend(a, b, k=0.05):
    """A smooth minimum of two distances (a union with a fillet of about k)."""
    h = np.clip(0.5 + 0.5 * (b - a) / k, 0.0, 1.0)
    return b * (1 - h) + a * h - k * h * (1 - h)


def implicit_surface(distance, n=160, keep=None, extent=1.5):
    """The marching-cubes surface (its largest piece) of a signed distance
    function on an n^3 grid over [-extent, extent]^3, as a scan gives it,
    quadric-decimated to `keep` of its triangles where set (which leaves
    long slivers): (points, triangles)."""
    from vtkmodules.vtkFiltersCore import vtkFlyingEdges3D, vtkPolyDataConnectivityFilter, vtkQuadricDecimation

    g = np.linspace(-extent, extent, n)
    d = np.concatenate([distance(np.stack(np.meshgrid(g[i:i + 16], g, g, indexing="ij"), axis=-1))
                        for i in range(0, n, 16)])
    image = vtkImageData()
    image.SetDimensions(n, n, n)
    image.SetOrigin(-extent, -extent, -extent)
    image.SetSpacing(*([2.0 * extent / (n - 1)] * 3))
    image.GetPointData().SetScalars(numpy_to_vtk(d.transpose(2, 1, 0).ravel().copy(), deep=True))
    surface = vtkFlyingEdges3D()
    surface.SetInputData(image)
    surface.SetValue(0, 0.0)
    last = vtkPolyDataConnectivityFilter()
    last.SetInputConnection(surface.GetOutputPort())
    last.SetExtractionModeToLargestRegion()
    if keep:
        decimate = vtkQuadricDecimation()
        decimate.SetInputConnection(last.GetOutputPort())
        decimate.SetTargetReduction(1.0 - keep)
        last = decimate
    last.Update()
    p, t = arrays_of(last.GetOutput())
    used = np.unique(t)
    remap = np.zeros(len(p), dtype=np.int64)
    remap[used] = np.arange(len(used))
    return p[used], remap[t]


def decimated_bone(n=160, keep=0.1):
    """A genus-2 bone (a shaft between two flat ends, each with a hole
    through it) as a decimated scan gives it (implicit_surface), which
    leaves long slivers along the shaft."""
    def distance(x):
        d = _segment(x, (-0.8, 0, 0), (0.8, 0, 0), 0.08)
        for end in (-0.85, 0.85):
            d = _blend(d, _ellipsoid(x, (end, 0, 0), (0.2, 0.25, 0.08)), 0.05)
            d = np.maximum(d, -_segment(x, (end, 0, -0.3), (end, 0, 0.3), 0.07))
        return d
    return implicit_surface(distance, n, keep)


def quadruped(n=160, keep=0.2):
    """An animal as a decimated scan gives it: a body on four thin legs, a
    long neck, a head with two horns that taper to a point and a thin tail
    (implicit_surface)."""
    def distance(x):
        d = _ellipsoid(x, (0, 0, 0), (0.6, 0.25, 0.25))
        for sx in (-0.45, 0.45):
            for sy in (-0.15, 0.15):
                d = _blend(d, _segment(x, (sx, sy, -0.1), (sx, sy, -0.9), 0.05, 0.035), 0.03)
        d = _blend(d, _segment(x, (0.5, 0, 0.1), (0.8, 0, 0.6), 0.08, 0.06), 0.03)
        d = _blend(d, _ellipsoid(x, (0.9, 0, 0.65), (0.18, 0.09, 0.09)), 0.03)
        for sy in (-0.06, 0.06):
            d = _blend(d, _segment(x, (0.85, sy, 0.72), (0.75, 3 * sy, 1.05), 0.03, 0.006), 0.01)
        return _blend(d, _segment(x, (-0.55, 0, 0.05), (-1.1, 0, -0.3), 0.03, 0.01), 0.02)
    return implicit_surface(distance, n, keep)


def turbine_disk(n=160, blades=12):
    """A disk with a bore and thin twisted blades (torus topology), its
    marching-cubes surface: the blades' rims are about a spacing thick at
    10,000 vertices (implicit_surface)."""
    def distance(x):
        r = np.linalg.norm(x[..., :2], axis=-1)
        d = np.maximum(np.maximum(r - 0.5, np.abs(x[..., 2]) - 0.08), 0.12 - r)
        for k in range(blades):
            c, s = np.cos(2 * np.pi * k / blades), np.sin(2 * np.pi * k / blades)
            u, v, w = x[..., 0] * c + x[..., 1] * s, x[..., 1] * c - x[..., 0] * s, x[..., 2]
            twisted = v - 0.6 * (u - 0.5) * w
            d = np.minimum(d, np.maximum(np.maximum(np.abs(u - 0.85) - 0.37, np.abs(twisted) - 0.015),
                                         np.abs(w) - 0.07))
        return d
    return implicit_surface(distance, n)


def octopus(n=160):
    """A head with eight curling, tapering tentacles blended on (marching
    cubes on an n^3 grid: an isosurface's irregular triangles)."""
    def distance(x):
        d = _ellipsoid(x, (0, 0, 0.5), (0.55, 0.55, 0.7))
        for k in range(8):
            a = 2 * math.pi * k / 8
            centres = [np.array(((0.3 + s) * math.cos(a + 1.2 * s * s), (0.3 + s) * math.sin(a + 1.2 * s * s),
                                 0.1 - 0.6 * s + 0.5 * s ** 3)) for s in np.linspace(0, 1, 9)]
            for j in range(8):
                d = _blend(d, _segment(x, centres[j], centres[j + 1], 0.16 * (1 - j / 8) + 0.02,
                                       0.16 * (1 - (j + 1) / 8) + 0.02), 0.03)
        return d
    return implicit_surface(distance, n=n, extent=1.6)


def hairy_sphere(n=64, hairs=100, length=0.5, seed=1):
    """A UV sphere with `hairs` of its vertices (the nearest to random
    directions) pulled out along them to 1 + `length`: needles one input
    vertex wide, their sides slivers."""
    rng = np.random.default_rng(seed)
    p, t = sphere(n)
    pulled = p.copy()
    directions = rng.normal(size=(hairs, 3))
    for d in directions / np.linalg.norm(directions, axis=1)[:, None]:
        pulled[np.argmax(p @ d)] = (1.0 + length) * d
    return pulled, t


def sphere_with_speck(n=24, speck=1e-4, distance=5.0):
    """A unit sphere and a far-away speck (a sphere of radius `speck`)."""
    return merge(sphere(n), sphere(4, radius=speck, center=(distance, 0.0, 0.0)))


def sphere_with_specks(count=40, seed=3):
    """A unit sphere amid `count` specks (spheres of radius 1e-4 to 3e-2,
    log-uniform, 1.2 to 3 from its centre), as a scan's debris."""
    rng = np.random.default_rng(seed)
    parts = [sphere(24)]
    for _ in range(count):
        c = rng.normal(size=3)
        c *= rng.uniform(1.2, 3.0) / np.linalg.norm(c)
        parts.append(sphere(4, radius=10 ** rng.uniform(-4, -1.5), center=tuple(c)))
    return merge(*parts)


def thin_plate(thickness=0.002, n=20):
    """A closed box 2 x 2 x thickness: thinner than any spacing (its faces
    made consistent by orient_consistently)."""
    g = np.linspace(-1.0, 1.0, n + 1)
    x, y = np.meshgrid(g, g, indexing="ij")
    top = np.stack([x.ravel(), y.ravel(), np.full(x.size, thickness / 2)], axis=1)
    bottom = top * [1, 1, -1]
    at = lambda i, j: i * (n + 1) + j  # noqa: E731
    tris = []
    for i in range(n):
        for j in range(n):
            a, b, c, d = at(i, j), at(i + 1, j), at(i, j + 1), at(i + 1, j + 1)
            tris += [(a, b, d), (a, d, c)]
    tris += [tuple(np.array(f) + (n + 1) ** 2) for f in tris]
    border = [(i, 0) for i in range(n)] + [(n, j) for j in range(n)] + \
        [(i, n) for i in range(n, 0, -1)] + [(0, j) for j in range(n, 0, -1)]
    for k in range(len(border)):
        ta, tb = at(*border[k]), at(*border[(k + 1) % len(border)])
        ba, bb = ta + (n + 1) ** 2, tb + (n + 1) ** 2
        tris += [(ta, ba, bb), (ta, bb, tb)]
    return np.vstack([top, bottom]), np.array(tris)


def flattened(points, triangles, share=0.001, seed=0):
    """A copy of the points with `share` of the triangles flattened: one
    corner moved onto the middle of its opposite edge (a triangle of no area,
    its other triangles folded beside it), no point moved twice."""
    rng = np.random.default_rng(seed)
    p, t = np.array(points, float), np.asarray(triangles)
    used = np.zeros(len(p), dtype=bool)
    for k in rng.choice(len(t), int(share * len(t)), replace=False):
        a, b, c = t[k]
        if not used[[a, b, c]].any():
            used[[a, b, c]] = True
            p[c] = 0.5 * (p[a] + p[b])
    return p


def collapsed(points, triangles, share=0.01, seed=7):
    """A copy of the points with the first edges of `share` of the triangles
    collapsed in place (one end moved onto the other: coincident points
    inside the surface and triangles of no area, as decimations and marching
    cubes at grid points leave them), no point moved twice."""
    rng = np.random.default_rng(seed)
    p, t = np.array(points, float), np.asarray(triangles)
    used = np.zeros(len(p), dtype=bool)
    for k in rng.choice(len(t), int(share * len(t)), replace=False):
        a, c = t[k][0], t[k][1]
        if not used[[a, c]].any():
            used[[a, c]] = True
            p[c] = p[a]
    return p


def decimated(mesh, keep):
    """(points, triangles) of `mesh` quadric-decimated to `keep` of its triangles."""
    from vtkmodules.vtkFiltersCore import vtkQuadricDecimation

    decimate = vtkQuadricDecimation()
    decimate.SetInputData(mesh)
    decimate.SetTargetReduction(1.0 - keep)
    decimate.Update()
    return arrays_of(decimate.GetOutput())


def decimated_cad(keep=0.1):
    """fandisk_large (the shared corpus) quadric-decimated to `keep` of its
    triangles: a CAD part whose creases run jagged and, in places, a
    fraction of the spacing apart (None where the corpus is not at hand)."""
    path = os.path.join(SHARED_MESHES, "fandisk_large.off")
    return decimated(read_off(path), keep) if os.path.exists(path) else None


def fan_double_cone(n=2000):
    """Two cones on one rim of n points, each a single fan of n slivers
    around its apex (a CAD part's cone tip or cylinder cap as exported)."""
    a = np.linspace(0.0, 2.0 * np.pi, n, endpoint=False)
    rim = np.stack([np.cos(a), np.sin(a), np.zeros(n)], axis=1)
    points = np.vstack([rim, [[0.0, 0.0, 1.0], [0.0, 0.0, -1.0]]])
    i = np.arange(n)
    up = np.stack([i, (i + 1) % n, np.full(n, n)], axis=1)
    down = np.stack([(i + 1) % n, i, np.full(n, n + 1)], axis=1)
    return points, np.vstack([up, down])


def needle(length=2.8, radius=0.02, around=12, along=400):
    """A closed tube 140 radii long (a wire, a probe): narrower than the
    spacing at 2,000 vertices, each end a flat fan."""
    x = np.repeat(np.linspace(-length / 2, length / 2, along + 1), around)
    a = np.tile(2.0 * np.pi * np.arange(around) / around, along + 1)
    points = np.vstack([np.stack([x, radius * np.cos(a), radius * np.sin(a)], axis=1),
                        [[-length / 2, 0.0, 0.0], [length / 2, 0.0, 0.0]]])
    j, i = np.meshgrid(np.arange(along), np.arange(around), indexing="ij")
    a, b = j * around + i, j * around + (i + 1) % around
    side = np.concatenate([np.stack([a, b, b + around], -1), np.stack([a, b + around, a + around], -1)]).reshape(-1, 3)
    i = np.arange(around)
    ends = (len(points) - 2, len(points) - 1)
    caps = np.vstack([np.stack([np.full(around, ends[0]), (i + 1) % around, i], axis=1),
                      np.stack([np.full(around, ends[1]), along * around + i, along * around + (i + 1) % around],
                               axis=1)])
    return points, np.vstack([side, caps])


def knife_edge_washer(n=120, m=24, width=0.3, thickness=0.01):
    """A torus whose tube is an ellipse 30 times wider than thick: a washer
    whose rims turn through about 150 degrees within one edge (a blade's or
    a fin's knife edge, where SplitAtFeatures is not set)."""
    u = np.repeat(2.0 * np.pi * np.arange(n) / n, m)
    v = np.tile(2.0 * np.pi * np.arange(m) / m, n)
    r = 1.0 + width * np.cos(v)
    points = np.stack([r * np.cos(u), r * np.sin(u), thickness * np.sin(v)], axis=1)
    i, j = np.meshgrid(np.arange(n), np.arange(m), indexing="ij")
    a, b = i * m + j, i * m + (j + 1) % m
    c, d = ((i + 1) % n) * m + j, ((i + 1) % n) * m + (j + 1) % m
    return points, np.concatenate([np.stack([a, c, d], -1), np.stack([a, d, b], -1)]).reshape(-1, 3)


def slab_with_holes(n=120):
    """A slab 2.6 x 1.6 x 0.24 with six round holes through it (genus 6) as
    a scan gives it (implicit_surface)."""
    centres = [(x, y) for y in (-0.4, 0.4) for x in (-0.9, 0.0, 0.9)]

    def distance(x):
        d = np.maximum(np.maximum(np.abs(x[..., 0]) - 1.3, np.abs(x[..., 1]) - 0.8), np.abs(x[..., 2]) - 0.12)
        for cx, cy in centres:
            d = np.maximum(d, 0.22 - np.hypot(x[..., 0] - cx, x[..., 1] - cy))
        return d
    return implicit_surface(distance, n=n)


def nested_spheres():
    """A sphere with one of half its radius inside, facing inwards (a hollow
    ball's two walls): one component within another."""
    p, t = sphere(24)
    q, s = sphere(16)
    return np.vstack([p, 0.5 * q]), np.vstack([t, s[:, ::-1] + len(p)])


def orient_consistently(points, triangles):
    """Flips faces so that the plate's faces agree (by breadth-first walk)."""
    from collections import defaultdict, deque
    edges = defaultdict(list)
    for f, (a, b, c) in enumerate(triangles):
        for u, v in ((a, b), (b, c), (c, a)):
            edges[(min(u, v), max(u, v))].append(f)
    tris = [list(t) for t in triangles]
    seen = [False] * len(tris)
    for start in range(len(tris)):
        if seen[start]:
            continue
        seen[start] = True
        queue = deque([start])
        while queue:
            f = queue.popleft()
            a, b, c = tris[f]
            for u, v in ((a, b), (b, c), (c, a)):
                for g in edges[(min(u, v), max(u, v))]:
                    if g == f or seen[g]:
                        continue
                    x, y, z = tris[g]
                    if (u, v) in ((x, y), (y, z), (z, x)):  # same direction: flip g
                        tris[g] = [x, z, y]
                    seen[g] = True
                    queue.append(g)
    return points, np.array(tris)


def swept(nu, nv, section):
    """A tube swept along z: section(t, v) -> (x, y, z) arrays for t in
    [0, 2 pi) around and v in [0, 1] along; open at both ends, its quads'
    diagonals alternating."""
    t, v = np.meshgrid(2.0 * np.pi * np.arange(nu) / nu, np.linspace(0.0, 1.0, nv), indexing="ij")
    points = np.stack(section(t, v), axis=-1).reshape(-1, 3)
    i, j = np.meshgrid(np.arange(nu), np.arange(nv - 1), indexing="ij")
    a, b = i * nv + j, ((i + 1) % nu) * nv + j
    c, d = b + 1, a + 1
    even = ((i + j) % 2 == 0)[..., None]
    first = np.where(even, np.stack([a, b, d], -1), np.stack([a, b, c], -1)).reshape(-1, 3)
    second = np.where(even, np.stack([b, c, d], -1), np.stack([a, c, d], -1)).reshape(-1, 3)
    return points, np.concatenate([first, second])


def ribbon(length=10.0, width=0.01, turns=2, along=800, across=4):
    """An open strip `length` long and `width` wide along x, twisted by
    `turns` full turns about its axis (its charts' maps: long thin boxes)."""
    x, y = np.meshgrid(np.linspace(0.0, length, along), np.linspace(-width / 2, width / 2, across), indexing="ij")
    turn = 2.0 * np.pi * turns * x / length
    points = np.stack([x, y * np.cos(turn), y * np.sin(turn)], axis=-1).reshape(-1, 3)
    i, j = np.meshgrid(np.arange(along - 1), np.arange(across - 1), indexing="ij")
    a = (i * across + j).ravel()
    b = a + across
    return points, np.concatenate([np.stack([a, b, a + 1], -1), np.stack([a + 1, b, b + 1], -1)])


def knotted_tube(radius=0.03, along=600, around=10):
    """A closed tube of the radius given along a trefoil knot (its length
    about 17, 90 times its girth): a torus far thinner than it is long."""
    u = 2.0 * np.pi * np.arange(along) / along
    centre = np.stack([np.sin(u) + 2 * np.sin(2 * u), np.cos(u) - 2 * np.cos(2 * u), -np.sin(3 * u)], axis=-1)
    tangent = np.stack([np.cos(u) + 4 * np.cos(2 * u), -np.sin(u) + 4 * np.sin(2 * u), -3 * np.cos(3 * u)], axis=-1)
    tangent /= np.linalg.norm(tangent, axis=1)[:, None]
    normal = np.cross(tangent, [0.0, 0.0, 1.0])
    normal /= np.linalg.norm(normal, axis=1)[:, None]
    binormal = np.cross(tangent, normal)
    v = 2.0 * np.pi * np.arange(around) / around
    points = (centre[:, None, :] + radius * (np.cos(v)[None, :, None] * normal[:, None, :] +
                                             np.sin(v)[None, :, None] * binormal[:, None, :])).reshape(-1, 3)
    i, j = np.meshgrid(np.arange(along), np.arange(around), indexing="ij")
    a = (i * around + j).ravel()
    b = (((i + 1) % along) * around + j).ravel()
    c = (i * around + (j + 1) % around).ravel()
    d = (((i + 1) % along) * around + (j + 1) % around).ravel()
    return points, np.concatenate([np.stack([a, b, c], -1), np.stack([c, b, d], -1)])


def lattice(cells=2, bar=0.1, n=80):
    """The surface of a cubic lattice of round bars (cells^3 cells, the bars
    along every edge of them, of radius `bar`, in [-1, 1]^3), as marching
    cubes on an n^3 grid gives it: of genus 3 cells (cells + 1)^2 - (cells +
    1)^3 + 1 (the bars' graph's cycles; 2 cells: 28)."""
    g = np.linspace(-1.0, 1.0, cells + 1)

    def distance(x):
        d = None
        for axis in range(3):
            o = [k for k in range(3) if k != axis]
            for i in g:
                for j in g:
                    a, b = np.zeros(3), np.zeros(3)
                    a[o[0]] = b[o[0]] = i
                    a[o[1]] = b[o[1]] = j
                    a[axis], b[axis] = -1.0, 1.0
                    s = _segment(x, a, b, bar)
                    d = s if d is None else np.minimum(d, s)
        return d
    return implicit_surface(distance, n=n, extent=1.2)


def tube(radius=1.0, length=4.0, nu=256, nv=200):
    """An open cylinder of revolution about z (principal curvatures 1 / radius and 0)."""
    return swept(nu, nv, lambda t, v: (radius * np.cos(t), radius * np.sin(t), length * (v - 0.5)))


def graded_plane(n=60):
    """An open bumpy square (z = 0.05 sin 6x sin 6y) whose grid is graded as
    the cube of its index: triangles a hundredfold smaller towards one
    corner, where noise of 1% of the diagonal is hundreds of their edges."""
    s = np.linspace(0.0, 1.0, n) ** 3
    x, y = np.meshgrid(s, s, indexing="ij")
    points = np.c_[x.ravel(), y.ravel(), (0.05 * np.sin(6 * x) * np.sin(6 * y)).ravel()]
    a = (np.arange(n - 1)[:, None] * n + np.arange(n - 1)[None, :]).ravel()
    triangles = np.r_[np.c_[a, a + n, a + n + 1], np.c_[a, a + n + 1, a + 1]]
    return points, triangles


def blade(nu=240, nv=500, span=5.0, chord=1.0, thickness=0.2, camber=0.15, twist=0.6):
    """A turbine-blade-like surface: a cambered, rounded section of the
    chord and thickness given, swept along z over the span and twisted by
    `twist` radians; open at both ends (flat sides, a tight leading and
    trailing edge: curvature ratios far above 3 almost everywhere)."""
    def section(t, v):
        x = 0.5 * chord * np.cos(t)
        y = thickness * np.sin(t) * (1.0 + 0.3 * np.cos(t)) + camber * np.cos(t) ** 2
        turn = twist * v
        return x * np.cos(turn) - y * np.sin(turn), x * np.sin(turn) + y * np.cos(turn), span * v
    return swept(nu, nv, section)


def isosurface(largest=False, level=0.4):
    """The flying-edges contour of a real MRI volume (Testing/Data) at
    `level` of its range, cleaned (as ParaView's Contour and Clean give it):
    112 components, most of them specks of a few voxels, 48 boundary loops
    where it meets the volume's sides; `largest`: its largest component (681
    points, 5 loops), where the level passes grid points and clusters of
    vertices 0.005 apart lie around them."""
    from vtkmodules.vtkFiltersCore import vtkCleanPolyData, vtkFlyingEdges3D, vtkPolyDataConnectivityFilter
    from vtkmodules.vtkIOXML import vtkXMLImageDataReader
    reader = vtkXMLImageDataReader()
    reader.SetFileName(os.path.join(DATA, "mri_s0_10slices.vti"))
    reader.Update()
    low, high = reader.GetOutput().GetPointData().GetArray("MRI").GetRange()
    contour = vtkFlyingEdges3D()
    contour.SetInputConnection(reader.GetOutputPort())
    contour.SetInputArrayToProcess(0, 0, 0, 0, "MRI")
    contour.SetValue(0, low + level * (high - low))
    contour.ComputeNormalsOff()
    last = contour
    if largest:
        last = vtkPolyDataConnectivityFilter()
        last.SetInputConnection(contour.GetOutputPort())
        last.SetExtractionModeToLargestRegion()
    clean = vtkCleanPolyData()
    clean.SetInputConnection(last.GetOutputPort())
    clean.Update()
    return clean.GetOutput()


def parametric_surface(name, resolution=80):
    """One of VTK's parametric surfaces (ParaView's Sources > Parametric
    Surfaces: "BohemianDome", "Kuen", ...) at `resolution` x `resolution`,
    cleaned and triangulated."""
    import vtkmodules.vtkCommonComputationalGeometry as geometry
    from vtkmodules.vtkFiltersCore import vtkCleanPolyData, vtkTriangleFilter
    from vtkmodules.vtkFiltersSources import vtkParametricFunctionSource
    source = vtkParametricFunctionSource()
    source.SetParametricFunction(getattr(geometry, "vtkParametric" + name)())
    source.SetUResolution(resolution)
    source.SetVResolution(resolution)
    clean = vtkCleanPolyData()
    clean.SetInputConnection(source.GetOutputPort())
    triangles = vtkTriangleFilter()
    triangles.SetInputConnection(clean.GetOutputPort())
    triangles.Update()
    return triangles.GetOutput()


def hard_shapes():
    """name -> (points, triangles): the shapes made to break a remesher."""
    shapes = {
        "spiky-sphere": spiky_sphere(),
        "comb": comb(),
        "dumbbell": dumbbell(),
        "torus-thin-handle": torus_with_thin_handle(),
        "sphere-with-speck": sphere_with_speck(),
        "sphere-with-specks": sphere_with_specks(),
        "thin-plate": orient_consistently(*thin_plate()),
        "decimated-bone": decimated_bone(),
        "quadruped": quadruped(),
        "turbine-disk": turbine_disk(),
        "fan-double-cone": fan_double_cone(),
        "isosurface": arrays_of(isosurface(largest=True)),
        "needle": needle(),
        "knife-edge-washer": knife_edge_washer(),
        "slab-six-holes": slab_with_holes(),
        "nested-spheres": nested_spheres(),
    }
    cad = decimated_cad()
    if cad is not None:
        shapes["decimated-cad"] = cad
    p, t = sphere(24)
    shapes["huge-sphere"] = (p * 1e12 + 3e12, t)
    shapes["tiny-sphere"] = (p * 1e-12 + 1e-11, t)
    # (a scan in a map's coordinates: metres of it, millions from the origin)
    shapes["far-sphere"] = (p + np.array([5e5, 5e6, 100.0]), t)
    # (a decimation's leftovers: coincident points inside the surface)
    bunny = arrays_of(read_off(os.path.join(DATA, "bunny00.off")))
    shapes["collapsed-bunny"] = (collapsed(*bunny), bunny[1])
    return shapes


# ------------------------------------------------------------ hostile inputs
