#include "Maps/GeometryImages.h"

#include "Mesh/Geometry.h"
#include "Support/Parallel.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>

namespace beltrami
{

namespace
{

/// The raster pixel (column or row) of coordinate u at resolution n: -1
/// below the first pixel's centre, clamped to n - 1 above.
inline int RasterPixel(double u, int n)
{
  return std::clamp(static_cast<int>(std::floor(u * n - 0.5)), -1, n - 1);
}

/// Barycentric coordinates of a point p in a triangle (a, b, c) of twice
/// the signed area `area` (positive), from Cross2(p, b, c) and
/// Cross2(a, p, c); true when p is inside or on its boundary (a relative
/// tolerance of 1e-12 for round-off).
inline bool BarycentricFromCrosses(double pbc, double apc, double area, double* w)
{
  w[0] = pbc / area;
  w[1] = apc / area;
  w[2] = 1.0 - w[0] - w[1];
  const double eps = -1e-12;
  return w[0] >= eps && w[1] >= eps && w[2] >= eps;
}

/// The centre of pixel column (or row) i of a raster n pixels a side, in
/// [0, 1]: the one place that says where a pixel samples (RasterizeRow
/// and PixelBarycentric must agree to the bit).
inline double PixelCentre(std::int64_t i, int n)
{
  return (static_cast<double>(i) + 0.5) / n;
}

/// The corners' UVs of chart triangle t.
inline void TriangleUV(const AtlasChart& chart, Index t, const double* (&uv)[3])
{
  for (int k = 0; k < 3; ++k)
  {
    uv[k] = &chart.UV[2 * chart.Corners[3 * static_cast<std::size_t>(t) + k]];
  }
}

/// Barycentric coordinates of p in the chart triangle t
/// (BarycentricFromCrosses); false for a triangle without positive area.
bool Barycentric(const AtlasChart& chart, Index t, const double* p, double* w)
{
  const double* uv[3];
  TriangleUV(chart, t, uv);
  const double area = Cross2(uv[0], uv[1], uv[2]);
  return area > 0.0 && BarycentricFromCrosses(Cross2(p, uv[1], uv[2]), Cross2(uv[0], p, uv[2]), area, w);
}

} // namespace

AtlasChart PackedAtlas(const AtlasResult& atlas)
{
  AtlasChart packed;
  for (const AtlasChart& chart : atlas.Charts)
  {
    const Index first = static_cast<Index>(packed.Vertices.size());
    packed.Triangles.insert(packed.Triangles.end(), chart.Triangles.begin(), chart.Triangles.end());
    packed.Vertices.insert(packed.Vertices.end(), chart.Vertices.begin(), chart.Vertices.end());
    for (Index corner : chart.Corners)
    {
      packed.Corners.push_back(first + corner);
    }
    for (Index v = 0; v < static_cast<Index>(chart.Vertices.size()); ++v)
    {
      double uv[2];
      AtlasUV(chart, v, uv);
      packed.UV.insert(packed.UV.end(), uv, uv + 2);
    }
    packed.Area3D += chart.Area3D;
  }
  return packed;
}

Index LocateInChart(const AtlasChart& chart, const double uv[2], double barycentric[3])
{
  for (Index t = 0; t < static_cast<Index>(chart.Corners.size() / 3); ++t)
  {
    if (Barycentric(chart, t, uv, barycentric))
    {
      return t;
    }
  }
  return -1;
}

ChartLocator::ChartLocator(const AtlasChart& chart)
  : Chart(&chart)
{
  const Index triangles = static_cast<Index>(chart.Corners.size() / 3);
  double upper[2] = { -HUGE_VAL, -HUGE_VAL };
  Lower[0] = Lower[1] = HUGE_VAL;
  for (std::size_t i = 0; i < chart.UV.size(); ++i)
  {
    Lower[i % 2] = std::min(Lower[i % 2], chart.UV[i]);
    upper[i % 2] = std::max(upper[i % 2], chart.UV[i]);
  }
  Cells = std::max(1, static_cast<int>(std::sqrt(static_cast<double>(triangles))));
  for (int axis = 0; axis < 2; ++axis)
  {
    Width[axis] = upper[axis] > Lower[axis] ? (upper[axis] - Lower[axis]) / Cells : 1.0;
  }
  // Each triangle in every cell its bounding box touches (counted, then filled).
  const auto forCells = [&](Index t, auto&& visit) {
    int lo[2] = { Cells, Cells }, hi[2] = { -1, -1 };
    for (int k = 0; k < 3; ++k)
    {
      for (int axis = 0; axis < 2; ++axis)
      {
        const int c = CellOf(chart.UV[2 * chart.Corners[3 * t + k] + axis], axis);
        lo[axis] = std::min(lo[axis], c);
        hi[axis] = std::max(hi[axis], c);
      }
    }
    for (int y = lo[1]; y <= hi[1]; ++y)
    {
      for (int x = lo[0]; x <= hi[0]; ++x)
      {
        visit(static_cast<std::size_t>(y) * Cells + x);
      }
    }
  };
  Offsets.assign(static_cast<std::size_t>(Cells) * Cells + 1, 0);
  for (Index t = 0; t < triangles; ++t)
  {
    forCells(t, [&](std::size_t cell) { ++Offsets[cell + 1]; });
  }
  for (std::size_t c = 1; c < Offsets.size(); ++c)
  {
    Offsets[c] += Offsets[c - 1];
  }
  Items.resize(Offsets.back());
  std::vector<std::int64_t> fill(Offsets.begin(), Offsets.end() - 1);
  for (Index t = 0; t < triangles; ++t)
  {
    forCells(t, [&](std::size_t cell) { Items[fill[cell]++] = t; });
  }
}

int ChartLocator::CellOf(double u, int axis) const
{
  const double c = std::floor((u - Lower[axis]) / Width[axis]);
  return static_cast<int>(std::clamp(c, 0.0, static_cast<double>(Cells - 1)));
}

Index ChartLocator::Locate(const double uv[2], double barycentric[3]) const
{
  if (!(std::isfinite(uv[0]) && std::isfinite(uv[1])))
  {
    return -1;
  }
  const std::size_t cell = static_cast<std::size_t>(CellOf(uv[1], 1)) * Cells + CellOf(uv[0], 0);
  for (std::int64_t i = Offsets[cell]; i < Offsets[cell + 1]; ++i)
  {
    if (Barycentric(*Chart, Items[i], uv, barycentric))
    {
      return Items[i];
    }
  }
  return -1;
}

Index ChartLocator::LocateNearest(const double uv[2], double barycentric[3]) const
{
  Index best = Locate(uv, barycentric);
  if (best >= 0 || !(std::isfinite(uv[0]) && std::isfinite(uv[1])))
  {
    return best;
  }
  double bestOutside = HUGE_VAL, w[3];
  const int cx = CellOf(uv[0], 0), cy = CellOf(uv[1], 1);
  for (int y = std::max(0, cy - 1); y <= std::min(Cells - 1, cy + 1); ++y)
  {
    for (int x = std::max(0, cx - 1); x <= std::min(Cells - 1, cx + 1); ++x)
    {
      const std::size_t cell = static_cast<std::size_t>(y) * Cells + x;
      for (std::int64_t i = Offsets[cell]; i < Offsets[cell + 1]; ++i)
      {
        w[0] = w[1] = w[2] = -HUGE_VAL; // a degenerate triangle leaves them unset
        Barycentric(*Chart, Items[i], uv, w);
        const double outside = -std::min({ w[0], w[1], w[2] });
        if (std::isfinite(outside) && outside < bestOutside)
        {
          bestOutside = outside;
          best = Items[i];
          double sum = 0.0;
          for (int k = 0; k < 3; ++k)
          {
            barycentric[k] = std::max(0.0, w[k]);
            sum += barycentric[k];
          }
          for (int k = 0; k < 3; ++k)
          {
            barycentric[k] /= sum;
          }
        }
      }
    }
  }
  return best;
}

ChartRaster RasterizeChart(const AtlasChart& chart, int resolution, int numThreads)
{
  ChartRaster raster;
  RasterizeChart(chart, resolution, raster, numThreads);
  return raster;
}

namespace
{

/// The triangles that reach each raster row (CSR, in triangle order, so
/// that a pixel on a shared edge goes to the first triangle whatever the
/// thread count): rows [first, last] of its v range, one more for round-off.
void RowsOfTriangles(const AtlasChart& chart, int n, std::vector<std::int64_t>& offsets, std::vector<Index>& items)
{
  const Index triangles = static_cast<Index>(chart.Corners.size() / 3);
  std::vector<int> span(2 * static_cast<std::size_t>(triangles));
  offsets.assign(static_cast<std::size_t>(n) + 2, 0);
  for (Index t = 0; t < triangles; ++t)
  {
    const double* uv[3];
    TriangleUV(chart, t, uv);
    const double lo = std::min({ uv[0][1], uv[1][1], uv[2][1] }), hi = std::max({ uv[0][1], uv[1][1], uv[2][1] });
    int* rows = &span[2 * static_cast<std::size_t>(t)];
    rows[0] = std::max(0, RasterPixel(lo, n));
    rows[1] = std::min(n - 1, RasterPixel(hi, n) + 1);
    for (int j = rows[0]; j <= rows[1]; ++j)
    {
      ++offsets[j + 2];
    }
  }
  for (std::size_t j = 2; j < offsets.size(); ++j)
  {
    offsets[j] += offsets[j - 1];
  }
  items.resize(offsets.back());
  for (Index t = 0; t < triangles; ++t) // (offsets[j + 1]: where row j's next item goes)
  {
    for (int j = span[2 * static_cast<std::size_t>(t)]; j <= span[2 * static_cast<std::size_t>(t) + 1]; ++j)
    {
      items[offsets[j + 1]++] = t;
    }
  }
  offsets.pop_back(); // row j: [offsets[j], offsets[j + 1])
}

/// Raster row j (centre line v = (j + 0.5) / n): each of its triangles'
/// pixels not taken by an earlier triangle whose centres lie inside it.
void RasterizeRow(const AtlasChart& chart, int n, std::int64_t j, const Index* begin, const Index* end,
  ChartRaster& raster)
{
  const double y = PixelCentre(j, n);
  for (const Index* item = begin; item != end; ++item)
  {
    const double* uv[3];
    TriangleUV(chart, *item, uv);
    const double area = Cross2(uv[0], uv[1], uv[2]);
    if (!(area > 0.0))
    {
      continue; // (no pixel is inside it)
    }
    // The triangle's span on the row's centre line (the pixels a scanline
    // meets; one more on each side for round-off: the barycentric test
    // decides).
    double lo = HUGE_VAL, hi = -HUGE_VAL;
    for (int k = 0; k < 3; ++k)
    {
      const double* p = uv[k];
      const double* q = uv[(k + 1) % 3];
      if ((p[1] - y) * (q[1] - y) <= 0.0)
      {
        const double u = p[1] == q[1] ? p[0] : p[0] + (y - p[1]) * (q[0] - p[0]) / (q[1] - p[1]);
        lo = std::min({ lo, u, p[1] == q[1] ? q[0] : u });
        hi = std::max({ hi, u, p[1] == q[1] ? q[0] : u });
      }
    }
    if (!(lo <= hi))
    {
      continue; // the row's centre line misses the triangle
    }
    // Pixels clearly outside (by more than the test's tolerance and its
    // round-off) are skipped without the test's divisions: most pixels
    // tried are outside, and the divisions were most of the time.
    const double outside = -2e-12 * area;
    for (int i = std::max(0, RasterPixel(lo, n) - 1); i <= std::min(n - 1, RasterPixel(hi, n) + 2); ++i)
    {
      const std::size_t p = static_cast<std::size_t>(j) * n + i;
      const double centre[2] = { PixelCentre(i, n), y };
      if (raster.Face[p] >= 0)
      {
        continue;
      }
      const double pbc = Cross2(centre, uv[1], uv[2]), apc = Cross2(uv[0], centre, uv[2]);
      double w[3];
      if (pbc >= outside && apc >= outside && BarycentricFromCrosses(pbc, apc, area, w))
      {
        raster.Face[p] = *item;
      }
    }
  }
}

} // namespace

void RasterizeChart(const AtlasChart& chart, int resolution, ChartRaster& raster, int numThreads)
{
  const int n = std::max(1, resolution);
  raster.Resolution = n;
  const std::size_t pixels = static_cast<std::size_t>(n) * n;
  raster.Face.assign(pixels, -1);
  std::vector<std::int64_t> offsets;
  std::vector<Index> items;
  RowsOfTriangles(chart, n, offsets, items);
  ParallelFor(n, numThreads,
    [&](std::int64_t begin, std::int64_t end) {
      for (std::int64_t j = begin; j < end; ++j)
      {
        RasterizeRow(chart, n, j, items.data() + offsets[j], items.data() + offsets[j + 1], raster);
      }
    },
    {}, 0, 1);
}

void PixelBarycentric(const AtlasChart& chart, const ChartRaster& raster, std::size_t p, double* w)
{
  const int n = raster.Resolution;
  const double centre[2] = { PixelCentre(static_cast<std::int64_t>(p % n), n),
    PixelCentre(static_cast<std::int64_t>(p / n), n) };
  const double* uv[3];
  TriangleUV(chart, raster.Face[p], uv);
  BarycentricFromCrosses(Cross2(centre, uv[1], uv[2]), Cross2(uv[0], centre, uv[2]), Cross2(uv[0], uv[1], uv[2]), w);
}

void InterpolateOnRaster(const ChartRaster& raster, const AtlasChart& chart, const double* values, int components,
  double* out, bool chartValues, int numThreads)
{
  const std::int64_t pixels = static_cast<std::int64_t>(raster.Face.size());
  ParallelFor(pixels, numThreads, [&](std::int64_t begin, std::int64_t end) {
    for (std::int64_t p = begin; p < end; ++p)
    {
      const Index t = raster.Face[p];
      double w[3];
      if (t >= 0)
      {
        PixelBarycentric(chart, raster, static_cast<std::size_t>(p), w);
      }
      for (int c = 0; c < components; ++c)
      {
        double v = std::numeric_limits<double>::quiet_NaN();
        if (t >= 0)
        {
          v = 0.0;
          for (int k = 0; k < 3; ++k)
          {
            const Index corner = chart.Corners[3 * t + k];
            const std::size_t vertex = static_cast<std::size_t>(chartValues ? corner : chart.Vertices[corner]);
            v += w[k] * values[vertex * components + c];
          }
        }
        out[p * components + c] = v;
      }
    }
  });
}

void AreaMap(const ChartRaster& raster, const AtlasChart& chart, const double* points, double* out, int numThreads)
{
  const Index triangles = static_cast<Index>(chart.Corners.size() / 3);
  LargeVector<double> ratio(triangles);
  ParallelFor(triangles, numThreads, [&](std::int64_t begin, std::int64_t end) {
    for (Index t = static_cast<Index>(begin); t < end; ++t)
    {
      const Index* c = &chart.Corners[3 * t];
      const Vec3 a = Point(points, chart.Vertices[c[0]]), b = Point(points, chart.Vertices[c[1]]),
                 d = Point(points, chart.Vertices[c[2]]);
      const double area3D = 0.5 * (b - a).cross(d - a).norm();
      const double area2D = 0.5 * Cross2(&chart.UV[2 * c[0]], &chart.UV[2 * c[1]], &chart.UV[2 * c[2]]);
      ratio[t] = area2D > 0.0 ? area3D / area2D : 0.0;
    }
  });
  ParallelFor(static_cast<std::int64_t>(raster.Face.size()), numThreads, [&](std::int64_t begin, std::int64_t end) {
    for (std::int64_t p = begin; p < end; ++p)
    {
      out[p] = raster.Face[p] >= 0 ? ratio[raster.Face[p]] : std::numeric_limits<double>::quiet_NaN();
    }
  });
}

} // namespace beltrami
