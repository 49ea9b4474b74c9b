#include "Remeshing/SurfaceRemeshing.h"

#include "Flows/Fairing.h"
#include "Mesh/Curvatures.h"
#include "Mesh/Laplacian.h"
#include "Mesh/MeshMeasures.h"
#include "Mesh/SurfaceDistance.h"
#include "Remeshing/RemeshMetric.h"
#include "Solvers/SparseGraph.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <sstream>

namespace beltrami
{

namespace
{

double SecondsSince(std::chrono::steady_clock::time_point start)
{
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

} // namespace

AtlasOptions RemeshingAtlasOptions(double spacing)
{
  AtlasOptions options;
  options.ChartBoundary = ParameterizationBoundary::Natural;
  options.BalanceAreas = true;
  options.MaximumSqueezedShare = 0.3;
  options.MaximumStretchedShare = 0.3;
  options.MeasureDistortion = false;
  options.MinimumFeatureLength = spacing;
  return options;
}

double UniformSpacing(double area, std::int64_t count)
{
  return std::sqrt(2.0 * area / (std::sqrt(3.0) * static_cast<double>(std::max<std::int64_t>(1, count))));
}

std::vector<double> CurvatureValues(const MeshTopology& topology, const double* points, CurvatureMeasure measure,
  int numThreads)
{
  const std::size_t n = static_cast<std::size_t>(topology.NumberOfVertices());
  std::vector<double> h(n), k(n), k1(n), k2(n), values(n);
  CurvatureOptions options;
  options.NumberOfThreads = numThreads;
  CurvatureOutputs outputs;
  outputs.MeanCurvature = h.data();
  outputs.GaussianCurvature = k.data();
  outputs.MaximumCurvature = k1.data();
  outputs.MinimumCurvature = k2.data();
  ComputeCurvatures(topology, points, options, outputs);
  for (std::size_t v = 0; v < n; ++v)
  {
    switch (measure)
    {
      case CurvatureMeasure::MeanCurvature: values[v] = std::abs(h[v]); break;
      case CurvatureMeasure::GaussianCurvature: values[v] = std::abs(k[v]); break;
      case CurvatureMeasure::TotalCurvature: values[v] = k1[v] * k1[v] + k2[v] * k2[v]; break;
      case CurvatureMeasure::MaximumCurvature: values[v] = std::max(std::abs(k1[v]), std::abs(k2[v])); break;
    }
  }
  return values;
}

namespace
{

/// The piecewise-linear function through `pairs` (x, y; x ascending) at x.
double PiecewiseLinear(const std::vector<double>& pairs, double x)
{
  const std::size_t n = pairs.size() / 2;
  if (x <= pairs[0])
  {
    return pairs[1];
  }
  for (std::size_t k = 1; k < n; ++k)
  {
    if (x <= pairs[2 * k])
    {
      const double x0 = pairs[2 * k - 2], x1 = pairs[2 * k];
      const double t = x1 > x0 ? (x - x0) / (x1 - x0) : 1.0;
      return pairs[2 * k - 1] + t * (pairs[2 * k + 1] - pairs[2 * k - 1]);
    }
  }
  return pairs[2 * n - 1];
}

} // namespace

bool SmoothOverSurface(const MeshTopology& topology, const double* points, const GraphLaplacian& laplacian,
  double width, int steps, double tolerance, std::vector<double>& values, int numThreads, int columns)
{
  // Beyond the bounding-box diagonal the kernel is flat over the surface
  // already (and the steps' systems would only get harder to solve).
  Vec3 lo = Vec3::Constant(HUGE_VAL), hi = Vec3::Constant(-HUGE_VAL);
  for (Index v = 0; v < topology.NumberOfVertices(); ++v)
  {
    lo = lo.cwiseMin(Point(points, v));
    hi = hi.cwiseMax(Point(points, v));
  }
  width = std::min(width, (hi - lo).norm());
  // S = -M Laplace / 2 (Mesh/Laplacian), so (M + t S) u' = M u is an
  // implicit step of t / 2 of u_t = Laplace u; n of width^2 / n make the
  // variance width^2.
  ShiftedLaplacianProblem problem = laplacian.Problem(columns);
  problem.Shift = laplacian.Mass.data();
  problem.Factor = width * width / steps;
  problem.Tolerance = tolerance;
  problem.MaximumIterations = 1000 + 10 * topology.NumberOfVertices(); // a safety bound, far above the need
  problem.NumberOfThreads = numThreads;
  double largest = 1e-300; // (every column's size: the values as a whole)
  for (double value : values)
  {
    largest = std::max(largest, std::abs(value));
  }
  problem.Scale.assign(columns, largest);
  const std::size_t rows = values.size() / columns;
  std::vector<std::uint8_t> fixed(rows, 0);
  for (std::size_t v = 0; v < rows; ++v)
  {
    fixed[v] = !(laplacian.Mass[v] > 0.0); // no area: kept
  }
  problem.Fixed = fixed.data();
  const std::vector<Index> order =
    LocalityOrder(problem.Rows, problem.Offsets, problem.Neighbors); // once for all steps
  problem.Order = order.data();
  bool converged = true;
  std::vector<double> b(values.size());
  for (int step = 0; step < steps; ++step)
  {
    for (std::size_t i = 0; i < values.size(); ++i)
    {
      b[i] = fixed[i / columns] ? values[i] : laplacian.Mass[i / columns] * values[i];
    }
    converged = SolveShiftedLaplacian(problem, b.data(), values.data()).Converged && converged;
  }
  return converged;
}

ImportanceResult ImportanceFromValues(const MeshTopology& topology, const double* points,
  const std::vector<double>& values, const ImportanceOptions& options, int numThreads)
{
  double sum = 0.0;
  std::size_t finite = 0;
  for (double v : values)
  {
    if (std::isfinite(v))
    {
      sum += std::abs(v);
      ++finite;
    }
  }
  const double mean = finite > 0 ? sum / finite : 0.0;
  std::vector<std::pair<double, double>> knots; // the transfer function's finite points, by x
  for (std::size_t k = 0; k + 1 < options.TransferFunction.size(); k += 2)
  {
    if (std::isfinite(options.TransferFunction[k]) && std::isfinite(options.TransferFunction[k + 1]))
    {
      knots.emplace_back(options.TransferFunction[k], options.TransferFunction[k + 1]);
    }
  }
  std::stable_sort(knots.begin(), knots.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<double> pairs;
  for (const auto& [x, y] : knots)
  {
    pairs.insert(pairs.end(), { x, y });
  }
  const bool table = !pairs.empty();
  ImportanceResult out;
  out.Importance.assign(values.size(), 1.0);
  for (std::size_t i = 0; i < values.size(); ++i)
  {
    const double relative = std::isfinite(values[i]) && mean > 0.0 ? std::abs(values[i]) / mean : 1.0;
    const double f = table ? PiecewiseLinear(pairs, relative) : std::pow(relative, options.Gamma);
    out.Importance[i] = std::isfinite(f) ? std::max(0.0, f) : 1.0;
  }
  if (options.Gradation > 0.0)
  {
    GraphLaplacian laplacian;
    AssembleSurfaceLaplacian(topology, points, LaplacianWeights::Cotangent, laplacian, numThreads);
    // (A density needs no more than a residual reduction of 1e-4 per step:
    // at 1e-8 the 8 steps on bunny Loop x2 took 809 Jacobi iterations, the
    // whole remesh to 100k vertices 13.2-15.6 s against 11.6-12.2 s now.)
    if (!SmoothOverSurface(topology, points, laplacian, options.Gradation, 8, 1e-4, out.Importance, numThreads))
    {
      out.Warning = "the gradation's solve did not converge";
    }
  }
  for (double& importance : out.Importance)
  {
    importance = std::max(options.Minimum, std::max(0.0, importance));
  }
  return out;
}

std::vector<double> RaiseImportanceForSag(const MeshTopology& topology, const double* points,
  const double* importance, const std::vector<double>& maximumCurvature, const std::uint8_t* featureEdges,
  std::int64_t count, double sag, int numThreads, const GraphLaplacian* surfaceLaplacian)
{
  const std::size_t n = static_cast<std::size_t>(topology.NumberOfVertices());
  if (!(sag > 0.0) || count <= 0 || maximumCurvature.size() != n)
  {
    return {};
  }
  GraphLaplacian assembled;
  if (!surfaceLaplacian)
  {
    AssembleSurfaceLaplacian(topology, points, LaplacianWeights::Cotangent, assembled, numThreads);
  }
  const GraphLaplacian& laplacian = surfaceLaplacian ? *surfaceLaplacian : assembled;
  const auto at = [&](std::size_t v) { return importance ? importance[v] : 1.0; };
  double integral = 0.0; // of the importance over the surface
  for (std::size_t v = 0; v < n; ++v)
  {
    integral += laplacian.Mass[v] * at(v);
  }
  // Samples per unit area where the importance is 1; the spacing of a
  // density d is 1 / sqrt(d).
  const double density = static_cast<double>(count) / integral;
  if (!(density > 0.0) || !std::isfinite(density))
  {
    return {};
  }
  std::vector<std::uint8_t> onFeature(featureEdges ? n : 0, 0);
  for (std::int64_t e = 0; featureEdges && e < topology.Edges().NumberOfEdges(); ++e)
  {
    if (featureEdges[e])
    {
      onFeature[topology.Edges().Vertices[2 * e]] = onFeature[topology.Edges().Vertices[2 * e + 1]] = 1;
    }
  }
  const MeshTopology::VertexGraph& graph = topology.Graph();
  std::vector<double> factor(n, 1.0);
  bool raised = false;
  for (std::size_t v = 0; v < n; ++v)
  {
    const bool counts = std::isfinite(maximumCurvature[v]) && !(featureEdges && onFeature[v]);
    const double kappa = counts ? maximumCurvature[v] : 0.0;
    const double spacing = at(v) > 0.0 ? 1.0 / std::sqrt(density * at(v)) : 0.0;
    factor[v] = std::max(1.0, kappa * spacing / (8.0 * sag));
    if (factor[v] > 1.0)
    {
      // No finer than the input's own edges there: the remesh lies on the
      // input, whose facets are flat, and at a spike's long edges the
      // curvature is the tip's, which no spacing follows.
      double longest = 0.0;
      for (std::int64_t k = graph.NeighborOffsets[v]; k < graph.NeighborOffsets[v + 1]; ++k)
      {
        longest = std::max(longest, (Point(points, static_cast<Index>(v)) - Point(points, graph.Neighbors[k])).norm());
      }
      factor[v] = longest > 0.0 ? std::max(1.0, std::min(factor[v], spacing * spacing / (longest * longest))) : 1.0;
    }
    raised = raised || factor[v] > 1.0;
  }
  if (!raised)
  {
    return {};
  }
  // Without the spread the raised spots are single vertices of a scan's
  // bumps, and the remesh's edge lengths vary more than the fidelity gains.
  // One coarse step: the kernel's exact shape does not matter here (the
  // 1.2M-triangle bunny to 100k: 0.25-0.35 s; eight steps to 1e-8 would
  // take seconds).
  SmoothOverSurface(topology, points, laplacian, 1.0 / std::sqrt(density), 1, 1e-2, factor, numThreads);
  raised = false;
  for (std::size_t v = 0; v < n; ++v)
  {
    raised = raised || factor[v] > 1.0;
    factor[v] = at(v) * std::max(1.0, factor[v]);
  }
  return raised ? factor : std::vector<double>();
}

namespace
{

/// "a -> b" where the remesh's count differs from the input's.
void CompareCount(const char* what, std::int64_t input, std::int64_t remesh, std::string& differences)
{
  if (input != remesh)
  {
    differences += (differences.empty() ? "" : ", ") + std::string(what) + " " + std::to_string(input) + " -> " +
      std::to_string(remesh);
  }
}

/// The surface's largest principal curvatures and cotangent Laplacian in
/// `cache` (computed once per surface).
void KeepCurvatures(const MeshTopology& topology, const double* points, int numThreads, RemeshCache& cache)
{
  if (cache.MaximumCurvature.size() != static_cast<std::size_t>(topology.NumberOfVertices()))
  {
    cache.MaximumCurvature = CurvatureValues(topology, points, CurvatureMeasure::MaximumCurvature, numThreads);
    AssembleSurfaceLaplacian(topology, points, LaplacianWeights::Cotangent, cache.SurfaceLaplacian, numThreads);
  }
}

/// The vertex count whose equilateral triangles keep within `bound` of a
/// surface of largest principal curvatures `kappa` (per vertex, areas
/// `mass`): a triangle of spacing s has its centre about kappa s^2 / 6 from
/// the surface, and s^2 = 6 bound / kappa holds 2 / (sqrt(3) s^2) vertices a
/// unit area; with a margin of 1.3 for the remesh's uneven edges.
std::int64_t CountForDeviation(const LargeVector<double>& mass, const std::vector<double>& kappa, double bound)
{
  double needed = 0.0;
  for (std::size_t v = 0; v < kappa.size(); ++v)
  {
    const double k = std::isfinite(kappa[v]) ? kappa[v] : 0.0;
    needed += mass[v] * 1.3 * 2.0 * k / (std::sqrt(3.0) * 6.0 * bound);
  }
  return static_cast<std::int64_t>(std::ceil(needed));
}

/// `values` replaced by their largest over each vertex's `rings`-ring.
void DilateOverRings(const MeshTopology& topology, int rings, std::vector<double>& values)
{
  const MeshTopology::VertexGraph& graph = topology.Graph();
  std::vector<double> next(values.size());
  for (int r = 0; r < rings; ++r)
  {
    for (std::size_t v = 0; v < values.size(); ++v)
    {
      next[v] = values[v];
      for (std::int64_t k = graph.NeighborOffsets[v]; k < graph.NeighborOffsets[v + 1]; ++k)
      {
        next[v] = std::max(next[v], values[graph.Neighbors[k]]);
      }
    }
    values.swap(next);
  }
}

/// The remesh's deviation at every input vertex: its distance to the
/// remesh, and the distance to the input of the centre of every remesh
/// triangle that a corner of lies on one of the vertex's triangles (a
/// triangle that spans a gap; the largest of those).  Every input vertex
/// farther than `pin` from the remesh that is the farthest of its 1-ring
/// (a cone point of the input between the remesh's vertices) is flagged in
/// `pinned`.
std::vector<double> LocalDeviations(const MeshTopology& topology, const double* points, const TriangleGrid& toInput,
  const RemeshResult& remesh, double pin, std::vector<std::uint8_t>& pinned, int numThreads)
{
  const std::size_t triangles = remesh.Triangles.size() / 3;
  const TriangleGrid toRemesh(remesh.Points.data(), remesh.Triangles.data(), triangles, numThreads);
  std::vector<double> deviation(static_cast<std::size_t>(topology.NumberOfVertices()), 0.0);
  ParallelFor(topology.NumberOfVertices(), numThreads, [&](std::int64_t begin, std::int64_t end) {
    for (Index v = static_cast<Index>(begin); v < end; ++v)
    {
      deviation[v] = topology.Valence(v) > 0 ? toRemesh.Distance(Point(points, v)) : 0.0;
    }
  });
  const MeshTopology::VertexGraph& graph = topology.Graph();
  for (Index v = 0; v < topology.NumberOfVertices(); ++v)
  {
    bool farthest = deviation[v] > pin;
    for (std::int64_t k = graph.NeighborOffsets[v]; farthest && k < graph.NeighborOffsets[v + 1]; ++k)
    {
      farthest = deviation[graph.Neighbors[k]] <= deviation[v];
    }
    pinned[v] = pinned[v] || farthest;
  }
  std::vector<double> centre(triangles);
  ParallelFor(static_cast<std::int64_t>(triangles), numThreads, [&](std::int64_t begin, std::int64_t end) {
    for (std::int64_t t = begin; t < end; ++t)
    {
      const Index* c = remesh.Triangles.data() + 3 * t;
      centre[t] = toInput.Distance(
        (Point(remesh.Points.data(), c[0]) + Point(remesh.Points.data(), c[1]) + Point(remesh.Points.data(), c[2])) /
        3.0);
    }
  });
  const IndexArray& input = topology.TriangleList();
  for (std::size_t t = 0; t < triangles; ++t)
  {
    for (int k = 0; k < 3; ++k)
    {
      const Index source = remesh.SourceTriangle[remesh.Triangles[3 * t + k]];
      for (int j = 0; source >= 0 && j < 3; ++j)
      {
        double& d = deviation[input[3 * static_cast<std::size_t>(source) + j]];
        d = std::max(d, centre[t]);
      }
    }
  }
  return deviation;
}

/// RaiseWhereFar's power of the ratio of the deviation to its target where
/// the remesh's spacing is longer than the input's edges: a little beyond
/// the ratio of a smooth surface's sag (a small raised spot moves the
/// samples of error diffusion less than its share of the count).  Where
/// the spacing is shorter, the square: with 1.5 throughout, fandisk_large
/// decimated to a tenth (remeshed at 0.5% of the diagonal with 5,000-8,500
/// vertices, its input 2,600) stayed beyond the bound for 8 rounds, the
/// count growing by the least tenth each; with the square throughout, the
/// error-driven remesh of a fine cylinder at 0.05% took twice the vertices.
constexpr double LocalRaise = 1.5;

/// The input's lengths RaiseWhereFar compares the remesh with, measured
/// once for every round: its mean edge, per vertex the mean length of its
/// edges (0 at a vertex in none), and its area.
struct InputScales
{
  double MeanEdge = 0.0;
  std::vector<double> VertexEdges;
  double Area = 0.0;
};

/// InputScales::VertexEdges.
std::vector<double> MeanEdgeAtVertices(const MeshTopology& topology, const double* points)
{
  const MeshTopology::EdgeTable& e = topology.Edges();
  std::vector<double> sum(static_cast<std::size_t>(topology.NumberOfVertices()), 0.0), count(sum.size(), 0.0);
  for (std::int64_t k = 0; k < e.NumberOfEdges(); ++k)
  {
    const Index a = e.Vertices[2 * k], b = e.Vertices[2 * k + 1];
    const double length = (Point(points, a) - Point(points, b)).norm();
    sum[a] += length;
    sum[b] += length;
    count[a] += 1.0;
    count[b] += 1.0;
  }
  for (std::size_t v = 0; v < sum.size(); ++v)
  {
    sum[v] = count[v] > 0.0 ? sum[v] / count[v] : 0.0;
  }
  return sum;
}

/// The next remesh's weights and count after one that left the input
/// farther than `bound`, aiming at three quarters of it (each remesh's
/// vertices fall elsewhere: its deviation varies by 10-20%).  Where the
/// remesh's spacing is longer than the input's edges the deviation falls
/// with the square of the spacing (the sag of a smooth surface), where it
/// is shorter only with the spacing (the input is a polyhedron at that
/// scale: its edges are creases the remesh cuts): the density (`weight`,
/// whose integral over the surface is `integral`) is raised by the ratio to
/// the power 1.5 or 2 (LocalRaise) wherever the input is left farther
/// within about two spacings (the input's vertices sample the remesh's sag
/// unevenly: most lie near its vertices), and the count with the integral,
/// by a tenth at least (a small raised
/// spot moves the count less than the remeshes' deviation varies, and the
/// rounds would creep); where no input vertex is (the remesh's triangles
/// are the far ones), the count alone.  At most `most`.  The input's cone
/// points farther than the bound are pinned (LocalDeviations; pinned from
/// three quarters of it, they cost more vertices than they save).
std::int64_t RaiseWhereFar(const MeshTopology& topology, const double* points, const TriangleGrid& toInput,
  const RemeshResult& remesh,
  const LargeVector<double>& mass, const InputScales& input, double bound, double worst, std::int64_t count,
  std::int64_t most, std::vector<double>& weight, double& integral, std::vector<std::uint8_t>& pinned, int numThreads)
{
  const double target = 0.75 * bound;
  std::vector<double> factor = LocalDeviations(topology, points, toInput, remesh, bound, pinned, numThreads);
  const int rings =
    static_cast<int>(std::min(32.0, std::ceil(2.0 * remesh.Spacing / std::max(input.MeanEdge, 1e-300))));
  DilateOverRings(topology, rings, factor);
  bool raised = false;
  for (std::size_t v = 0; v < factor.size(); ++v)
  {
    double& f = factor[v];
    const double spacing = remesh.Spacing * std::sqrt(integral / std::max(input.Area * weight[v], 1e-300));
    f = f > target ? std::min(16.0, std::pow(f / target, spacing < input.VertexEdges[v] ? 2.0 : LocalRaise)) : 1.0;
    raised = raised || f > 1.0;
  }
  double growth = std::min(4.0, worst / target);
  if (raised)
  {
    double raisedIntegral = 0.0;
    for (std::size_t v = 0; v < weight.size(); ++v)
    {
      weight[v] *= factor[v];
      raisedIntegral += mass[v] * weight[v];
    }
    growth = std::min(4.0, raisedIntegral / integral);
    integral = raisedIntegral;
  }
  return std::min(static_cast<std::int64_t>(std::ceil(static_cast<double>(count) * std::max(1.1, growth))), most);
}

/// The remesh made on a smoothed copy moved onto options.FinalSurface
/// (RemeshOptions::FinalSurface) and its triangles shaped there by
/// stitching rounds alone.
void ShapeOnFinalSurface(const MeshTopology& topology, const AtlasResult& atlas, const RemeshOptions& options,
  const SurfaceSamples& samples, RemeshOptimizationOptions optimization, Remesh& remesh)
{
  for (Index v = 0; v < remesh.Mesh.NumberOfVertices(); ++v)
  {
    remesh.Mesh.SetPosition(v, SurfacePoint(topology, options.FinalSurface, remesh.Triangle[v], &remesh.Barycentric[3 * v]));
  }
  RemeshCache local;
  optimization.Iterations = 0;
  optimization.StitchingIterations = options.FinalIterations;
  optimization.Cache = options.FinalCache ? options.FinalCache : &local;
  OptimizeRemesh(remesh, topology, options.FinalSurface, atlas, samples, optimization);
}

} // namespace

TriangleQuality RemeshQuality(const RemeshResult& r, int numThreads)
{
  const MeshTopology t(static_cast<Index>(r.Points.size() / 3), IndexArray(r.Triangles.begin(), r.Triangles.end()),
    numThreads);
  return MeasureTriangleQuality(t, r.Points.data());
}

namespace
{

/// AsGoodTriangles' rule on (smallest angle, share below 30 degrees).
bool AsGood(double angle, double below30, double firstAngle, double firstBelow30)
{
  const bool withinBar = angle >= 15.0 && below30 <= 0.005;
  return withinBar || (angle >= std::min(firstAngle, 15.0) && below30 <= firstBelow30 + 1e-3);
}

/// A remesh's smallest angle and share of angles below 30 degrees, measured
/// in its metric where it has one (an anisotropic remesh's triangles are
/// long and thin by design: measured in space, its fidelity rounds were
/// never kept).
std::pair<double, double> ShapeFigures(
  const MeshTopology& topology, const double* points, const RemeshResult& r, int numThreads)
{
  if (r.GradedMetric.empty())
  {
    const TriangleQuality q = RemeshQuality(r, numThreads);
    return { q.MinimumAngle, q.FractionBelow30 };
  }
  const MetricQuality q = MeasureInMetric(
    topology, points, r.GradedMetric.data(), r.Points, r.Triangles, r.SourceTriangle, r.SourceBarycentric);
  return { q.MinimumAngle, q.TrianglesBelow30 };
}

} // namespace

bool AsGoodTriangles(const RemeshResult& second, const RemeshResult& first, int numThreads)
{
  const TriangleQuality a = RemeshQuality(first, numThreads), b = RemeshQuality(second, numThreads);
  return AsGood(b.MinimumAngle, b.FractionBelow30, a.MinimumAngle, a.FractionBelow30);
}

void CheckFidelity(const MeshTopology& topology, const double* points, const RemeshOptions& options, RemeshResult& out)
{
  const MeshTopology remesh(static_cast<Index>(out.Points.size() / 3),
    IndexArray(out.Triangles.begin(), out.Triangles.end()), options.NumberOfThreads);
  const TopologySummary &a = topology.Summary(), &b = remesh.Summary();
  std::string differences;
  CompareCount("Euler characteristic", a.EulerCharacteristic, b.EulerCharacteristic, differences);
  CompareCount("components", topology.CountComponents(), remesh.CountComponents(), differences);
  CompareCount("boundary loops", a.NumberOfBoundaryLoops, b.NumberOfBoundaryLoops, differences);
  if (!b.IsManifold() || !b.IsOriented() || remesh.NumberOfDroppedTriangles() > 0)
  {
    differences += (differences.empty() ? "" : ", ") + std::string("not a manifold, oriented mesh");
  }
  const double diagonal = UsedBoundingBoxDiagonal(points, topology.TriangleList().data(), topology.NumberOfTriangles());
  const SurfaceDeviation deviation = MeasureDeviation(points, topology.TriangleList().data(),
    topology.NumberOfTriangles(), DeviationSamples::Vertices, out.Points.data(), out.Triangles.data(),
    out.Triangles.size() / 3, DeviationSamples::Centres, options.NumberOfThreads);
  const double scale = diagonal > 0.0 ? diagonal : 1.0;
  out.Diagonal = diagonal;
  out.DeviationFromInput = deviation.FirstToSecond / scale;
  out.DeviationToInput = deviation.SecondToFirst / scale;
  out.FarthestInputPoint = deviation.FarthestOfFirst;
  out.Spacing = UniformSpacing(SurfaceArea(topology, points, options.NumberOfThreads), options.NumberOfVertices);
  if (!differences.empty())
  {
    out.Error = "the remesh does not keep the input's topology (" + differences + ")";
  }
  else if (deviation.FirstToSecond > LostPartSpacings * out.Spacing)
  {
    // Not a coarse remesh but a part cut off or bridged (a limb's end):
    // a mesh without it would pass for the input.
    std::ostringstream said;
    said << "a part of the input is lost: the input point (" << out.FarthestInputPoint[0] << ", "
         << out.FarthestInputPoint[1] << ", " << out.FarthestInputPoint[2] << ") is " << deviation.FirstToSecond
         << " from the remesh, " << deviation.FirstToSecond / out.Spacing << " times its spacing";
    out.Error = said.str();
  }
}

namespace
{

RemeshResult RemeshOnce(const MeshTopology& topology, const double* points, const AtlasResult& atlas,
  const double* importance, const RemeshOptions& options)
{
  RemeshResult out;
  const Index n = topology.NumberOfVertices();
  if (importance && n > 0 && importance[0] > 0.0 &&
    std::all_of(importance, importance + n, [&](double value) { return value == importance[0]; }))
  {
    importance = nullptr; // a constant importance is the uniform density: the uniform remesh, exactly
  }
  RemeshCache local; // one run's locators shared by its stages, where the caller keeps none
  RemeshCache* cache = options.Cache ? options.Cache : &local;
  auto start = std::chrono::steady_clock::now();
  // The atlas's feature lines where it split at them, else the sharp edges.
  const bool splitAtFeatures = !atlas.FeatureEdges.empty();
  const std::vector<std::uint8_t> sharp = options.FeatureAngle > 0.0 && !splitAtFeatures
    ? SharpEdges(topology, points, options.FeatureAngle)
    : std::vector<std::uint8_t>();
  const std::uint8_t* features =
    options.FeatureAngle <= 0.0 ? nullptr : splitAtFeatures ? atlas.FeatureEdges.data() : sharp.data();
  std::vector<double> density, raised;
  const double* metric = nullptr;
  if (options.Metric)
  {
    out.GradedMetric.assign(options.Metric, options.Metric + 6 * static_cast<std::size_t>(n));
    RaiseMetricOnKeptLines(topology, points, features, out.GradedMetric);
    if (options.MetricGradation > 0.0)
    {
      KeepCurvatures(topology, points, options.NumberOfThreads, *cache);
      GradeMetric(topology, points, cache->SurfaceLaplacian,
        options.MetricGradation * UniformSpacing(SurfaceArea(topology, points, options.NumberOfThreads),
                                    options.NumberOfVertices),
        out.GradedMetric, options.NumberOfThreads);
    }
    metric = out.GradedMetric.data();
    density = MetricDensities(metric, n);
    for (Index v = 0; importance && v < n; ++v)
    {
      density[v] *= std::max(0.0, importance[v]);
    }
    importance = density.data();
  }
  if (options.MaximumSurfaceSag > 0.0)
  {
    KeepCurvatures(topology, points, options.NumberOfThreads, *cache);
    raised = RaiseImportanceForSag(topology, points, importance,
      metric ? ShortestEdgeCurvatures(metric, cache->MaximumCurvature) : cache->MaximumCurvature,
      features, options.NumberOfVertices, options.MaximumSurfaceSag, options.NumberOfThreads,
      &cache->SurfaceLaplacian);
    importance = raised.empty() ? importance : raised.data();
  }
  SamplingOptions sampling;
  sampling.FeatureEdges = features;
  sampling.NumberOfSamples = options.NumberOfVertices;
  sampling.Resolution = options.Resolution;
  sampling.MaximumLineSag = options.MaximumLineSag;
  sampling.Metric = metric;
  sampling.PinnedVertices = options.PinnedVertices;
  sampling.NumberOfThreads = options.NumberOfThreads;
  sampling.Cache = cache;
  out.Samples = SampleSurface(topology, points, atlas, importance, sampling);
  out.SamplingSeconds = SecondsSince(start);
  if (!out.Samples.Error.empty())
  {
    out.Error = out.Samples.Error;
    return out;
  }
  start = std::chrono::steady_clock::now();
  Remesh remesh = CreateRemesh(topology, points, atlas, out.Samples, options.NumberOfThreads, cache);
  out.TriangulationSeconds = SecondsSince(start);
  if (!remesh.Error.empty())
  {
    out.Error = remesh.Error;
    return out;
  }
  start = std::chrono::steady_clock::now();
  RemeshOptimizationOptions optimization;
  optimization.Iterations = options.Iterations;
  optimization.StitchingIterations = options.StitchingIterations;
  optimization.OverRelaxation = options.OverRelaxation;
  optimization.NumberOfThreads = options.NumberOfThreads;
  optimization.Importance = importance;
  optimization.Metric = metric;
  optimization.FeatureEdges = features;
  optimization.PinnedVertices = options.PinnedVertices;
  optimization.MaximumLineSag = options.MaximumLineSag;
  optimization.Cache = cache;
  out.Optimization = OptimizeRemesh(remesh, topology, points, atlas, out.Samples, optimization);
  out.OptimizationSeconds = SecondsSince(start);
  out.Points = remesh.Mesh.Points();
  out.Triangles = remesh.Mesh.Triangles();
  start = std::chrono::steady_clock::now();
  CheckFidelity(topology, points, options, out);
  out.FidelitySeconds = SecondsSince(start);
  if (options.FinalSurface)
  {
    start = std::chrono::steady_clock::now();
    ShapeOnFinalSurface(topology, atlas, options, out.Samples, optimization, remesh);
    out.Points = remesh.Mesh.Points();
    out.Triangles = remesh.Mesh.Triangles();
    out.OptimizationSeconds += SecondsSince(start);
  }
  out.SourceTriangle = std::move(remesh.Triangle);
  out.SourceBarycentric = std::move(remesh.Barycentric);
  return out;
}

} // namespace

double WorstDeviation(const RemeshResult& r)
{
  return std::max(r.DeviationToInput, r.DeviationFromInput);
}

namespace
{

/// `kept` with the times of `other` added (the time both took).
void AddTimes(RemeshResult& kept, const RemeshResult& other)
{
  kept.SamplingSeconds += other.SamplingSeconds;
  kept.TriangulationSeconds += other.TriangulationSeconds;
  kept.OptimizationSeconds += other.OptimizationSeconds;
  kept.FidelitySeconds += other.FidelitySeconds;
}

} // namespace

/// One remesh, then up to FarPinRounds more, each with the input vertices
/// the closest remesh so far leaves farther than FarPinSpacings spacings
/// pinned too (the pins of the rounds before kept); the closest kept, its
/// triangles within the bar or as good as the first's (AsGoodTriangles'
/// rule, in the metric for an anisotropic remesh: ShapeFigures).
/// (Over the corpus and generated shapes at 2,000 and 10,000 vertices, with
/// one round at 0.35 spacings the second was made on 51 of 98 and kept on
/// 13; with up to three at 0.15 the two-sided deviation fell by 5% in
/// geometric mean at 2,000 and 8% at 10,000, by a quarter to a half on
/// cow, elephant, nefertiti, patch-01, three_peaks and the double cone, in
/// 1.6-1.8 times the time.)
RemeshResult RemeshSurface(const MeshTopology& topology, const double* points, const AtlasResult& atlas,
  const double* importance, const RemeshOptions& options)
{
  RemeshResult best = RemeshOnce(topology, points, atlas, importance, options);
  const SurfaceSamples& samples = best.Samples;
  if (!best.Error.empty() && samples.ChartsWithoutSample > 0)
  {
    // (Many specks of an isosurface at a count their charts' boundaries
    // nearly take: charts without a sample inside made the same triangles.)
    best.Error = "the chart boundaries need " + std::to_string(samples.BoundarySamples) + " samples and each of the " +
      std::to_string(atlas.Charts.size()) + " charts one inside (" + std::to_string(samples.ChartsWithoutSample) +
      " have none): " + std::to_string(samples.NeededSamples) + ", more than the " +
      std::to_string(options.NumberOfVertices) + " requested (" + best.Error + ")";
  }
  if (options.FarPinSpacings <= 0.0 || options.PinnedVertices || options.FinalSurface || !best.Error.empty())
  {
    return best;
  }
  const TriangleGrid toInput(
    points, topology.TriangleList().data(), topology.NumberOfTriangles(), options.NumberOfThreads);
  std::vector<std::uint8_t> pinned(static_cast<std::size_t>(topology.NumberOfVertices()), 0);
  std::ptrdiff_t count = 0; // of the pinned vertices
  const auto first = ShapeFigures(topology, points, best, options.NumberOfThreads); // (the rounds' bar)
  for (int round = 0; round < options.FarPinRounds; ++round)
  {
    LocalDeviations(
      topology, points, toInput, best, options.FarPinSpacings * best.Spacing, pinned, options.NumberOfThreads);
    const std::ptrdiff_t now = std::count(pinned.begin(), pinned.end(), std::uint8_t(1));
    if (now == count)
    {
      break; // (no new vertex to pin)
    }
    count = now;
    RemeshOptions again = options;
    again.PinnedVertices = pinned.data();
    RemeshResult next = RemeshOnce(topology, points, atlas, importance, again);
    bool closer = next.Error.empty() && WorstDeviation(next) < FarPinGain * WorstDeviation(best);
    if (closer)
    {
      const auto figures = ShapeFigures(topology, points, next, options.NumberOfThreads);
      closer = AsGood(figures.first, figures.second, first.first, first.second);
    }
    AddTimes(closer ? next : best, closer ? best : next);
    if (!closer)
    {
      break;
    }
    best = std::move(next);
  }
  return best;
}

DeviationRemeshResult RemeshToDeviation(const MeshTopology& topology, const double* points, const AtlasResult& atlas,
  const double* importance, const RemeshOptions& options, double maximumDeviation, int maximumRounds)
{
  DeviationRemeshResult out;
  const std::size_t n = static_cast<std::size_t>(topology.NumberOfVertices());
  RemeshCache local;
  RemeshCache* cache = options.Cache ? options.Cache : &local;
  KeepCurvatures(topology, points, options.NumberOfThreads, *cache);
  const LargeVector<double>& mass = cache->SurfaceLaplacian.Mass;
  const double diagonal = UsedBoundingBoxDiagonal(points, topology.TriangleList().data(), topology.NumberOfTriangles());
  const double bound = maximumDeviation * diagonal;
  std::vector<double> weight(n, 1.0);
  double integral = 0.0; // of the weight over the surface
  for (std::size_t v = 0; v < n; ++v)
  {
    weight[v] = importance ? importance[v] : 1.0;
    integral += mass[v] * weight[v];
  }
  std::int64_t count = options.NumberOfVertices;
  if (count <= 0)
  {
    // (With a metric in curvature's units, its density is the curvature
    // the isotropic estimate uses: sqrt(kappa_1 kappa_2) where it is
    // anisotropic.)
    count = std::max<std::int64_t>(100,
      CountForDeviation(mass,
        options.Metric ? MetricDensities(options.Metric, static_cast<Index>(n)) : cache->MaximumCurvature, bound));
  }
  const InputScales input{ MeanEdgeLength(topology, points), MeanEdgeAtVertices(topology, points),
    std::accumulate(mass.begin(), mass.end(), 0.0) };
  // The input's grid, once for every round (its triangles stay).
  const TriangleGrid toInput(points, topology.TriangleList().data(), topology.NumberOfTriangles(), options.NumberOfThreads);
  std::vector<std::uint8_t> pinned(n, 0); // where a remesh left the input farthest
  RemeshOptions round = options;
  round.Cache = cache;
  round.PinnedVertices = pinned.data();
  int failures = 0, stalled = 0, doublings = 0;
  double closest = HUGE_VAL;
  for (int r = 0; r < maximumRounds && !out.Met; ++r)
  {
    round.NumberOfVertices = count;
    out.Counts.push_back(count);
    out.Remesh = RemeshSurface(topology, points, atlas, weight.data(), round);
    out.Rounds = r + 1;
    if (!out.Remesh.Error.empty())
    {
      // The chart boundaries (and a sample inside each chart) need more
      // samples, or a thin part was lost (tried twice more with twice the
      // count: beyond, more vertices fail as these did).
      const SurfaceSamples& samples = out.Remesh.Samples;
      const bool boundaries = samples.BoundarySamples >= count || samples.ChartsWithoutSample > 0;
      if (!boundaries && ++failures > 2)
      {
        break;
      }
      count = 2 * std::max(count, samples.BoundarySamples >= count ? samples.BoundarySamples : samples.NeededSamples);
      continue;
    }
    const double worst = std::max(out.Remesh.DeviationToInput, out.Remesh.DeviationFromInput) * diagonal;
    out.Met = worst <= bound;
    // More vertices where it is far that do not bring the remesh closer
    // (twice in a row: a thin part split along its length by a seam, whose
    // halves are narrower than the band the halftone leaves beside the
    // seams) take twice the count everywhere, twice at most; beyond, or
    // beyond what the input's resolution can use, the last remesh stands
    // (Met says it missed).
    stalled = worst > 0.95 * closest ? stalled + 1 : 0;
    closest = std::min(closest, worst);
    const std::int64_t most = MostVerticesPerInputVertex * static_cast<std::int64_t>(n);
    if (out.Met || (stalled >= 2 && ++doublings > 2) || count >= most)
    {
      break;
    }
    if (stalled >= 2)
    {
      count = std::min(2 * count, most);
      stalled = 0;
      continue;
    }
    // With a metric, whose lengths keep the deviation even, the count
    // alone, by the ratio of the deviation to 0.85 of the bound (a tenth
    // more at least), and the input's vertices left farthest pinned (a
    // comb's fingers, a thin handle): raised spots took the density from
    // elsewhere and drew the remesh no closer on a blade's rims, where the
    // far part is long, or on fandisk (its error-driven remesh at 0.1% of
    // the diagonal took 8,343 vertices so, 4,286 now).
    if (options.Metric)
    {
      LocalDeviations(topology, points, toInput, out.Remesh, bound, pinned, options.NumberOfThreads);
      count = std::min(most, static_cast<std::int64_t>(std::ceil(
                               static_cast<double>(count) * std::clamp(worst / (0.85 * bound), 1.1, 4.0))));
    }
    else
    {
      count = RaiseWhereFar(topology, points, toInput, out.Remesh, mass, input, bound, worst, count, most, weight,
        integral, pinned, options.NumberOfThreads);
    }
  }
  return out;
}

} // namespace beltrami
