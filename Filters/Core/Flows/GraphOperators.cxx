#include "Flows/GraphOperators.h"

#include "Flows/GraphFlowDiscretization.h"
#include "Flows/NoiseEstimation.h"
#include "Mesh/Laplacian.h"
#include "Mesh/MeshMeasures.h"
#include "Mesh/SurfaceOperators.h"
#include "Mesh/Tetrahedra.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <functional>
#include <limits>
#include <memory>
#include <vector>

namespace beltrami
{

namespace
{

using namespace detail;

/// Vertices per band of a grid (bounded memory for any image).
constexpr Index BandVertices = Index(1) << 18;

/// The options and the component count: an error sentence, empty if usable.
std::string CheckInput(const GraphOperatorOptions& o, int components, int maximum)
{
  if (components < 1 || components > maximum)
  {
    return "the data have " + std::to_string(components) + " components; 1 to " + std::to_string(maximum) +
      " are supported";
  }
  if (!(o.ContrastScale >= 0.0) || !std::isfinite(o.ContrastScale))
  {
    return "ContrastScale must be 0 (automatic) or positive";
  }
  if (!(o.NoiseLevel >= 0.0) || !std::isfinite(o.NoiseLevel))
  {
    return "NoiseLevel must be 0 (estimated) or positive";
  }
  return {};
}

/// The contrast scale alpha: the given one, or the flows' automatic
/// c h / sigma with sigma given or estimated (1 where no noise is found).
void ChooseContrast(const GraphOperatorOptions& o, double c, double h, const std::function<double()>& estimate,
  GraphOperatorReport& report)
{
  if (o.ContrastScale > 0.0)
  {
    report.ContrastScale = o.ContrastScale;
    return;
  }
  report.EstimatedNoiseLevel = o.NoiseLevel > 0.0 ? 0.0 : estimate();
  report.NoiseLevel = o.NoiseLevel > 0.0 ? o.NoiseLevel : report.EstimatedNoiseLevel;
  report.ContrastScale = report.NoiseLevel > 0.0 ? c * h / report.NoiseLevel : 1.0;
}

/// Writes the outputs of a vertex from its mean curvature normal K in R^N.
class Writer
{
public:
  Writer(const GraphOperatorOutputs& out, int base, int components, double alpha, int manifold)
    : Out(out), Base(base), Components(components), N(base + components), Alpha(alpha), Manifold(manifold)
  {
  }

  void Defined(Index o, const double* k, double gaussian, double indicator) const
  {
    if (Out.Undefined)
    {
      Out.Undefined[o] = 0;
    }
    double norm2 = 0.0;
    for (int a = 0; a < N; ++a)
    {
      norm2 += k[a] * k[a];
    }
    if (Out.MeanCurvatureNormal)
    {
      std::copy(k, k + N, Out.MeanCurvatureNormal + static_cast<std::int64_t>(N) * o);
    }
    if (Out.BeltramiOperator)
    {
      for (int a = 0; a < Components; ++a)
      {
        Out.BeltramiOperator[static_cast<std::int64_t>(Components) * o + a] = -k[Base + a] / Alpha;
      }
    }
    if (Out.MeanCurvature)
    {
      Out.MeanCurvature[o] = std::sqrt(norm2) / Manifold;
    }
    if (Out.GaussianCurvature)
    {
      Out.GaussianCurvature[o] = gaussian;
    }
    if (Out.EdgeIndicator)
    {
      Out.EdgeIndicator[o] = indicator;
    }
  }

  void Undefined(Index o) const
  {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    std::vector<double> k(N, nan);
    Defined(o, k.data(), nan, nan);
    if (Out.Undefined)
    {
      Out.Undefined[o] = 1;
    }
  }

private:
  const GraphOperatorOutputs& Out;
  int Base, Components, N;
  double Alpha;
  int Manifold;
};

/// The value a grid axis of n samples has at index i in [-1, n] as up to two
/// (index, weight) terms: inside, itself; one outside, the boundary rule's
/// continuation (Linear: 2 f(0) - f(1), Reflect: f(1); f(0) when n = 1).
int AxisTerms(std::int64_t i, std::int64_t n, GridBoundary rule, std::int64_t index[2], double weight[2])
{
  if (i >= 0 && i < n)
  {
    index[0] = i;
    weight[0] = 1.0;
    return 1;
  }
  const std::int64_t edge = i < 0 ? 0 : n - 1, inner = i < 0 ? 1 : n - 2;
  if (n < 2)
  {
    index[0] = 0;
    weight[0] = 1.0;
    return 1;
  }
  if (rule == GridBoundary::Reflect)
  {
    index[0] = inner;
    weight[0] = 1.0;
    return 1;
  }
  index[0] = edge;
  weight[0] = 2.0;
  index[1] = inner;
  weight[1] = -1.0;
  return 2;
}

/// A grid continued by one ring: the values (times alpha) at padded
/// position (x, y, z) (each in [-1, n]), the embedding's data part.
struct PaddedGrid
{
  std::int64_t Size[3] = { 1, 1, 1 };
  int Components = 1;
  const double* Values = nullptr;
  GridBoundary Rule = GridBoundary::Linear;
  double Alpha = 1.0;

  PaddedGrid(std::int64_t nx, std::int64_t ny, std::int64_t nz, int components, const double* values,
    GridBoundary rule, double alpha)
    : Size{ nx, ny, nz }
    , Components(components)
    , Values(values)
    , Rule(rule)
    , Alpha(alpha)
  {
  }

  void Data(std::int64_t x, std::int64_t y, std::int64_t z, double* out) const
  {
    std::int64_t ix[2], iy[2], iz[2];
    double wx[2], wy[2], wz[2];
    const int nx = AxisTerms(x, Size[0], Rule, ix, wx);
    const int ny = AxisTerms(y, Size[1], Rule, iy, wy);
    const int nz = AxisTerms(z, Size[2], Rule, iz, wz);
    std::fill(out, out + Components, 0.0);
    for (int c = 0; c < nz; ++c)
    {
      for (int b = 0; b < ny; ++b)
      {
        for (int a = 0; a < nx; ++a)
        {
          const double w = Alpha * wx[a] * wy[b] * wz[c];
          const double* v = Values + Components * (ix[a] + Size[0] * (iy[b] + Size[1] * iz[c]));
          for (int k = 0; k < Components; ++k)
          {
            out[k] += w * v[k];
          }
        }
      }
    }
  }
};

/// The two triangulations of a grid of w x h points (row-major): every cell
/// split along one diagonal, or along the other.
std::unique_ptr<MeshTopology> GridTriangles(Index w, Index h, bool otherDiagonal, int threads)
{
  IndexArray triangles;
  triangles.reserve(static_cast<std::size_t>(w - 1) * (h - 1) * 6);
  for (Index r = 0; r + 1 < h; ++r)
  {
    for (Index c = 0; c + 1 < w; ++c)
    {
      const Index a = r * w + c, b = a + 1, d = a + w, e = d + 1; // e: diagonal to a
      const Index t[6] = { a, b, e, a, e, d };
      const Index u[6] = { a, b, d, b, e, d };
      const Index* use = otherDiagonal ? u : t;
      triangles.insert(triangles.end(), use, use + 6);
    }
  }
  return std::make_unique<MeshTopology>(w * h, std::move(triangles), threads);
}

/// The start of both mesh paths: the input checked (`maximum` components),
/// alpha chosen (from the mean edge length and the noise estimate), and the
/// graph (x, y, z, alpha f) of the point data, 3 + components values per
/// vertex; empty when there is nothing to do (an error, or no vertex).
std::vector<double> StartMesh(Index size, const double* points, int components, const double* values,
  const GraphOperatorOptions& options, int maximum, const std::function<double()>& meanEdgeLength,
  const std::function<double()>& estimate, GraphOperatorReport& report, bool collective = false)
{
  report.Error = CheckInput(options, components, maximum);
  if (!report.Error.empty() || (size == 0 && !collective)) // (a process of a split run joins the sums)
  {
    return {};
  }
  ChooseContrast(options, SurfaceAutomaticContrast, meanEdgeLength(), estimate, report);
  const double alpha = report.ContrastScale;
  const int n = 3 + components;
  std::vector<double> embedded(static_cast<std::size_t>(size) * n);
  for (std::size_t i = 0; i < static_cast<std::size_t>(size); ++i)
  {
    std::copy(points + 3 * i, points + 3 * i + 3, &embedded[i * n]);
    for (int k = 0; k < components; ++k)
    {
      embedded[i * n + 3 + k] = alpha * values[i * components + k];
    }
  }
  return embedded;
}

} // namespace

GraphOperatorReport ComputeImageGraphOperators(const PixelGrid& grid, int components, const double* values,
  const GraphOperatorOptions& options, const GraphOperatorOutputs& outputs)
{
  GraphOperatorReport report;
  report.Error = CheckInput(options, components, 6);
  const double sx = grid.SpacingX, sy = grid.SpacingY;
  if (report.Error.empty() && !(sx > 0.0 && sy > 0.0 && std::isfinite(sx * sy)))
  {
    report.Error = "the pixel spacing must be positive";
  }
  if (!report.Error.empty() || grid.Width < 1 || grid.Height < 1)
  {
    return report;
  }
  const int threads = options.NumberOfThreads;
  ChooseContrast(options, SurfaceAutomaticContrast, std::sqrt(sx * sy),
    [&]() { return EstimateImageNoise(grid, components, values, threads); }, report);
  const int n = 2 + components;
  const Writer writer(outputs, 2, components, report.ContrastScale, 2);
  const PaddedGrid padded(grid.Width, grid.Height, 1, components, values, options.Boundary, report.ContrastScale);
  const Index pw = grid.Width + 2;
  const Index band = std::max<Index>(1, std::min<Index>(grid.Height, BandVertices / pw));
  std::unique_ptr<MeshTopology> first, second;
  Index builtRows = 0;
  for (Index r0 = 0; r0 < grid.Height; r0 += band)
  {
    const Index rows = std::min(band, grid.Height - r0) + 2; // padded rows r0 - 1 .. r0 + rows - 2
    if (rows != builtRows)
    {
      first = GridTriangles(pw, rows, false, threads);
      second = GridTriangles(pw, rows, true, threads);
      builtRows = rows;
    }
    const Index count = pw * rows;
    std::vector<double> embedded(static_cast<std::size_t>(count) * n);
    ParallelFor(count, threads, [&](std::int64_t b, std::int64_t e) {
      for (std::int64_t v = b; v < e; ++v)
      {
        const std::int64_t x = v % pw - 1, y = r0 + v / pw - 1;
        double* p = &embedded[static_cast<std::size_t>(v) * n];
        p[0] = x * sx;
        p[1] = y * sy;
        padded.Data(x, y, 0, p + 2);
      }
    });
    std::vector<double> k1(embedded.size()), k2(embedded.size()), a1(count), a2(count), d1(count), d2(count);
    ComputeBeltramiOperator(*first, embedded.data(), n, n, k1.data(), a1.data(), d1.data(), threads);
    ComputeBeltramiOperator(*second, embedded.data(), n, n, k2.data(), a2.data(), d2.data(), threads);
    ParallelFor((rows - 2) * grid.Width, threads, [&](std::int64_t b, std::int64_t e) {
      std::vector<double> k(n);
      for (std::int64_t i = b; i < e; ++i)
      {
        const std::int64_t x = i % grid.Width, y = i / grid.Width; // y: row in the band
        const std::int64_t v = (y + 1) * pw + x + 1;
        const double area = a1[v] + a2[v];
        for (int a = 0; a < n; ++a)
        {
          k[a] = (k1[v * n + a] * a1[v] + k2[v * n + a] * a2[v]) / area;
        }
        writer.Defined(static_cast<Index>((r0 + y) * grid.Width + x), k.data(), (d1[v] + d2[v]) / area,
          2.0 * sx * sy / area);
      }
    });
  }
  return report;
}

GraphOperatorReport ComputeVolumeGraphOperators(const VoxelGrid& grid, int components, const double* values,
  const GraphOperatorOptions& options, const GraphOperatorOutputs& outputs)
{
  GraphOperatorReport report;
  report.Error = CheckInput(options, components, 6);
  const double sx = grid.SpacingX, sy = grid.SpacingY, sz = grid.SpacingZ;
  if (report.Error.empty() && !(sx > 0.0 && sy > 0.0 && sz > 0.0 && std::isfinite(sx * sy * sz)))
  {
    report.Error = "the voxel spacing must be positive";
  }
  if (!report.Error.empty() || grid.Width < 1 || grid.Height < 1 || grid.Depth < 1)
  {
    return report;
  }
  const int threads = options.NumberOfThreads;
  ChooseContrast(options, VolumeAutomaticContrast, std::cbrt(sx * sy * sz),
    [&]() { return EstimateVolumeNoise(grid, components, values, threads); }, report);
  const int n = 3 + components;
  const Writer writer(outputs, 3, components, report.ContrastScale, 3);
  const PaddedGrid padded(grid.Width, grid.Height, grid.Depth, components, values, options.Boundary,
    report.ContrastScale);
  const Index pw = static_cast<Index>(grid.Width + 2), ph = static_cast<Index>(grid.Height + 2);
  const std::int64_t plane = static_cast<std::int64_t>(pw) * ph;
  const Index slab = static_cast<Index>(std::max<std::int64_t>(1, std::min<std::int64_t>(grid.Depth, BandVertices / plane)));
  std::unique_ptr<TetrahedralMesh> mesh;
  Index builtPlanes = 0;
  const double cell = sx * sy * sz;
  std::atomic<Index> overflowed{ 0 };
  for (std::int64_t z0 = 0; z0 < grid.Depth; z0 += slab)
  {
    const Index planes = static_cast<Index>(std::min<std::int64_t>(slab, grid.Depth - z0) + 2);
    if (planes != builtPlanes)
    {
      mesh = std::make_unique<TetrahedralMesh>(static_cast<Index>(plane * planes), GridTetrahedra(pw, ph, planes), threads);
      builtPlanes = planes;
    }
    const std::int64_t count = plane * planes;
    std::vector<double> embedded(static_cast<std::size_t>(count) * n), kx(embedded.size());
    ParallelFor(count, threads, [&](std::int64_t b, std::int64_t e) {
      for (std::int64_t v = b; v < e; ++v)
      {
        const std::int64_t x = v % pw - 1, y = (v / pw) % ph - 1, z = z0 + v / plane - 1;
        double* p = &embedded[static_cast<std::size_t>(v) * n];
        p[0] = x * sx;
        p[1] = y * sy;
        p[2] = z * sz;
        padded.Data(x, y, z, p + 3);
      }
    });
    GraphLaplacian laplacian;
    AssembleTetrahedralLaplacian(*mesh, embedded.data(), n, laplacian, threads);
    laplacian.ApplyStiffness(embedded.data(), kx.data(), n, threads);
    const std::int64_t inner = static_cast<std::int64_t>(grid.Width) * grid.Height * (planes - 2);
    ParallelFor(inner, threads, [&](std::int64_t b, std::int64_t e) {
      std::vector<double> k(n);
      for (std::int64_t i = b; i < e; ++i)
      {
        const std::int64_t x = i % grid.Width, y = (i / grid.Width) % grid.Height, z = i / (grid.Width * grid.Height);
        const std::int64_t v = (z + 1) * plane + (y + 1) * pw + x + 1;
        const Index o = static_cast<Index>(x + grid.Width * (y + grid.Height * (z0 + z)));
        const double mass = laplacian.Mass[v];
        if (!(mass > 0.0))
        {
          writer.Undefined(o);
          ++overflowed; // (a voxel's own volume is positive)
          continue;
        }
        for (int a = 0; a < n; ++a)
        {
          k[a] = kx[v * n + a] / mass;
        }
        writer.Defined(o, k.data(), std::numeric_limits<double>::quiet_NaN(), cell / mass);
      }
    });
  }
  report.OverflowVertices = overflowed;
  return report;
}

namespace
{

GraphOperatorReport SurfaceGraphOperatorsAtScale(const MeshTopology& topology, const double* points,
  int components, const double* values, const GraphOperatorOptions& options, const GraphOperatorOutputs& outputs,
  const Partition* split);

} // namespace

GraphOperatorReport ComputeSurfaceGraphOperators(const MeshTopology& topology, const double* points,
  int components, const double* values, const GraphOperatorOptions& options, const GraphOperatorOutputs& outputs,
  const Partition* split)
{
  // A surface far from unit size (squared areas out of range): the points
  // times 2^-e (exactly), the embedding with them (alpha follows the mean
  // edge length), the results scaled back: K and H 1/length, Delta_g f and
  // the Gaussian curvature 1/length^2, alpha length per data unit.
  Eigen::AlignedBox3d box = UsedPointsBox(topology, points);
  if (split)
  {
    double ends[6] = { -box.min()[0], -box.min()[1], -box.min()[2], box.max()[0], box.max()[1], box.max()[2] };
    split->Max(ends, 6); // (the same exponent on every process; collective)
    box = Eigen::AlignedBox3d(Vec3(-ends[0], -ends[1], -ends[2]), Vec3(ends[3], ends[4], ends[5]));
  }
  const int e = FarScaleExponent(box);
  if (e == 0)
  {
    return SurfaceGraphOperatorsAtScale(topology, points, components, values, options, outputs, split);
  }
  const std::vector<double> scaled = PointsTimesPowerOfTwo(points, topology.NumberOfVertices(), -e);
  GraphOperatorOptions o = options;
  o.ContrastScale = std::ldexp(options.ContrastScale, -e); // (0, automatic, stays 0)
  GraphOperatorReport report =
    SurfaceGraphOperatorsAtScale(topology, scaled.data(), components, values, o, outputs, split);
  const std::size_t n = static_cast<std::size_t>(topology.NumberOfVertices());
  TimesPowerOfTwo(outputs.MeanCurvatureNormal, (3 + components) * n, -e);
  TimesPowerOfTwo(outputs.MeanCurvature, n, -e);
  TimesPowerOfTwo(outputs.BeltramiOperator, components * n, -2 * e);
  TimesPowerOfTwo(outputs.GaussianCurvature, n, -2 * e);
  report.ContrastScale = std::ldexp(report.ContrastScale, e);
  return report;
}

namespace
{

GraphOperatorReport SurfaceGraphOperatorsAtScale(const MeshTopology& topology, const double* points,
  int components, const double* values, const GraphOperatorOptions& options, const GraphOperatorOutputs& outputs,
  const Partition* split)
{
  GraphOperatorReport report;
  const Index size = topology.NumberOfVertices();
  std::vector<std::uint8_t> unusable(size);
  for (Index i = 0; i < size; ++i)
  {
    unusable[i] = topology.VertexFlags(i) != VertexRegular;
  }
  const std::vector<double> embedded = StartMesh(size, points, components, values, options, 5,
    [&]() { return MeanEdgeLength(topology, points, split); },
    [&]() {
      const auto& edges = topology.Graph();
      return EstimateGraphNoise(size, edges.NeighborOffsets.data(), edges.Neighbors.data(), points, components,
        values, unusable.data(), split);
    },
    report, split != nullptr);
  if (embedded.empty() || !report.Error.empty())
  {
    if (split && report.Error.empty())
    {
      report.UndefinedVertices = static_cast<Index>(split->Sum(0.0)); // the other processes' sum
      report.OverflowVertices = static_cast<Index>(split->Sum(0.0));
    }
    return report;
  }
  const int threads = options.NumberOfThreads, n = 3 + components;
  const double alpha = report.ContrastScale;
  std::vector<double> kn(embedded.size()), area(size), defect(size), base(size);
  ComputeBeltramiOperator(topology, embedded.data(), n, n, kn.data(), area.data(), defect.data(), threads);
  ComputeBeltramiOperator(topology, points, 3, 3, nullptr, base.data(), nullptr, threads);
  const Writer writer(outputs, 3, components, alpha, 2);
  double undefined = 0.0, overflowed = 0.0; // (split: at owned rows)
  for (Index i = 0; i < size; ++i)
  {
    if (unusable[i] || !(area[i] > 0.0) || !(base[i] > 0.0))
    {
      writer.Undefined(i);
      const bool owned = !split || split->IsOwned(i);
      undefined += owned;
      overflowed += owned && !unusable[i] && base[i] > 0.0; // (the data's doing: the surface has area there)
      continue;
    }
    writer.Defined(i, &kn[static_cast<std::size_t>(i) * n], defect[i] / area[i], base[i] / area[i]);
  }
  report.UndefinedVertices = static_cast<Index>(split ? split->Sum(undefined) : undefined);
  report.OverflowVertices = static_cast<Index>(split ? split->Sum(overflowed) : overflowed);
  return report;
}

} // namespace

GraphOperatorReport ComputeTetrahedralGraphOperators(const TetrahedralMesh& mesh, const double* points,
  int components, const double* values, const GraphOperatorOptions& options, const GraphOperatorOutputs& outputs,
  const Partition* split)
{
  GraphOperatorReport report;
  const Index size = mesh.NumberOfVertices();
  const std::vector<std::uint8_t> boundary = mesh.BoundaryVertices(); // (split: the rings' rims too)
  const std::vector<double> embedded = StartMesh(size, points, components, values, options, 6,
    [&]() { return mesh.MeanEdgeLength(points, split); },
    [&]() {
      return EstimateGraphNoise(size, mesh.NeighborOffsets().data(), mesh.Neighbors().data(), points, components,
        values, boundary.data(), split);
    },
    report, split != nullptr);
  if (embedded.empty() || !report.Error.empty())
  {
    if (split && report.Error.empty())
    {
      report.UndefinedVertices = static_cast<Index>(split->Sum(0.0)); // the other processes' sum
      report.OverflowVertices = static_cast<Index>(split->Sum(0.0));
    }
    return report;
  }
  const int threads = options.NumberOfThreads, n = 3 + components;
  const double alpha = report.ContrastScale;
  GraphLaplacian graph, base;
  AssembleTetrahedralLaplacian(mesh, embedded.data(), n, graph, threads);
  AssembleTetrahedralLaplacian(mesh, points, 3, base, threads);
  std::vector<double> kx(embedded.size()), k(n);
  graph.ApplyStiffness(embedded.data(), kx.data(), n, threads);
  const Writer writer(outputs, 3, components, alpha, 3);
  double undefined = 0.0, overflowed = 0.0; // (split: at owned rows)
  for (Index i = 0; i < size; ++i)
  {
    const double mass = graph.Mass[i];
    if (boundary[i] || !(mass > 0.0) || !(base.Mass[i] > 0.0))
    {
      writer.Undefined(i);
      const bool owned = !split || split->IsOwned(i);
      undefined += owned;
      overflowed += owned && !boundary[i] && base.Mass[i] > 0.0; // (the data's doing: the mesh has volume there)
      continue;
    }
    for (int a = 0; a < n; ++a)
    {
      k[a] = kx[static_cast<std::size_t>(i) * n + a] / mass;
    }
    writer.Defined(i, k.data(), std::numeric_limits<double>::quiet_NaN(), base.Mass[i] / mass);
  }
  report.UndefinedVertices = static_cast<Index>(split ? split->Sum(undefined) : undefined);
  report.OverflowVertices = static_cast<Index>(split ? split->Sum(overflowed) : overflowed);
  return report;
}

} // namespace beltrami
