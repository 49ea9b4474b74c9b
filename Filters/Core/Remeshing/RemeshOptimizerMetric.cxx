// Beltrami core, private to Remeshing/RemeshOptimization: the optimiser's
// measures in an anisotropic remesh's metric (Remeshing/RemeshMetric): the
// metric at a vertex, its factor over a few vertices, the quads and angles
// of the swaps in it, Lloyd's step carried into a chart's plane, and the
// pull towards a lattice aligned with it.
#include "Remeshing/RemeshOptimizer.h"

#include "Remeshing/RemeshMetric.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>

namespace beltrami::detail
{

Mat3 Optimizer::MetricAt(Index v) const
{
  double metric[6], tangent[9];
  InterpolatedMetric(Topology, MetricValues, R.Triangle[v], &R.Barycentric[3 * v], metric);
  TangentMetric(metric, InputNormals[v].data(), tangent);
  return Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(tangent);
}

Mat3 Optimizer::MetricFactor(std::initializer_list<Index> vertices) const
{
  Mat3 mean = Mat3::Zero();
  for (const Index v : vertices)
  {
    mean += VertexMetric[v];
  }
  const Eigen::LLT<Mat3> factor(mean / static_cast<double>(vertices.size()));
  return factor.info() == Eigen::Success ? Mat3(factor.matrixU()) : Mat3::Identity();
}

std::array<Vec3, 4> Optimizer::Quad(Index h) const
{
  const Index a = M.Tail(h), b = M.Head(h), c = M.Tail(HalfEdgeMesh::Prev(h)),
              d = M.Tail(HalfEdgeMesh::Prev(M.Twin(h)));
  std::array<Vec3, 4> quad = { M.Position(a), M.Position(b), M.Position(c), M.Position(d) };
  if (!VertexMetric.empty())
  {
    const Mat3 u = MetricFactor({ a, b, c, d });
    const Vec3 origin = quad[0];
    for (Vec3& p : quad)
    {
      p = u * (p - origin);
    }
  }
  return quad;
}

double Optimizer::FaceLargestCosine(Index f) const
{
  const Index a = M.Tail(3 * f), b = M.Tail(3 * f + 1), c = M.Tail(3 * f + 2);
  if (VertexMetric.empty())
  {
    return LargestCosine(M.Position(a), M.Position(b), M.Position(c));
  }
  const Mat3 u = MetricFactor({ a, b, c });
  return LargestCosine(Vec3::Zero(), u * (M.Position(b) - M.Position(a)), u * (M.Position(c) - M.Position(a)));
}

/// U with U^T U the metric at v carried into its chart's plane (the mean
/// over v's faces of J^T G J, J the map of the face from the plane to 3D):
/// U d is a step d of the plane as the metric measures it.
Eigen::Matrix2d Optimizer::PlaneMetricFactor(Index v) const
{
  Eigen::Matrix2d sum = Eigen::Matrix2d::Zero();
  const Vec3 x = M.Position(v);
  M.ForEachOutgoing(v, [&](Index h) {
    const double *q0 = UVAt(h), *q1 = UVAt(HalfEdgeMesh::Next(h)), *q2 = UVAt(HalfEdgeMesh::Prev(h));
    Eigen::Matrix2d plane;
    plane << q1[0] - q0[0], q2[0] - q0[0], q1[1] - q0[1], q2[1] - q0[1];
    Eigen::Matrix<double, 3, 2> space;
    space.col(0) = M.Position(M.Head(h)) - x;
    space.col(1) = M.Position(M.Tail(HalfEdgeMesh::Prev(h))) - x;
    if (std::abs(plane.determinant()) > 0.0)
    {
      const Eigen::Matrix<double, 3, 2> j = space * plane.inverse();
      sum += j.transpose() * VertexMetric[v] * j;
    }
  });
  const Eigen::LLT<Eigen::Matrix2d> factor(sum);
  return factor.info() == Eigen::Success && sum.allFinite() ? Eigen::Matrix2d(factor.matrixU())
                                                            : Eigen::Matrix2d::Identity();
}

/// With a metric, the move of v (in the metric's coordinates: U of
/// MetricFactor) that brings its neighbours nearest to a triangular lattice
/// of their mean distance with one edge direction along the metric's
/// strongest tangent direction (the short edges'), each neighbour rounded
/// to the lattice direction nearest to it (the lattice rounding of Jakob et
/// al.'s field-aligned meshes); `weight` says how anisotropic the metric at
/// v is (0 isotropic, 1 from an edge ratio of 2).
Vec3 Optimizer::LatticeShift(Index v, const Mat3& u, double& weight) const
{
  const Eigen::SelfAdjointEigenSolver<Mat3> eigen(VertexMetric[v]);
  const Eigen::Vector3d values = eigen.eigenvalues();
  // The tangent eigenvalues are the two smaller ones (the normal's is their sum).
  const double ratio = values[0] > 0.0 ? std::sqrt(values[1] / values[0]) : 1.0;
  weight = std::clamp(ratio - 1.0, 0.0, 1.0);
  const Vec3 a = (u * eigen.eigenvectors().col(1)).normalized(), c = (u * InputNormals[v]).normalized();
  const Vec3 b = c.cross(a);
  const Vec3 x = M.Position(v);
  double length = 0.0;
  int count = 0;
  M.ForEachOutgoing(v, [&](Index h) {
    const Vec3 y = u * (M.Position(M.Head(h)) - x);
    length += std::hypot(y.dot(a), y.dot(b));
    ++count;
  });
  length /= std::max(1, count);
  Vec3 shift = Vec3::Zero();
  M.ForEachOutgoing(v, [&](Index h) {
    const Vec3 y = u * (M.Position(M.Head(h)) - x);
    const double angle = std::atan2(y.dot(b), y.dot(a));
    const double k = std::round(angle / (M_PI / 3.0)) * (M_PI / 3.0);
    shift += y - length * (std::cos(k) * a + std::sin(k) * b);
  });
  return count > 0 ? Vec3(shift / count) : Vec3::Zero();
}

} // namespace beltrami::detail
