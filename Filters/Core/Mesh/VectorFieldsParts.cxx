// Beltrami core, private to Mesh/VectorFields: the steps of the
// decomposition that work triangle by triangle or vertex by vertex, shared
// by the serial decomposer and the one split over processes
// (Mesh/DistributedVectorFields.cxx).
#include "Mesh/VectorFieldsDetail.h"

#include "Mesh/MeshMeasures.h"
#include "Mesh/RingGeometry.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace beltrami::detail
{

namespace
{

/// Per triangle of non-zero area: sum over its corners c of term(t, c, e_c)
/// (e_c the side opposite c), over the area; into `out` (3 per triangle).
template <typename Term>
void SumOverCorners(const MeshTopology& topo, const double* points, const TriangleFrames& f, int threads,
  std::vector<double>& out, Term term)
{
  const IndexArray& tri = topo.TriangleList();
  out.assign(3 * static_cast<std::size_t>(topo.NumberOfTriangles()), 0.0);
  ParallelFor(topo.NumberOfTriangles(), threads, [&](std::int64_t begin, std::int64_t end) {
    for (std::int64_t t = begin; t < end; ++t)
    {
      if (f.Areas[t] == 0.0)
      {
        continue;
      }
      Vec3 sum = Vec3::Zero();
      for (Index c = static_cast<Index>(3 * t); c < 3 * t + 3; ++c)
      {
        sum += term(t, c, Side(points, tri, c));
      }
      Store(&out[3 * t], sum / f.Areas[t]);
    }
  });
}

} // namespace

TriangleFrames MakeFrames(const MeshTopology& topo, const double* points, int threads)
{
  const IndexArray& tri = topo.TriangleList();
  const Index nt = topo.NumberOfTriangles();
  TriangleFrames f;
  f.Normals.assign(3 * static_cast<std::size_t>(nt), 0.0);
  f.Areas.assign(nt, 0.0);
  ParallelFor(nt, threads, [&](std::int64_t begin, std::int64_t end) {
    for (std::int64_t t = begin; t < end; ++t)
    {
      const Vec3 a = Point(points, tri[3 * t]), b = Point(points, tri[3 * t + 1]), c = Point(points, tri[3 * t + 2]);
      const Vec3 cross = (b - a).cross(c - a);
      const double twice = cross.norm();
      const double longest = std::max({ (b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm() });
      if (twice > DegenerateTolerance * longest && std::isfinite(twice))
      {
        Store(&f.Normals[3 * t], cross / twice);
        f.Areas[t] = 0.5 * twice;
      }
    }
  });
  return f;
}

/// Splits the input into its tangent part and normal component.
void ProjectToTangent(const TriangleFrames& f, const double* vectors, VectorFieldDecomposition& r, int threads)
{
  const std::int64_t nt = static_cast<std::int64_t>(f.Areas.size());
  r.Tangent.assign(3 * nt, 0.0);
  r.Normal.assign(nt, 0.0);
  ParallelFor(nt, threads, [&](std::int64_t begin, std::int64_t end) {
    for (std::int64_t t = begin; t < end; ++t)
    {
      Vec3 x(vectors[3 * t], vectors[3 * t + 1], vectors[3 * t + 2]);
      if (!x.allFinite() || f.Areas[t] == 0.0)
      {
        continue; // left out: no part
      }
      const Vec3 n(&f.Normals[3 * t]);
      r.Normal[t] = x.dot(n);
      Store(&r.Tangent[3 * t], x - r.Normal[t] * n);
    }
  });
}

/// The right-hand side of the potential's system, (X, grad phi_i) per
/// vertex; also the divergence and curl at the vertices (they share the
/// loop over the corners).
std::vector<double> PotentialRightHandSide(const MeshTopology& topo, const double* points, const TriangleFrames& f,
  int threads, VectorFieldDecomposition& r)
{
  const Index nv = topo.NumberOfVertices();
  const IndexArray& tri = topo.TriangleList();
  std::vector<double> b(nv, 0.0);
  r.Divergence.assign(nv, 0.0);
  r.Curl.assign(nv, 0.0);
  ParallelFor(nv, threads, [&](std::int64_t begin, std::int64_t end) {
    for (Index i = static_cast<Index>(begin); i < end; ++i)
    {
      double flux = 0.0, circulation = 0.0, area = 0.0;
      for (const Index* c = topo.CornersBegin(i); c != topo.CornersEnd(i); ++c)
      {
        const Index t = *c / 3;
        area += f.Areas[t] / 3.0;
        const Vec3 x(&r.Tangent[3 * static_cast<std::int64_t>(t)]), n(&f.Normals[3 * static_cast<std::int64_t>(t)]);
        const Vec3 side = Side(points, tri, *c);
        flux += 0.5 * x.dot(n.cross(side));  // (X, grad phi_i) on t
        circulation += 0.5 * x.dot(side);    // (J^T X, grad phi_i) on t
      }
      b[i] = flux;
      r.Divergence[i] = area > 0.0 ? -flux / area : std::numeric_limits<double>::quiet_NaN();
      r.Curl[i] = area > 0.0 ? circulation / area : std::numeric_limits<double>::quiet_NaN();
    }
  });
  return b;
}

/// grad u per triangle: sum_k u_k n x e_k / 2A.
void GradientPart(const MeshTopology& topo, const double* points, const TriangleFrames& f, int threads,
  VectorFieldDecomposition& r)
{
  const IndexArray& tri = topo.TriangleList();
  SumOverCorners(topo, points, f, threads, r.CurlFree, [&](std::int64_t t, Index c, const Vec3& side) -> Vec3 {
    return 0.5 * r.Potential[tri[c]] * Vec3(&f.Normals[3 * t]).cross(side);
  });
}

/// The right-hand side of the stream function's system, (J^T X, grad psi_e)
/// = sum of X . e_k over the edge's triangles (e_k the edge opposite corner k).
std::vector<double> StreamRightHandSide(const MeshTopology& topo, const double* points, int threads,
  const VectorFieldDecomposition& r)
{
  const MeshTopology::EdgeTable& edges = topo.Edges();
  const IndexArray& tri = topo.TriangleList();
  std::vector<double> b(static_cast<std::size_t>(edges.NumberOfEdges()), 0.0);
  ParallelFor(edges.NumberOfEdges(), threads, [&](std::int64_t begin, std::int64_t end) {
    for (std::int64_t e = begin; e < end; ++e)
    {
      for (int s = 0; s < 2; ++s)
      {
        const Index c = edges.OppositeCorners[2 * e + s];
        if (c >= 0)
        {
          b[e] += Vec3(&r.Tangent[3 * static_cast<std::int64_t>(c / 3)]).dot(Side(points, tri, c));
        }
      }
    }
  });
  return b;
}

/// J grad v per triangle: sum_k v_k e_k / A.
void RotatedGradientPart(const MeshTopology& topo, const double* points, const TriangleFrames& f,
  const EdgeGraph& graph, int threads, VectorFieldDecomposition& r)
{
  SumOverCorners(topo, points, f, threads, r.DivergenceFree, [&](std::int64_t, Index c, const Vec3& side) -> Vec3 {
    return r.StreamFunction[graph.TriangleEdges[c]] * side;
  });
}

/// The harmonic remainder, the energies and the inner products.
void HarmonicPart(const TriangleFrames& f, int threads, VectorFieldDecomposition& r, const std::uint8_t* counted)
{
  const std::int64_t nt = static_cast<std::int64_t>(f.Areas.size());
  r.Harmonic.resize(r.Tangent.size());
  for (std::size_t k = 0; k < r.Tangent.size(); ++k)
  {
    r.Harmonic[k] = r.Tangent[k] - r.CurlFree[k] - r.DivergenceFree[k];
  }
  const std::vector<double> sums = ParallelSum(nt, 7, threads, [&](std::int64_t begin, std::int64_t end, double* s) {
    for (std::int64_t t = begin; t < end; ++t)
    {
      const double a = !counted || counted[t] ? f.Areas[t] : 0.0;
      const Vec3 x(&r.Tangent[3 * t]), g(&r.CurlFree[3 * t]), d(&r.DivergenceFree[3 * t]), h(&r.Harmonic[3 * t]);
      s[0] += a * x.squaredNorm();
      s[1] += a * g.squaredNorm();
      s[2] += a * d.squaredNorm();
      s[3] += a * h.squaredNorm();
      s[4] += a * g.dot(d);
      s[5] += a * g.dot(h);
      s[6] += a * d.dot(h);
    }
  });
  std::copy(sums.begin(), sums.begin() + 4, r.Energy);
  std::copy(sums.begin() + 4, sums.end(), r.InnerProducts);
}

std::vector<std::uint8_t> FixedVertices(
  const MeshTopology& topo, const TriangleFrames& f, const GraphLaplacian& cotangent, VectorFieldBoundary boundary)
{
  const Index nv = topo.NumberOfVertices();
  // The boundary of what is decomposed: the surface's, and the rims of the
  // triangles left out (zero area), where the boundary condition holds too
  // (else the parts are not orthogonal: 0.15 of the energy on a Bohemian
  // dome with 158 such triangles).
  std::vector<std::uint8_t> rim(nv, 0);
  const IndexArray& tri = topo.TriangleList();
  for (Index t = 0; t < topo.NumberOfTriangles(); ++t)
  {
    for (int k = 0; k < 3 && f.Areas[t] == 0.0; ++k)
    {
      rim[tri[3 * static_cast<std::int64_t>(t) + k]] = 1;
    }
  }
  std::vector<std::uint8_t> fixed(nv);
  for (Index i = 0; i < nv; ++i)
  {
    const bool onBoundary = rim[i] || (topo.VertexFlags(i) & VertexBoundary) != 0;
    fixed[i] = !(cotangent.Diagonal[i] > 0.0) || (onBoundary && boundary == VectorFieldBoundary::NormalCurlFree);
  }
  return fixed;
}

std::vector<std::uint8_t> FixedEdges(
  const MeshTopology& topo, const TriangleFrames& f, const GraphLaplacian& nonconforming, VectorFieldBoundary boundary)
{
  const MeshTopology::EdgeTable& edges = topo.Edges();
  const Index ne = static_cast<Index>(edges.NumberOfEdges());
  std::vector<std::uint8_t> fixed(ne);
  for (Index e = 0; e < ne; ++e)
  {
    int faces = 0; // with an area
    for (int k = 0; k < 2; ++k)
    {
      const Index corner = edges.OppositeCorners[2 * static_cast<std::int64_t>(e) + k];
      faces += corner >= 0 && f.Areas[corner / 3] > 0.0;
    }
    fixed[e] = !(nonconforming.Diagonal[e] > 0.0) || edges.FaceCount[e] > 2 ||
      (faces == 1 && boundary == VectorFieldBoundary::TangentDivergenceFree);
  }
  return fixed;
}

/// The results of the points times 2^-e and the field times 2^-f back to
/// their scales.
void ScaleBack(int e, int f, VectorFieldDecomposition& r)
{
  for (std::vector<double>* part : { &r.Tangent, &r.CurlFree, &r.DivergenceFree, &r.Harmonic })
  {
    TimesPowerOfTwo(part->data(), part->size(), f);
  }
  TimesPowerOfTwo(r.Potential.data(), r.Potential.size(), e + f);
  TimesPowerOfTwo(r.StreamFunction.data(), r.StreamFunction.size(), e + f);
  TimesPowerOfTwo(r.Divergence.data(), r.Divergence.size(), f - e);
  TimesPowerOfTwo(r.Curl.data(), r.Curl.size(), f - e);
  TimesPowerOfTwo(r.Energy, 4, 2 * (e + f));
  TimesPowerOfTwo(r.InnerProducts, 3, 2 * (e + f));
}

} // namespace beltrami::detail
