// Beltrami core: the metric of an anisotropic remesh (the thesis' future
// work of section 6.2: a tensor control map of the principal curvatures).
// A metric is a symmetric 3x3 tensor per input vertex, six numbers (xx, yy,
// zz, xy, yz, xz), whose restriction to the tangent plane says the wanted
// edge length in every direction: an edge d is of unit length where
// d^T T d = 1.  From the curvature tensor, the eigenvalues are |kappa_i|
// along the principal directions e_i (edge lengths proportional to
// |kappa_i|^(-1/2): the chordal error of a triangle is then the same in
// every direction and everywhere); any scale, as the remesher scales it to
// the vertex count.
#pragma once

#include "Mesh/Geometry.h"
#include "Mesh/Laplacian.h"
#include "Mesh/MeshTopology.h"

#include <cstdint>
#include <string>
#include <vector>

namespace beltrami
{

struct MetricOptions
{
  /// The longest over the shortest wanted edge length at a point, at most
  /// (1: isotropic; a cylinder's metric is infinitely anisotropic).
  double MaximumAnisotropy = 6.0;
  /// The least density (sqrt of the tangent determinant), relative to the
  /// surface's mean: flat parts keep at least this (isotropic) density.
  double Minimum = 0.05;
  /// The metric's components low-pass filtered over the surface by the heat
  /// kernel of this standard deviation (surface units; 0: none), so that
  /// the wanted lengths grade smoothly.
  double Gradation = 0.0;
  /// One flag per edge of topology.Edges() (may be null): kept lines
  /// (sharp edges), whose vertices' curvature is their crease's and no
  /// metric's: they take their neighbours' metric.
  const std::uint8_t* FeatureEdges = nullptr;
  int NumberOfThreads = 0;
};

struct MetricResult
{
  std::vector<double> Metric; ///< 6 per vertex
  std::string Warning;        ///< non-empty: the gradation's solve did not converge
};

/// The metric from the principal curvatures (chapter 2's operators).  Where
/// they are not defined (boundary, non-manifold or non-finite vertices,
/// feature lines), the mean of the neighbours', ring by ring; a component
/// without any: isotropic at the mean density.
MetricResult CurvatureMetric(const MeshTopology& topology, const double* points, const MetricOptions& options);

/// The metric's components low-pass filtered over the surface (one implicit
/// heat step of variance width^2 with the surface's cotangent `laplacian`,
/// all six together); false if the solve did not converge.
bool GradeMetric(const MeshTopology& topology, const double* points, const GraphLaplacian& laplacian, double width,
  std::vector<double>& metric, int numThreads = 0);

/// The metric at the vertices of kept lines (the surface's boundary, and
/// `featureEdges`' where given: one flag per edge of topology.Edges()) at
/// least isotropic at its mean density over the surface (both tangent
/// eigenvalues raised to it): the triangles beside a kept line, which is
/// sampled no sparser than a uniform remesh (SamplingOptions), then
/// match its spacing instead of fanning out from it into a flat face's
/// sparse metric.
void RaiseMetricOnKeptLines(const MeshTopology& topology, const double* points, const std::uint8_t* featureEdges,
  std::vector<double>& metric);

/// The metric's density at one point: the square root of its tangent
/// determinant (the second invariant of the tensor: lambda_1 lambda_2 for a
/// tangent one), the vertices per unit area up to a constant.
double MetricDensity(const double* metric);

/// The metric's length along direction t over its mean length (the square
/// root of MetricDensity): how much denser than the density's mean spacing
/// a line along t is to be sampled; 1 where either is not positive.
double StretchAlong(const double* metric, Vec3 t);

/// Densities per vertex (MetricDensity), for the sampler's importance.
std::vector<double> MetricDensities(const double* metric, Index vertices);

/// Per vertex, the largest principal curvature (`maximumCurvature`, one per
/// vertex) times the metric's shortest edge over its mean edge (the square
/// root of the smaller over the larger eigenvalue, to the power 1/2 again):
/// the curvature at which a triangle of the density's mean spacing sags as
/// much as the metric's shortest edges do along the most curved direction,
/// for RaiseImportanceForSag (thin tubes and fins narrower than the
/// metric's spacing get more samples, as in the isotropic mode).
std::vector<double> ShortestEdgeCurvatures(const double* metric, const std::vector<double>& maximumCurvature);

/// The metric at one point in its tangent plane of unit normal n: the
/// tensor's tangent part, plus its trace times n n^T (so that it is
/// positive definite and a triangle's tilt out of the plane counts as its
/// largest wanted length would).  3x3, row major.
void TangentMetric(const double* metric, const double* n, double* out);

/// The metric at (triangle, w) of the input: its corners' interpolated.
void InterpolatedMetric(const MeshTopology& topology, const double* metric, Index triangle, const double* w,
  double* out);

/// A remesh's edges and angles measured in the metric: its interpolation
/// (barycentric, at each remesh vertex's place on the input), scaled so that
/// the density's integral over the input is the remesh's vertex count times
/// sqrt(3)/2 (unit equilateral triangles).
struct MetricQuality
{
  double MedianEdgeLength = 0.0;
  double EdgesWithin20Percent = 0.0; ///< share of edges of length 0.8-1.2
  double MinimumAngle = 0.0, MeanMinimumAngle = 0.0; ///< degrees
  double TrianglesBelow30 = 0.0;     ///< share
  /// Per remesh vertex, the scaled tangent metric there (6 numbers).
  std::vector<double> PointMetric;
};
MetricQuality MeasureInMetric(const MeshTopology& topology, const double* points, const double* metric,
  const std::vector<double>& remeshPoints, const std::vector<Index>& remeshTriangles,
  const std::vector<Index>& sourceTriangle, const std::vector<double>& sourceBarycentric);

} // namespace beltrami
