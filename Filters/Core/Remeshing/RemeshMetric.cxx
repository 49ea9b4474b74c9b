#include "Remeshing/RemeshMetric.h"

#include "Mesh/Curvatures.h"
#include "Mesh/Laplacian.h"
#include "Mesh/SurfaceDistance.h"
#include "Remeshing/SurfaceRemeshing.h"
#include "Remeshing/SurfaceSampling.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>

namespace beltrami
{

namespace
{

/// The six components as a 3x3 matrix.
Eigen::Matrix3d Full(const double* t)
{
  Eigen::Matrix3d m;
  m << t[0], t[3], t[5], t[3], t[1], t[4], t[5], t[4], t[2];
  return m;
}

/// The metric's density integrated over the surface (per triangle, its
/// area times its corners' mean density), and in `area` the area counted
/// (the triangles where both are finite).
double DensityIntegral(const MeshTopology& topology, const double* points, const double* metric, double& area)
{
  double integral = 0.0;
  area = 0.0;
  const IndexArray& triangles = topology.TriangleList();
  for (Index t = 0; t < topology.NumberOfTriangles(); ++t)
  {
    const Index* c = triangles.data() + 3 * static_cast<std::size_t>(t);
    const double a =
      0.5 * (Point(points, c[1]) - Point(points, c[0])).cross(Point(points, c[2]) - Point(points, c[0])).norm();
    const double d =
      (MetricDensity(metric + 6 * c[0]) + MetricDensity(metric + 6 * c[1]) + MetricDensity(metric + 6 * c[2])) / 3.0;
    if (std::isfinite(a * d))
    {
      area += a;
      integral += a * d;
    }
  }
  return integral;
}

/// a e e^T + b f f^T into the six components.
void Tensor(double a, const double* e, double b, const double* f, double* out)
{
  const int row[6] = { 0, 1, 2, 0, 1, 0 }, col[6] = { 0, 1, 2, 1, 2, 2 };
  for (int k = 0; k < 6; ++k)
  {
    out[k] = a * e[row[k]] * e[col[k]] + b * f[row[k]] * f[col[k]];
  }
}

/// Vertices whose metric is not defined take their densest defined
/// neighbour's (MetricDensity), ring by ring: a crease's or the boundary's
/// vertex the side that asks the most of the line; `defined` is updated.
/// Those of components without a defined vertex get `fallback` (6
/// components).
void FillUndefined(const MeshTopology& topology, std::vector<double>& metric, std::vector<std::uint8_t>& defined,
  const double* fallback)
{
  const MeshTopology::VertexGraph& graph = topology.Graph();
  const Index n = topology.NumberOfVertices();
  std::vector<Index> front;
  for (Index v = 0; v < n; ++v)
  {
    if (!defined[v])
    {
      front.push_back(v);
    }
  }
  while (!front.empty())
  {
    std::vector<Index> next, filled;
    for (Index v : front)
    {
      Index densest = -1;
      for (std::int64_t k = graph.NeighborOffsets[v]; k < graph.NeighborOffsets[v + 1]; ++k)
      {
        const Index w = graph.Neighbors[k];
        if (defined[w] && (densest < 0 || MetricDensity(&metric[6 * w]) > MetricDensity(&metric[6 * densest])))
        {
          densest = w;
        }
      }
      if (densest < 0)
      {
        next.push_back(v);
        continue;
      }
      std::copy(&metric[6 * densest], &metric[6 * densest] + 6, &metric[6 * v]);
      filled.push_back(v);
    }
    for (Index v : filled)
    {
      defined[v] = 1;
    }
    if (filled.empty())
    {
      for (Index v : next)
      {
        std::copy(fallback, fallback + 6, &metric[6 * v]);
        defined[v] = 1;
      }
      break;
    }
    front.swap(next);
  }
}

} // namespace

double MetricDensity(const double* t)
{
  const double i2 = t[0] * t[1] - t[3] * t[3] + t[1] * t[2] - t[4] * t[4] + t[0] * t[2] - t[5] * t[5];
  return i2 > 0.0 ? std::sqrt(i2) : 0.0;
}

double StretchAlong(const double* m, Vec3 t)
{
  t.normalize();
  const double along = t[0] * t[0] * m[0] + t[1] * t[1] * m[1] + t[2] * t[2] * m[2] +
    2.0 * (t[0] * t[1] * m[3] + t[1] * t[2] * m[4] + t[0] * t[2] * m[5]);
  const double mean = MetricDensity(m);
  return along > 0.0 && mean > 0.0 && std::isfinite(along / mean) ? std::sqrt(along / mean) : 1.0;
}

std::vector<double> MetricDensities(const double* metric, Index vertices)
{
  std::vector<double> density(static_cast<std::size_t>(std::max<Index>(0, vertices)));
  for (std::size_t v = 0; v < density.size(); ++v)
  {
    density[v] = MetricDensity(metric + 6 * v);
  }
  return density;
}

std::vector<double> ShortestEdgeCurvatures(const double* metric, const std::vector<double>& maximumCurvature)
{
  std::vector<double> out(maximumCurvature.size());
  for (std::size_t v = 0; v < out.size(); ++v)
  {
    const Eigen::Vector3d values =
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(Full(metric + 6 * v), Eigen::EigenvaluesOnly).eigenvalues();
    // (The two largest are the tangent ones: a smoothed metric has a little normal part.)
    const double ratio = values[2] > 0.0 ? std::max(0.0, values[1]) / values[2] : 1.0;
    out[v] = maximumCurvature[v] * std::sqrt(std::sqrt(ratio));
  }
  return out;
}

void TangentMetric(const double* t, const double* n, double* out)
{
  const Eigen::Vector3d normal(n[0], n[1], n[2]);
  const Eigen::Matrix3d p = Eigen::Matrix3d::Identity() - normal * normal.transpose();
  Eigen::Matrix3d tangent = p * Full(t) * p;
  tangent += std::max(0.0, tangent.trace()) * normal * normal.transpose();
  for (int r = 0; r < 3; ++r)
  {
    for (int c = 0; c < 3; ++c)
    {
      out[3 * r + c] = tangent(r, c);
    }
  }
}

void InterpolatedMetric(const MeshTopology& topology, const double* metric, Index triangle, const double* w,
  double* out)
{
  std::fill(out, out + 6, 0.0);
  for (int j = 0; j < 3; ++j)
  {
    const double* t = metric + 6 * static_cast<std::int64_t>(topology.CornerVertex(3 * triangle + j));
    for (int c = 0; c < 6; ++c)
    {
      out[c] += w[j] * t[c];
    }
  }
}

namespace
{

/// The tangent metric (TangentMetric) at each remesh vertex, from its place
/// on the input.
std::vector<Eigen::Matrix3d> RemeshMetrics(const MeshTopology& topology, const double* points, const double* metric,
  const std::vector<Index>& sourceTriangle, const std::vector<double>& sourceBarycentric)
{
  std::vector<Eigen::Matrix3d> out(sourceTriangle.size(), Eigen::Matrix3d::Identity());
  for (std::size_t v = 0; v < sourceTriangle.size(); ++v)
  {
    const Index t = sourceTriangle[v];
    if (t < 0)
    {
      continue;
    }
    double m[6], tangent[9];
    InterpolatedMetric(topology, metric, t, &sourceBarycentric[3 * v], m);
    const Vec3 a = Point(points, topology.CornerVertex(3 * t)), b = Point(points, topology.CornerVertex(3 * t + 1)),
               c = Point(points, topology.CornerVertex(3 * t + 2));
    const Vec3 normal = (b - a).cross(c - a).normalized();
    TangentMetric(m, normal.data(), tangent);
    out[v] = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(tangent);
  }
  return out;
}

} // namespace

MetricQuality MeasureInMetric(const MeshTopology& topology, const double* points, const double* metric,
  const std::vector<double>& remeshPoints, const std::vector<Index>& remeshTriangles,
  const std::vector<Index>& sourceTriangle, const std::vector<double>& sourceBarycentric)
{
  MetricQuality quality;
  // The scale: the density's integral is the count times sqrt(3) / 2.
  double area = 0.0;
  const double integral = DensityIntegral(topology, points, metric, area);
  const std::size_t vertices = remeshPoints.size() / 3, triangles = remeshTriangles.size() / 3;
  if (!(integral > 0.0) || vertices == 0 || triangles == 0)
  {
    return quality;
  }
  const double scale = static_cast<double>(vertices) * std::sqrt(3.0) / 2.0 / integral;
  std::vector<Eigen::Matrix3d> at = RemeshMetrics(topology, points, metric, sourceTriangle, sourceBarycentric);
  quality.PointMetric.resize(6 * vertices);
  for (std::size_t v = 0; v < vertices; ++v)
  {
    at[v] *= scale;
    const double six[6] = { at[v](0, 0), at[v](1, 1), at[v](2, 2), at[v](0, 1), at[v](1, 2), at[v](0, 2) };
    std::copy(six, six + 6, &quality.PointMetric[6 * v]);
  }
  std::vector<double> lengths;
  quality.MinimumAngle = 180.0;
  double sumMinimum = 0.0;
  std::size_t below30 = 0;
  for (std::size_t t = 0; t < triangles; ++t)
  {
    const Index* c = remeshTriangles.data() + 3 * t;
    const Eigen::Matrix3d m = (at[c[0]] + at[c[1]] + at[c[2]]) / 3.0;
    double angles[3];
    for (int k = 0; k < 3; ++k)
    {
      const Index a = c[k], b = c[(k + 1) % 3], o = c[(k + 2) % 3];
      const Vec3 pa = Point(remeshPoints.data(), a), pb = Point(remeshPoints.data(), b),
                 po = Point(remeshPoints.data(), o);
      if (a < b) // each interior edge once (its other face has it as b, a)
      {
        const Vec3 d = pb - pa;
        lengths.push_back(std::sqrt(std::max(0.0, d.dot(0.5 * (at[a] + at[b]) * d))));
      }
      const Vec3 u = pb - pa, v = po - pa;
      const double uu = u.dot(m * u), vv = v.dot(m * v), uv = u.dot(m * v);
      angles[k] = std::acos(std::clamp(uv / std::sqrt(std::max(1e-300, uu * vv)), -1.0, 1.0)) * 180.0 / M_PI;
    }
    const double smallest = std::min({ angles[0], angles[1], angles[2] });
    quality.MinimumAngle = std::min(quality.MinimumAngle, smallest);
    sumMinimum += smallest;
    below30 += smallest < 30.0;
  }
  quality.MeanMinimumAngle = sumMinimum / static_cast<double>(triangles);
  quality.TrianglesBelow30 = static_cast<double>(below30) / static_cast<double>(triangles);
  std::sort(lengths.begin(), lengths.end());
  quality.MedianEdgeLength = lengths[lengths.size() / 2];
  quality.EdgesWithin20Percent =
    static_cast<double>(std::count_if(lengths.begin(), lengths.end(), [](double l) { return l >= 0.8 && l <= 1.2; })) /
    static_cast<double>(lengths.size());
  return quality;
}

void RaiseMetricOnKeptLines(const MeshTopology& topology, const double* points, const std::uint8_t* featureEdges,
  std::vector<double>& metric)
{
  double area = 0.0;
  const double integral = DensityIntegral(topology, points, metric.data(), area);
  const double mean = area > 0.0 ? integral / area : 0.0;
  const MeshTopology::EdgeTable& edges = topology.Edges();
  std::vector<std::uint8_t> kept(static_cast<std::size_t>(topology.NumberOfVertices()), 0);
  for (std::int64_t e = 0; e < edges.NumberOfEdges(); ++e)
  {
    if (IsKeptEdge(edges, e, featureEdges))
    {
      kept[edges.Vertices[2 * e]] = kept[edges.Vertices[2 * e + 1]] = 1;
    }
  }
  for (std::size_t v = 0; v < kept.size() && mean > 0.0; ++v)
  {
    if (!kept[v])
    {
      continue;
    }
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(Full(&metric[6 * v]));
    Eigen::Matrix3d m = Full(&metric[6 * v]);
    for (int k = 1; k < 3; ++k) // (the two largest are the tangent ones)
    {
      const Eigen::Vector3d e = eigen.eigenvectors().col(k);
      m += std::max(0.0, mean - eigen.eigenvalues()[k]) * e * e.transpose();
    }
    const double six[6] = { m(0, 0), m(1, 1), m(2, 2), m(0, 1), m(1, 2), m(0, 2) };
    std::copy(six, six + 6, &metric[6 * v]);
  }
}

bool GradeMetric(const MeshTopology& topology, const double* points, const GraphLaplacian& laplacian, double width,
  std::vector<double>& metric, int numThreads)
{
  // (One coarse step: the kernel's exact shape does not matter here, as
  // for RaiseImportanceForSag's spread.)  Solved on the metric scaled by a
  // power of two to about 1, so that any scale grades alike (the solver's
  // single-precision products underflow below about 1e-19).
  double largest = 0.0;
  for (const double x : metric)
  {
    largest = std::max(largest, std::abs(x));
  }
  int exponent = 0;
  std::frexp(largest, &exponent);
  for (double& x : metric)
  {
    x = std::ldexp(x, -exponent);
  }
  const bool converged = SmoothOverSurface(topology, points, laplacian, width, 1, 1e-3, metric, numThreads, 6);
  for (double& x : metric)
  {
    x = std::ldexp(x, exponent);
  }
  return converged;
}

MetricResult CurvatureMetric(const MeshTopology& topology, const double* points, const MetricOptions& options)
{
  const Index n = topology.NumberOfVertices();
  const std::size_t size = static_cast<std::size_t>(n);
  std::vector<double> k1(size), k2(size), e1(3 * size), e2(3 * size);
  CurvatureOptions curvatureOptions;
  curvatureOptions.NumberOfThreads = options.NumberOfThreads;
  CurvatureOutputs outputs;
  outputs.MaximumCurvature = k1.data();
  outputs.MinimumCurvature = k2.data();
  outputs.PrincipalDirection1 = e1.data();
  outputs.PrincipalDirection2 = e2.data();
  ComputeCurvatures(topology, points, curvatureOptions, outputs);
  GraphLaplacian laplacian;
  AssembleSurfaceLaplacian(topology, points, LaplacianWeights::Cotangent, laplacian, options.NumberOfThreads);
  std::vector<std::uint8_t> defined(size, 0);
  for (std::size_t v = 0; v < size; ++v)
  {
    defined[v] = std::isfinite(k1[v]) && std::isfinite(k2[v]) && std::isfinite(e1[3 * v]) &&
      std::isfinite(e2[3 * v]) && laplacian.Mass[v] > 0.0;
  }
  const MeshTopology::EdgeTable& edges = topology.Edges();
  for (std::int64_t e = 0; options.FeatureEdges && e < edges.NumberOfEdges(); ++e)
  {
    if (options.FeatureEdges[e])
    {
      defined[edges.Vertices[2 * e]] = defined[edges.Vertices[2 * e + 1]] = 0;
    }
  }
  // Eigenvalues |kappa_i|, the smaller raised to the anisotropy's cap.
  const double cap = std::max(1.0, options.MaximumAnisotropy);
  std::vector<double> a(size, 0.0), b(size, 0.0);
  double massSum = 0.0, densitySum = 0.0;
  for (std::size_t v = 0; v < size; ++v)
  {
    if (!defined[v])
    {
      continue;
    }
    a[v] = std::abs(k1[v]);
    b[v] = std::abs(k2[v]);
    const double large = std::max(a[v], b[v]);
    a[v] = std::max(a[v], large / (cap * cap));
    b[v] = std::max(b[v], large / (cap * cap));
    massSum += laplacian.Mass[v];
    densitySum += laplacian.Mass[v] * std::sqrt(a[v] * b[v]);
  }
  // The floor: an isotropic density of Minimum times the mean, and at least
  // the curvature of a sphere a thousand times the surface's size (a plane's
  // curvatures are round-off, whose directions and ratios mean nothing).
  const double diagonal =
    UsedBoundingBoxDiagonal(points, topology.TriangleList().data(), topology.NumberOfTriangles());
  const double flat = diagonal > 0.0 && std::isfinite(diagonal) ? 1e-3 / diagonal : 1e-300;
  const double mean = massSum > 0.0 ? densitySum / massSum : 0.0;
  const double floor = std::isfinite(mean) ? std::max(flat, options.Minimum * mean) : flat;
  MetricResult out;
  out.Metric.assign(6 * size, 0.0);
  for (std::size_t v = 0; v < size; ++v)
  {
    if (defined[v])
    {
      Tensor(std::max(a[v], floor), &e1[3 * v], std::max(b[v], floor), &e2[3 * v], &out.Metric[6 * v]);
    }
  }
  const double isotropic = std::isfinite(mean) ? std::max(flat, mean) : flat;
  const double fallback[6] = { isotropic, isotropic, isotropic, 0.0, 0.0, 0.0 };
  FillUndefined(topology, out.Metric, defined, fallback);
  if (options.Gradation > 0.0 &&
    !GradeMetric(topology, points, laplacian, options.Gradation, out.Metric, options.NumberOfThreads))
  {
    out.Warning = "the metric's gradation did not converge";
  }
  return out;
}

} // namespace beltrami
