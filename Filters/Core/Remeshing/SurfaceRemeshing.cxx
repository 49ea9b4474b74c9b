#include "Remeshing/SurfaceRemeshing.h"

#include "Mesh/Curvatures.h"
#include "Mesh/MeshMeasures.h"

#include <algorithm>
#include <chrono>
#include <cmath>

namespace beltrami
{

namespace
{

double SecondsSince(std::chrono::steady_clock::time_point start)
{
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

} // namespace

AtlasOptions RemeshingAtlasOptions()
{
  AtlasOptions options;
  options.ChartBoundary = ParameterizationBoundary::Natural;
  options.BalanceAreas = true;
  return options;
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

std::vector<double> ImportanceFromValues(const std::vector<double>& values, double gamma, double minimum)
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
  std::vector<double> importance(values.size(), 1.0);
  for (std::size_t i = 0; i < values.size(); ++i)
  {
    const double relative = std::isfinite(values[i]) && mean > 0.0 ? std::abs(values[i]) / mean : 1.0;
    importance[i] = std::max(minimum, std::pow(relative, gamma));
  }
  return importance;
}

RemeshResult RemeshSurface(const MeshTopology& topology, const double* points, const AtlasResult& atlas,
  const double* importance, const RemeshOptions& options)
{
  RemeshResult out;
  auto start = std::chrono::steady_clock::now();
  SamplingOptions sampling;
  sampling.NumberOfSamples = options.NumberOfVertices;
  sampling.Resolution = options.Resolution;
  sampling.NumberOfThreads = options.NumberOfThreads;
  out.Samples = SampleSurface(topology, points, atlas, importance, sampling);
  out.SamplingSeconds = SecondsSince(start);
  if (!out.Samples.Error.empty())
  {
    out.Error = out.Samples.Error;
    return out;
  }
  start = std::chrono::steady_clock::now();
  Remesh remesh = CreateRemesh(topology, points, atlas, out.Samples, options.NumberOfThreads);
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
  optimization.Importance = importance;
  const std::vector<std::uint8_t> features =
    options.FeatureAngle > 0.0 ? SharpEdges(topology, points, options.FeatureAngle) : std::vector<std::uint8_t>();
  optimization.FeatureEdges = features.empty() ? nullptr : features.data();
  out.Optimization = OptimizeRemesh(remesh, topology, points, atlas, out.Samples, optimization);
  out.OptimizationSeconds = SecondsSince(start);
  out.Points = remesh.Mesh.Points();
  out.Triangles = remesh.Mesh.Triangles();
  out.SourceTriangle = std::move(remesh.Triangle);
  out.SourceBarycentric = std::move(remesh.Barycentric);
  return out;
}

} // namespace beltrami
