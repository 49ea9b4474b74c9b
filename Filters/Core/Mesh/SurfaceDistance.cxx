#include "Mesh/SurfaceDistance.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

namespace beltrami
{

namespace
{

bool Finite(const Vec3& p)
{
  return std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]);
}

/// The bounding box of the finite vertices used by the triangles.
void UsedBounds(const double* points, const Index* triangles, std::size_t count, Vec3& lo, Vec3& hi)
{
  lo = Vec3::Constant(HUGE_VAL);
  hi = Vec3::Constant(-HUGE_VAL);
  for (std::size_t c = 0; c < 3 * count; ++c)
  {
    const Vec3 p = Point(points, triangles[c]);
    if (Finite(p))
    {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
  }
}

} // namespace

double UsedBoundingBoxDiagonal(const double* points, const Index* triangles, std::size_t numberOfTriangles)
{
  Vec3 lo, hi;
  UsedBounds(points, triangles, numberOfTriangles, lo, hi);
  return lo[0] <= hi[0] ? (hi - lo).norm() : 0.0;
}

TriangleGrid::TriangleGrid(
  const double* points, const Index* triangles, std::size_t numberOfTriangles, int numThreads)
  : Points(points)
  , Triangles(triangles)
{
  Vec3 lo, hi;
  UsedBounds(points, triangles, numberOfTriangles, lo, hi);
  if (!(lo[0] <= hi[0]))
  {
    return; // no finite vertex: no cells, every distance infinite
  }
  double area = 0.0;
  for (std::size_t t = 0; t < numberOfTriangles; ++t)
  {
    const Vec3 a = Point(points, triangles[3 * t]);
    const double twice = (Point(points, triangles[3 * t + 1]) - a).cross(Point(points, triangles[3 * t + 2]) - a).norm();
    area += std::isfinite(twice) ? 0.5 * twice : 0.0;
  }
  const Vec3 extent = hi - lo;
  const double n = static_cast<double>(std::max<std::size_t>(1, numberOfTriangles));
  // About two triangles of mean area a cell; no more cells than two a
  // triangle (a surface in a box: most cells are empty; slivers; a few
  // large triangles).
  Cell = 1.5 * std::sqrt(area / n);
  const double volumeCell = std::cbrt((extent[0] + 1e-300) * (extent[1] + 1e-300) * (extent[2] + 1e-300) / (2.0 * n));
  Cell = std::max(Cell, volumeCell);
  Cell = std::max(Cell, 1e-9 * extent.maxCoeff());
  if (!(Cell > 0.0) || !std::isfinite(Cell) || !std::isfinite(extent.maxCoeff() / Cell))
  {
    Cell = extent.maxCoeff() > 0.0 && std::isfinite(extent.maxCoeff()) ? extent.maxCoeff() : 1.0;
  }
  Origin = lo;
  for (int d = 0; d < 3; ++d)
  {
    const double cells = std::floor(extent[d] / Cell) + 1.0;
    Dims[d] = std::isfinite(cells) ? static_cast<long>(std::min(cells, 1e6)) : 1;
  }
  Offsets.assign(static_cast<std::size_t>(Dims[0] * Dims[1] * Dims[2]) + 1, 0);
  // Each triangle's box of cells (on the threads), then a counting sort of
  // (cell, triangle): count, start of each cell, fill (Offsets[c] runs to
  // the end of cell c), shift back.
  std::vector<std::int32_t> boxes(6 * numberOfTriangles);
  ParallelFor(static_cast<std::int64_t>(numberOfTriangles), numThreads, [&](std::int64_t begin, std::int64_t end) {
    for (std::int64_t t = begin; t < end; ++t)
    {
      std::int32_t* box = &boxes[6 * t];
      for (int d = 0; d < 3; ++d)
      {
        box[d] = static_cast<std::int32_t>(Dims[d]);
        box[3 + d] = -1;
      }
      for (int k = 0; k < 3; ++k)
      {
        const Vec3 p = Point(points, triangles[3 * t + k]);
        for (int d = 0; d < 3 && Finite(p); ++d)
        {
          box[d] = std::min(box[d], static_cast<std::int32_t>(CellIndex(p, d)));
          box[3 + d] = std::max(box[3 + d], static_cast<std::int32_t>(CellIndex(p, d)));
        }
      }
    }
  });
  for (int pass = 0; pass < 2; ++pass)
  {
    if (pass == 1)
    {
      for (std::size_t c = 1; c < Offsets.size(); ++c)
      {
        Offsets[c] += Offsets[c - 1];
      }
      Items.resize(Offsets.back());
    }
    for (std::size_t t = 0; t < numberOfTriangles; ++t)
    {
      const std::int32_t* box = &boxes[6 * t];
      for (long x = box[0]; x <= box[3]; ++x)
        for (long y = box[1]; y <= box[4]; ++y)
          for (long z = box[2]; z <= box[5]; ++z)
          {
            const std::size_t cell = static_cast<std::size_t>((x * Dims[1] + y) * Dims[2] + z);
            if (pass == 0)
            {
              ++Offsets[cell + 1];
            }
            else
            {
              Items[Offsets[cell]++] = static_cast<Index>(t);
            }
          }
    }
  }
  for (std::size_t c = Offsets.size() - 1; c > 0; --c)
  {
    Offsets[c] = Offsets[c - 1];
  }
  Offsets[0] = 0;
}

long TriangleGrid::CellIndex(const Vec3& p, int axis) const
{
  const double x = std::floor((p[axis] - Origin[axis]) / Cell);
  if (!(x > 0.0))
  {
    return 0; // below the grid, or not a number
  }
  return x >= static_cast<double>(Dims[axis] - 1) ? Dims[axis] - 1 : static_cast<long>(x);
}

double TriangleGrid::BoxDistance2(const Vec3& p, long x, long y, long z) const
{
  const long cell[3] = { x, y, z };
  double d2 = 0.0;
  for (int d = 0; d < 3; ++d)
  {
    const double lo = Origin[d] + static_cast<double>(cell[d]) * Cell, hi = lo + Cell;
    const double out = p[d] < lo ? lo - p[d] : (p[d] > hi ? p[d] - hi : 0.0);
    d2 += out * out;
  }
  return d2;
}

double TriangleGrid::BoundsDistance2(Index t, const Vec3& p) const
{
  const double* a = Points + 3 * static_cast<std::int64_t>(Triangles[3 * t]);
  const double* b = Points + 3 * static_cast<std::int64_t>(Triangles[3 * t + 1]);
  const double* c = Points + 3 * static_cast<std::int64_t>(Triangles[3 * t + 2]);
  double d2 = 0.0;
  for (int d = 0; d < 3; ++d)
  {
    const double lo = std::min({ a[d], b[d], c[d] }), hi = std::max({ a[d], b[d], c[d] });
    const double out = p[d] < lo ? lo - p[d] : (p[d] > hi ? p[d] - hi : 0.0);
    d2 += out * out;
  }
  return d2;
}

double TriangleGrid::TriangleDistance2(Index t, const Vec3& p) const
{
  double w[3];
  return ClosestPointOnTriangle(p, Point(Points, Triangles[3 * t]), Point(Points, Triangles[3 * t + 1]),
    Point(Points, Triangles[3 * t + 2]), w);
}

double TriangleGrid::Distance(const Vec3& p) const
{
  double distance = HUGE_VAL;
  Nearest(p, distance);
  return distance;
}

Index TriangleGrid::Nearest(const Vec3& p, double& distance, double within) const
{
  distance = within;
  Index nearest = -1;
  if (Items.empty() || !Finite(p))
  {
    return nearest;
  }
  const long c[3] = { CellIndex(p, 0), CellIndex(p, 1), CellIndex(p, 2) };
  const long rings = std::max({ Dims[0], Dims[1], Dims[2] });
  double best = within * within;
  for (long r = 0; r <= rings; ++r)
  {
    // The cells at Chebyshev distance r from p's cell (clipped to the grid).
    const long x0 = std::max(0L, c[0] - r), x1 = std::min(Dims[0] - 1, c[0] + r);
    const long y0 = std::max(0L, c[1] - r), y1 = std::min(Dims[1] - 1, c[1] + r);
    const long z0 = std::max(0L, c[2] - r), z1 = std::min(Dims[2] - 1, c[2] + r);
    const auto visit = [&](long x, long y, long z) {
      const std::size_t cell = static_cast<std::size_t>((x * Dims[1] + y) * Dims[2] + z);
      if (Offsets[cell] == Offsets[cell + 1] || BoxDistance2(p, x, y, z) >= best)
      {
        return; // empty, or no nearer than the nearest triangle so far
      }
      for (std::size_t k = Offsets[cell]; k < Offsets[cell + 1]; ++k)
      {
        if (BoundsDistance2(Items[k], p) >= best)
        {
          continue; // (its box no nearer: the cheaper test)
        }
        const double d2 = TriangleDistance2(Items[k], p);
        if (d2 < best)
        {
          best = d2;
          nearest = Items[k];
        }
      }
    };
    for (long x = x0; x <= x1; ++x)
      for (long y = y0; y <= y1; ++y)
      {
        if (std::abs(x - c[0]) == r || std::abs(y - c[1]) == r)
        {
          for (long z = z0; z <= z1; ++z)
          {
            visit(x, y, z); // a face of the shell
          }
          continue;
        }
        if (c[2] - r >= 0)
        {
          visit(x, y, c[2] - r); // inside the shell's x-y square: its two ends in z
        }
        if (c[2] + r < Dims[2])
        {
          visit(x, y, c[2] + r);
        }
      }
    // The cells not visited yet lie beyond the faces of the block of cells
    // visited (on the sides where the grid goes on): no nearer than p's
    // distance to those faces.
    double reach = HUGE_VAL;
    for (int d = 0; d < 3; ++d)
    {
      if (c[d] - r > 0)
      {
        reach = std::min(reach, p[d] - (Origin[d] + static_cast<double>(c[d] - r) * Cell));
      }
      if (c[d] + r < Dims[d] - 1)
      {
        reach = std::min(reach, Origin[d] + static_cast<double>(c[d] + r + 1) * Cell - p[d]);
      }
    }
    if (reach == HUGE_VAL || (reach > 0.0 && best <= reach * reach))
    {
      break;
    }
  }
  distance = nearest >= 0 ? std::sqrt(best) : within;
  return nearest;
}

Vec3 TriangleSample(const Vec3* corner, int k)
{
  return k < 3 ? Vec3(0.5 * (corner[k] + corner[(k + 1) % 3])) : Vec3((corner[0] + corner[1] + corner[2]) / 3.0);
}

double FarthestFrom(const double* points, const Index* triangles, std::size_t count, DeviationSamples samples,
  const TriangleGrid& to, int numThreads, Vec3& where)
{
  const bool vertices = samples == DeviationSamples::Vertices || samples == DeviationSamples::Both ||
    samples == DeviationSamples::All;
  const int perTriangle = samples == DeviationSamples::Vertices ? 0
    : samples == DeviationSamples::Midpoints || samples == DeviationSamples::All ? 4
                                                                                 : 1;
  Index numberOfVertices = 0;
  for (std::size_t c = 0; vertices && c < 3 * count; ++c)
  {
    numberOfVertices = std::max(numberOfVertices, triangles[c] + 1);
  }
  std::vector<std::uint8_t> used(static_cast<std::size_t>(numberOfVertices), 0);
  for (std::size_t c = 0; vertices && c < 3 * count; ++c)
  {
    used[triangles[c]] = 1;
  }
  // The triangles' samples (the centre, then the edges' midpoints), then the vertices'.
  const std::int64_t first = perTriangle * static_cast<std::int64_t>(count);
  const auto sample = [&](std::int64_t k, Vec3& p) {
    if (k < first)
    {
      const std::int64_t t = k / perTriangle;
      const int j = static_cast<int>(k % perTriangle);
      const Vec3 corner[3] = { Point(points, triangles[3 * t]), Point(points, triangles[3 * t + 1]),
        Point(points, triangles[3 * t + 2]) };
      p = TriangleSample(corner, (j + 3) % 4);
      return true;
    }
    p = Point(points, static_cast<Index>(k - first));
    return used[k - first] != 0;
  };
  const std::vector<double> partials = ParallelPartials(first + numberOfVertices, 2, numThreads,
    [&](std::int64_t begin, std::int64_t end, double* partial) {
      partial[1] = -1.0;
      for (std::int64_t k = begin; k < end; ++k)
      {
        Vec3 p;
        if (sample(k, p) && Finite(p))
        {
          const double d = to.Distance(p);
          if (partial[1] < 0.0 || d > partial[0])
          {
            partial[0] = d;
            partial[1] = static_cast<double>(k);
          }
        }
      }
    });
  double worst = 0.0;
  for (std::size_t c = 0; c + 1 < partials.size(); c += 2)
  {
    if (partials[c + 1] >= 0.0 && partials[c] > worst)
    {
      worst = partials[c];
      sample(static_cast<std::int64_t>(partials[c + 1]), where);
    }
  }
  return worst;
}

SurfaceDeviation MeasureDeviation(const double* firstPoints, const Index* firstTriangles, std::size_t firstCount,
  DeviationSamples firstSamples, const double* secondPoints, const Index* secondTriangles, std::size_t secondCount,
  DeviationSamples secondSamples, int numThreads)
{
  SurfaceDeviation out;
  const TriangleGrid first(firstPoints, firstTriangles, firstCount, numThreads);
  const TriangleGrid second(secondPoints, secondTriangles, secondCount, numThreads);
  out.FirstToSecond =
    FarthestFrom(firstPoints, firstTriangles, firstCount, firstSamples, second, numThreads, out.FarthestOfFirst);
  out.SecondToFirst =
    FarthestFrom(secondPoints, secondTriangles, secondCount, secondSamples, first, numThreads, out.FarthestOfSecond);
  return out;
}

} // namespace beltrami
