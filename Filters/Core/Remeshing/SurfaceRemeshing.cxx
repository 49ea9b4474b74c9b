#include "Remeshing/SurfaceRemeshing.h"

#include <chrono>

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
  optimization.Importance = importance;
  out.Optimization = OptimizeRemesh(remesh, topology, points, atlas, out.Samples, optimization);
  out.OptimizationSeconds = SecondsSince(start);
  out.Points = remesh.Mesh.Points();
  out.Triangles = remesh.Mesh.Triangles();
  out.SourceTriangle = std::move(remesh.Triangle);
  out.SourceBarycentric = std::move(remesh.Barycentric);
  return out;
}

} // namespace beltrami
