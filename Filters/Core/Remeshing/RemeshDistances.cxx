// Beltrami core: a remesh's distances from its input, both ways
// (RemeshDistances): measured at the input's vertices, at its edges'
// midpoints and triangles' centres where those could be farther, and at the
// remesh's triangles' centres and edges' midpoints (MeasureDistances), and
// measured again after a fidelity round moved part of it (UpdateDistances).
#include "Remeshing/RemeshFidelity.h"

#include "Mesh/MeshMeasures.h"
#include "Support/Parallel.h"

#include <algorithm>
#include <cmath>

namespace beltrami
{

namespace
{

/// The distances of the input vertices to the remesh (its triangles in
/// `grid`) into `d` (RemeshDistances), where `redo` holds for them.
template <typename Redo>
void InputVerticesTo(const MeshTopology& topology, const double* points, const TriangleGrid& grid, Redo&& redo,
  RemeshDistances& d, int numThreads)
{
  ParallelFor(topology.NumberOfVertices(), numThreads, [&](std::int64_t begin, std::int64_t end) {
    for (Index v = static_cast<Index>(begin); v < end; ++v)
    {
      const Vec3 p = Point(points, v);
      if (redo(v) && topology.Valence(v) > 0 && p.allFinite())
      {
        d.Nearest[v] = grid.Nearest(p, d.FromInput[v]); // (infinite where the remesh has no triangle)
      }
      else if (redo(v))
      {
        d.Nearest[v] = -1;
        d.FromInput[v] = 0.0;
      }
    }
  });
}

/// The distance from `p` to the surface in `grid`, known to be at most
/// `bound` (a triangle that far): a search that stops there.
double DistanceWithin(const TriangleGrid& grid, const Vec3& p, double bound)
{
  double distance = 0.0;
  return grid.Nearest(p, distance, bound * (1.0 + 1e-12) + 1e-300) >= 0 ? std::min(distance, bound) : bound;
}

/// The distances to the input of the remesh's triangle centres and edge
/// midpoints into `d` (RemeshDistances::FromTriangles), where `redo` holds
/// for the triangle.  A midpoint is at most as far as the input triangle
/// nearest to the centre: the search for it stops there.
template <typename Redo>
void TrianglesTo(const RemeshResult& remesh, const TriangleGrid& toInput, Redo&& redo, RemeshDistances& d,
  int numThreads)
{
  const double* x = remesh.Points.data();
  ParallelFor(static_cast<std::int64_t>(d.FromTriangles.size()), numThreads, [&](std::int64_t begin, std::int64_t end) {
    for (std::int64_t t = begin; t < end; ++t)
    {
      if (!redo(t))
      {
        continue;
      }
      const Index* c = remesh.Triangles.data() + 3 * t;
      const Vec3 corner[3] = { Point(x, c[0]), Point(x, c[1]), Point(x, c[2]) };
      const Vec3 centre = TriangleSample(corner, 3);
      double farthest = 0.0;
      const Index nearest = centre.allFinite() ? toInput.Nearest(centre, farthest) : -1;
      for (int k = 0; k < 3 && nearest >= 0; ++k)
      {
        const Vec3 m = TriangleSample(corner, k);
        farthest = std::max(farthest, DistanceWithin(toInput, m, toInput.DistanceTo(nearest, m)));
      }
      d.FromTriangles[t] = nearest >= 0 ? farthest : 0.0;
    }
  });
}

/// The distance from p, a point of an input triangle (its `corner`s at
/// `at` from the remesh, nearest to its triangles `nearest`), to the remesh
/// where it could exceed `most` (0 where not): a search that stops at the
/// least of `whole` (the triangle's bound), a corner's distance plus the
/// way to it and the distance to the corners' nearest triangles.
double DistanceWithinBounds(const TriangleGrid& grid, const Vec3& p, const Vec3* corner, const double* at,
  const Index* nearest, double whole, double most)
{
  double bound = whole;
  for (int j = 0; j < 3; ++j)
  {
    bound = std::min(bound, at[j] + (p - corner[j]).norm());
  }
  for (int j = 0; j < 3 && bound > most; ++j)
  {
    bound = std::min(bound, grid.DistanceTo(nearest[j], p));
  }
  return bound > most ? DistanceWithin(grid, p, bound) : 0.0;
}

/// The parts an input edge of `length` is measured in (at the points
/// between them): two (its midpoint) where it is at most two spacings long,
/// else parts of at most a spacing (a crease longer than the remesh's
/// triangles that they cut between its midpoint and its ends).
int EdgeParts(double length, double spacing)
{
  const double parts = spacing > 0.0 ? std::ceil(length / spacing) : 2.0;
  return parts > 2.0 && std::isfinite(parts) ? static_cast<int>(std::min(parts, 1e6)) : 2;
}

/// The distances to the remesh (its triangles in `grid`) of points along
/// the input triangles' edges (a spacing apart on long ones: EdgeParts) and
/// of their centres into `d` (RemeshDistances::FromInputTriangles),
/// measured only where they could
/// exceed the largest distance of the input vertices.  The distance to one
/// remesh triangle is convex, so no point of an input triangle is farther
/// from the remesh triangle nearest to a corner (RemeshDistances::Nearest)
/// than the farthest corner from it: an input triangle finer than the
/// remesh, its corners nearest to one remesh triangle, is no farther than
/// its farthest corner.  A point is also at most a vertex's distance plus
/// the way to it; the search for it stops at the least of those bounds.  On
/// an input finer than the remesh few are measured; on a coarser one, its
/// long edges and faces.
void InputTrianglesTo(const MeshTopology& topology, const double* points, const TriangleGrid& grid,
  RemeshDistances& d, int numThreads)
{
  double most = 0.0;
  for (double v : d.FromInput)
  {
    most = std::isfinite(v) ? std::max(most, v) : most;
  }
  const std::int64_t triangles = topology.NumberOfTriangles();
  const IndexArray& list = topology.TriangleList();
  d.FromInputTriangles.assign(static_cast<std::size_t>(triangles), 0.0);
  d.FarthestSample.assign(static_cast<std::size_t>(triangles), 0);
  d.FarthestAlong.assign(static_cast<std::size_t>(triangles), 0.5f);
  ParallelFor(triangles, numThreads, [&](std::int64_t begin, std::int64_t end) {
    for (std::int64_t t = begin; t < end; ++t)
    {
      Vec3 corner[3];
      double at[3];
      Index nearest[3];
      bool finite = true;
      for (int k = 0; k < 3; ++k)
      {
        const Index v = list[3 * t + k];
        corner[k] = Point(points, v);
        at[k] = d.FromInput[v];
        nearest[k] = d.Nearest[v];
        finite = finite && corner[k].allFinite() && std::isfinite(at[k]) && nearest[k] >= 0;
      }
      double whole = HUGE_VAL; // over the triangle
      for (int j = 0; j < 3 && finite && whole > most; ++j)
      {
        double farthest = at[j];
        for (int k = 0; k < 3 && farthest < whole; ++k)
        {
          farthest = std::max(farthest, nearest[k] == nearest[j] ? at[k] : grid.DistanceTo(nearest[j], corner[k]));
        }
        whole = std::min(whole, farthest);
      }
      for (int k = 0; k < 4 && finite && whole > most; ++k)
      {
        const int parts = k < 3 ? EdgeParts((corner[(k + 1) % 3] - corner[k]).norm(), d.Spacing) : 2;
        for (int i = 1; i < parts; ++i)
        {
          const double along = static_cast<double>(i) / parts;
          const Vec3 p =
            k < 3 ? Vec3(corner[k] + along * (corner[(k + 1) % 3] - corner[k])) : TriangleSample(corner, 3);
          const double distance = DistanceWithinBounds(grid, p, corner, at, nearest, whole, most);
          if (distance > d.FromInputTriangles[t])
          {
            d.FromInputTriangles[t] = distance;
            d.FarthestSample[t] = static_cast<std::uint8_t>(k);
            d.FarthestAlong[t] = static_cast<float>(along);
          }
        }
      }
    }
  });
}

} // namespace

RemeshDistances MeasureDistances(const MeshTopology& topology, const double* points, const TriangleGrid& toInput,
  const RemeshResult& remesh, int numThreads)
{
  RemeshDistances d;
  const auto count = static_cast<std::int64_t>(remesh.Points.size() / 3);
  d.Spacing = UniformSpacing(SurfaceArea(topology, points, numThreads), count);
  d.FromInput.assign(static_cast<std::size_t>(topology.NumberOfVertices()), 0.0);
  d.Nearest.assign(d.FromInput.size(), -1);
  d.FromTriangles.assign(remesh.Triangles.size() / 3, 0.0);
  const auto all = [](auto) { return true; };
  const TriangleGrid toRemesh(remesh.Points.data(), remesh.Triangles.data(), remesh.Triangles.size() / 3, numThreads);
  InputVerticesTo(topology, points, toRemesh, all, d, numThreads);
  InputTrianglesTo(topology, points, toRemesh, d, numThreads);
  TrianglesTo(remesh, toInput, all, d, numThreads);
  return d;
}

/// `d`, the distances of remesh `before`, made those of `after`, the same
/// mesh with vertices moved and edges swapped (PinNearestVertices):
/// measured again at the centres and edge midpoints of the triangles that
/// changed and, for the input vertices, to those triangles alone (the
/// nearest of the others stays) or, where the nearest changed, to all (then
/// the input triangles' points from them); measured anew where the counts
/// differ or a quarter of the triangles changed.
void UpdateDistances(const MeshTopology& topology, const double* points, const TriangleGrid& toInput,
  const RemeshResult& before, const RemeshResult& after, RemeshDistances& d, int numThreads)
{
  const std::size_t triangles = after.Triangles.size() / 3;
  std::vector<std::uint8_t> changed(triangles, 0);
  std::vector<Index> corners; // of the triangles that changed
  std::vector<Index> which;   // their ids
  for (std::size_t t = 0; t < triangles && before.Triangles.size() == after.Triangles.size() &&
       before.Points.size() == after.Points.size();
       ++t)
  {
    for (std::size_t c = 3 * t; c < 3 * t + 3 && !changed[t]; ++c)
    {
      const Index v = after.Triangles[c];
      changed[t] = v != before.Triangles[c] || Point(after.Points.data(), v) != Point(before.Points.data(), v);
    }
    if (changed[t])
    {
      corners.insert(corners.end(), after.Triangles.begin() + 3 * t, after.Triangles.begin() + 3 * t + 3);
      which.push_back(static_cast<Index>(t));
    }
  }
  if (before.Triangles.size() != after.Triangles.size() || before.Points.size() != after.Points.size() ||
    4 * which.size() > triangles)
  {
    d = MeasureDistances(topology, points, toInput, after, numThreads);
    return;
  }
  TrianglesTo(after, toInput, [&](std::int64_t t) { return changed[t] != 0; }, d, numThreads);
  const TriangleGrid whole(after.Points.data(), after.Triangles.data(), triangles, numThreads);
  InputVerticesTo(
    topology, points, whole, [&](Index v) { return d.Nearest[v] >= 0 && changed[d.Nearest[v]]; }, d, numThreads);
  const TriangleGrid moved(after.Points.data(), corners.data(), which.size(), numThreads);
  ParallelFor(topology.NumberOfVertices(), numThreads, [&](std::int64_t begin, std::int64_t end) {
    for (Index v = static_cast<Index>(begin); v < end; ++v)
    {
      double distance = 0.0;
      const Index t = d.Nearest[v] >= 0 ? moved.Nearest(Point(points, v), distance, d.FromInput[v]) : -1;
      if (t >= 0)
      {
        d.Nearest[v] = which[t];
        d.FromInput[v] = distance;
      }
    }
  });
  InputTrianglesTo(topology, points, whole, d, numThreads);
}

} // namespace beltrami
