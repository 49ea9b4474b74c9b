#include "Remeshing/SurfaceRemeshing.h"

#include "Flows/Fairing.h"
#include "Mesh/Curvatures.h"
#include "Mesh/Laplacian.h"
#include "Mesh/MeshMeasures.h"
#include "Mesh/SurfaceDistance.h"
#include "Remeshing/RemeshFidelity.h"
#include "Remeshing/RemeshMetric.h"
#include "Solvers/SparseGraph.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <queue>
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
  // (The corpus's and the generated shapes' longest charts: 83 times longer
  // than wide, a needle's of the spiky sphere.)
  options.MaximumChartAspect = 100.0;
  options.MeasureDistortion = false;
  options.MinimumFeatureLength = spacing;
  options.LongestFeatureGap = spacing;
  // (Creases that fade out followed to half the feature angle: fandisk's
  // remesh at 10,000 vertices cut one 0.19% of the diagonal from the input,
  // CGAL's 0.17%; followed 0.14%.  Over the corpus's CAD parts and the
  // generated ones at 2,000 and 10,000 vertices, the larger of the two
  // deviations 0.90 times as large in geometric mean (0.69-1.0), none
  // further; 15 or 45 degrees of turn instead of 30 changed single cases
  // either way.)
  options.MostFeatureTurn = 30.0;
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
  // A safety bound far above the need (bunny00's steps take 15 iterations,
  // the 1.2M-triangle bunny's about 100), short of the input's size: where
  // triangles beside a fold are slivers of next to no area, their cotangents
  // make the system so ill-conditioned that a bunny with 75 triangles
  // flattened ran 378,060 iterations (100 s) without converging; the
  // callers take the values as they are then, or say it did not converge.
  problem.MaximumIterations =
    static_cast<int>(std::min<double>(1000.0 + 10.0 * topology.NumberOfVertices(), 2000.0 + 10.0 * std::sqrt(
      static_cast<double>(topology.NumberOfVertices()))));
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

std::vector<double> GradedImportance(const MeshTopology& topology, const double* points, const double* importance,
  std::int64_t count, double growth, int numThreads, RemeshCache& cache)
{
  const std::size_t n = static_cast<std::size_t>(topology.NumberOfVertices());
  const auto [least, most] = std::minmax_element(importance, importance + n);
  if (n == 0 || count <= 0 || !(growth > 0.0) || !(*most > *least) || !(*least > 0.0))
  {
    return {};
  }
  KeepCurvatures(topology, points, numThreads, cache);
  const GraphLaplacian& graph = cache.SurfaceLaplacian;
  double integral = 0.0;
  for (std::size_t v = 0; v < n; ++v)
  {
    integral += graph.Mass[v] * importance[v];
  }
  // The spacing of equilateral triangles at the density count I / integral,
  // lowered where a neighbour's plus growth times the distance is less
  // (Dijkstra's order: each vertex final when it is the least left).
  std::vector<double> spacing(n);
  using Entry = std::pair<double, Index>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> queue;
  for (std::size_t v = 0; v < n; ++v)
  {
    spacing[v] = std::sqrt(2.0 * integral / (std::sqrt(3.0) * static_cast<double>(count) * importance[v]));
    queue.push({ spacing[v], static_cast<Index>(v) });
  }
  while (!queue.empty())
  {
    const auto [h, v] = queue.top();
    queue.pop();
    if (h > spacing[v])
    {
      continue; // (an entry superseded)
    }
    for (std::int64_t k = graph.Offsets[v]; k < graph.Offsets[v + 1]; ++k)
    {
      const Index w = graph.Neighbors[k];
      const double reach = h + growth * (Point(points, w) - Point(points, v)).norm();
      if (reach < spacing[w])
      {
        spacing[w] = reach;
        queue.push({ reach, w });
      }
    }
  }
  std::vector<double> graded(n);
  for (std::size_t v = 0; v < n; ++v)
  {
    graded[v] = 2.0 * integral / (std::sqrt(3.0) * static_cast<double>(count) * spacing[v] * spacing[v]);
    graded[v] = std::isfinite(graded[v]) ? std::max(importance[v], graded[v]) : importance[v];
  }
  return graded;
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

void KeepCurvatures(const MeshTopology& topology, const double* points, int numThreads, RemeshCache& cache)
{
  if (cache.MaximumCurvature.size() != static_cast<std::size_t>(topology.NumberOfVertices()))
  {
    cache.MaximumCurvature = CurvatureValues(topology, points, CurvatureMeasure::MaximumCurvature, numThreads);
    AssembleSurfaceLaplacian(topology, points, LaplacianWeights::Cotangent, cache.SurfaceLaplacian, numThreads);
  }
}

namespace
{

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
  else if (importance && options.ImportanceGradation > 0.0)
  {
    density = GradedImportance(
      topology, points, importance, options.NumberOfVertices, options.ImportanceGradation, options.NumberOfThreads, *cache);
    importance = density.empty() ? importance : density.data();
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
  sampling.SparserSeams = options.SparserSeams;
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
  CheckFidelityInRounds(topology, points, atlas, options, optimization, remesh, out);
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

/// `kept` with the times of `other` added (the time both took).
void AddTimes(RemeshResult& kept, const RemeshResult& other)
{
  kept.SamplingSeconds += other.SamplingSeconds;
  kept.TriangulationSeconds += other.TriangulationSeconds;
  kept.OptimizationSeconds += other.OptimizationSeconds;
  kept.FidelitySeconds += other.FidelitySeconds;
}

} // namespace

/// One remesh with its fidelity rounds (CheckFidelityInRounds); where they
/// leave far input vertices that no vertex could be moved onto, or whose
/// moves did not bring it closer (FarVerticesLeft), and while the closest
/// remesh so far is farther than FarRemeshSpacings, up to FarPinRounds
/// remeshes more, each with the input vertices the closest remesh so far
/// leaves farther than FarPinSpacings spacings pinned too (with those the
/// rounds reached, and the pins of the remeshes before); the closest kept,
/// its triangles within the bar or as good as the first's (AsGood, in the
/// metric for an anisotropic remesh: ShapeFigures).  (Over the corpus and
/// generated shapes at 2,000 and 10,000 vertices, remeshes alone brought
/// the two-sided deviation down by 5% and 8% in geometric mean in 1.6-1.8
/// times the time of one remesh; the moves first, remeshes only where they
/// fall short, by 12% and 21% in 1.3 times.)
RemeshResult RemeshSurface(const MeshTopology& topology, const double* points, const AtlasResult& atlas,
  const double* importance, const RemeshOptions& given)
{
  RemeshCache local; // (the remeshes' rasters and the input's grid shared, where the caller keeps none)
  RemeshOptions options = given;
  options.Cache = given.Cache ? given.Cache : &local;
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
  const auto nearEnough = [&] { return WorstDeviation(best) * best.Diagonal <= FarRemeshSpacings * best.Spacing; };
  if (!best.FarVerticesLeft || options.FarPinSpacings <= 0.0 || options.PinnedVertices ||
    options.FinalSurface || !best.Error.empty() || nearEnough())
  {
    return best;
  }
  const TriangleGrid& toInput = options.Cache->SurfaceGrid(topology, points, options.NumberOfThreads);
  std::vector<std::uint8_t> pinned(static_cast<std::size_t>(topology.NumberOfVertices()), 0);
  for (const Index v : best.ReachedFarVertices)
  {
    pinned[v] = 1;
  }
  std::ptrdiff_t count = static_cast<std::ptrdiff_t>(best.ReachedFarVertices.size()); // of the pinned vertices
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
    const bool closer = KeptOver(topology, points, next, best, first, options.NumberOfThreads);
    AddTimes(closer ? next : best, closer ? best : next);
    if (!closer)
    {
      break;
    }
    best = std::move(next);
    if (nearEnough())
    {
      break;
    }
  }
  return best;
}

} // namespace beltrami
