#include "Mesh/VectorFields.h"

#include "Mesh/Geometry.h"
#include "Mesh/Laplacian.h"
#include "Mesh/RingGeometry.h"
#include "Solvers/GraphSolvers.h"
#include "Solvers/NestedDissection.h"
#include "Solvers/SparseFactorization.h"
#include "Support/DisjointSets.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace beltrami
{

namespace
{

void Store(double* target, const Vec3& value)
{
  target[0] = value[0];
  target[1] = value[1];
  target[2] = value[2];
}

/// Vertex k of triangle t and the side opposite it: e_k = x_{k+2} - x_{k+1}
/// (counter-clockwise about the normal), the side of grad phi_k = n x e_k / 2A.
Vec3 Side(const double* points, const IndexArray& tri, Index corner)
{
  return Point(points, tri[MeshTopology::Prev(corner)]) - Point(points, tri[MeshTopology::Next(corner)]);
}

/// Per triangle: the unit normal and the area (0 for a zero-area triangle).
struct TriangleFrames
{
  std::vector<double> Normals; ///< 3 per triangle
  std::vector<double> Areas;
};

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

/// The vertex components (union-find over the triangles' vertices).
std::vector<Index> VertexComponents(const MeshTopology& topo)
{
  std::vector<Index> parent(topo.NumberOfVertices());
  std::iota(parent.begin(), parent.end(), 0);
  const IndexArray& tri = topo.TriangleList();
  for (std::size_t c = 0; c < tri.size(); c += 3)
  {
    for (int k = 1; k < 3; ++k)
    {
      const Index a = FindRoot(parent, tri[c]), b = FindRoot(parent, tri[c + k]);
      parent[std::max(a, b)] = std::min(a, b);
    }
  }
  for (Index v = 0; v < topo.NumberOfVertices(); ++v)
  {
    parent[v] = FindRoot(parent, v);
  }
  return parent;
}

/// One Poisson problem: K x = b on the rows of `laplacian` (true stiffness:
/// twice the assembler's normalization), rows with `fixed` kept at 0, one
/// row pinned in each component with none fixed; the solution then gets zero
/// mean there (the function is defined up to a constant).
struct Poisson
{
  const GraphLaplacian& Laplacian;
  std::vector<std::uint8_t> Fixed;      ///< boundary conditions and rows without coupling
  const std::vector<Index>& Component;  ///< per row: its component's id (a vertex id)
  const double* Positions;              ///< 3 per row: where the unknown lives (the elimination order's)
};

/// K x = b by a sparse Cholesky factorization in nested-dissection order
/// (the fixed rows identity rows); false if the factorization fails.
bool SolveDirectly(const Poisson& p, const std::vector<double>& b, int threads, std::vector<double>& x)
{
  const GraphLaplacian& l = p.Laplacian;
  const Index n = l.NumberOfVertices;
  std::vector<int> outer(static_cast<std::size_t>(n) + 1, 0), inner;
  std::vector<double> values;
  inner.reserve(static_cast<std::size_t>(l.Offsets[n]) + n);
  values.reserve(inner.capacity());
  for (Index i = 0; i < n; ++i) // column i (symmetric): the free neighbours and the diagonal, ascending
  {
    bool diagonal = false;
    for (std::int64_t k = l.Offsets[i]; !p.Fixed[i] && k < l.Offsets[i + 1]; ++k)
    {
      const Index j = l.Neighbors[k];
      if (!diagonal && j > i)
      {
        inner.push_back(i);
        values.push_back(2.0 * l.Diagonal[i]);
        diagonal = true;
      }
      if (!p.Fixed[j])
      {
        inner.push_back(j);
        values.push_back(-2.0 * l.Weights[k]);
      }
    }
    if (!diagonal)
    {
      inner.push_back(i);
      values.push_back(p.Fixed[i] ? 1.0 : 2.0 * l.Diagonal[i]);
    }
    outer[i + 1] = static_cast<int>(inner.size());
  }
  const SparseFactorization::MatrixView a(n, n, static_cast<Eigen::Index>(inner.size()), outer.data(), inner.data(),
    values.data());
  const std::vector<Index> order = NestedDissectionOrder(n, l.Offsets, l.Neighbors, p.Positions, threads);
  SparseFactorization factor;
  if (!factor.Compute(a, true, std::vector<int>(order.begin(), order.end()), false, threads))
  {
    return false;
  }
  Eigen::MatrixXd rhs(n, 1);
  for (Index i = 0; i < n; ++i)
  {
    rhs(i, 0) = p.Fixed[i] ? 0.0 : b[i];
  }
  const Eigen::MatrixXd solution = factor.Solve(rhs);
  x.assign(solution.data(), solution.data() + n);
  return x.size() == static_cast<std::size_t>(n) && std::all_of(x.begin(), x.end(), [](double v) { return std::isfinite(v); });
}

/// The relative residual of K x = b on the free rows.
double RelativeResidual(const Poisson& p, const std::vector<double>& b, const std::vector<double>& x, int threads)
{
  std::vector<double> y(x.size());
  p.Laplacian.ApplyStiffness(x.data(), y.data(), 1, threads);
  double r = 0.0, size = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i)
  {
    if (!p.Fixed[i])
    {
      r += (2.0 * y[i] - b[i]) * (2.0 * y[i] - b[i]);
      size += b[i] * b[i];
    }
  }
  return size > 0.0 ? std::sqrt(r / size) : std::sqrt(r);
}

/// Pins one row in each component that no fixed row anchors; returns the
/// pinned components (1 per component id).
std::vector<std::uint8_t> PinFloatingComponents(Poisson& p)
{
  const Index n = p.Laplacian.NumberOfVertices;
  std::vector<std::uint8_t> anchored(p.Component.size(), 0), floating(p.Component.size(), 0);
  for (Index i = 0; i < n; ++i)
  {
    if (p.Fixed[i] && p.Laplacian.Diagonal[i] > 0.0)
    {
      anchored[p.Component[i]] = 1;
    }
  }
  for (Index i = 0; i < n; ++i)
  {
    const Index c = p.Component[i];
    if (!anchored[c] && p.Laplacian.Diagonal[i] > 0.0)
    {
      anchored[c] = floating[c] = 1;
      p.Fixed[i] = 1;
    }
  }
  return floating;
}

/// Zero mean (mass-weighted) on the floating components.
void RemoveMeans(const Poisson& p, const std::vector<std::uint8_t>& floating, std::vector<double>& x)
{
  const Index n = p.Laplacian.NumberOfVertices;
  std::vector<double> sum(p.Component.size(), 0.0), mass(p.Component.size(), 0.0);
  for (Index i = 0; i < n; ++i)
  {
    sum[p.Component[i]] += p.Laplacian.Mass[i] * x[i];
    mass[p.Component[i]] += p.Laplacian.Mass[i];
  }
  for (Index i = 0; i < n; ++i)
  {
    const Index c = p.Component[i];
    if (floating[c] && mass[c] > 0.0)
    {
      x[i] -= sum[c] / mass[c];
    }
  }
}

/// The direct solve; where it fails or misses the tolerance, conjugate
/// gradients preconditioned by multigrid (from zero).
std::vector<double> SolvePoisson(Poisson& p, const std::vector<double>& b, double scale,
  const VectorFieldOptions& o, VectorFieldDecomposition& r)
{
  const Index n = p.Laplacian.NumberOfVertices;
  const std::vector<std::uint8_t> floating = PinFloatingComponents(p);
  std::vector<double> x(n, 0.0);
  if (std::all_of(p.Fixed.begin(), p.Fixed.end(), [](std::uint8_t f) { return f != 0; }))
  {
    return x; // nothing to solve (no triangle with area)
  }
  double residual = 1.0;
  if (SolveDirectly(p, b, o.NumberOfThreads, x))
  {
    residual = RelativeResidual(p, b, x, o.NumberOfThreads);
  }
  if (!(residual <= o.Tolerance))
  {
    std::fill(x.begin(), x.end(), 0.0);
    ShiftedLaplacianProblem pb = p.Laplacian.Problem(1);
    pb.Factor = 2.0;
    pb.Fixed = p.Fixed.data();
    pb.Scale.assign(1, scale);
    pb.Tolerance = o.Tolerance;
    pb.MaximumIterations = 20000;
    pb.NumberOfThreads = o.NumberOfThreads;
    pb.Preconditioner = Preconditioning::Multigrid;
    const ConjugateGradientResult result = SolveShiftedLaplacian(pb, b.data(), x.data());
    r.Iterations += result.Iterations;
    r.Converged = r.Converged && result.Converged;
    residual = RelativeResidual(p, b, x, o.NumberOfThreads);
  }
  r.Residual = std::max(r.Residual, residual);
  RemoveMeans(p, floating, x);
  return x;
}

/// The curl-free part: the potential u and grad u per triangle; also the
/// divergence and curl at the vertices (they share the loop over corners).
void CurlFreePart(const MeshTopology& topo, const double* points, const TriangleFrames& f,
  const std::vector<Index>& component, double scale, const VectorFieldOptions& o, VectorFieldDecomposition& r)
{
  const Index nv = topo.NumberOfVertices();
  const IndexArray& tri = topo.TriangleList();
  GraphLaplacian lap;
  AssembleSurfaceLaplacian(topo, points, LaplacianWeights::Cotangent, lap, o.NumberOfThreads);
  std::vector<double> b(nv, 0.0);
  r.Divergence.assign(nv, 0.0);
  r.Curl.assign(nv, 0.0);
  ParallelFor(nv, o.NumberOfThreads, [&](std::int64_t begin, std::int64_t end) {
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
  Poisson p{ lap, std::vector<std::uint8_t>(nv, 0), component, points };
  for (Index i = 0; i < nv; ++i)
  {
    const bool boundary = (topo.VertexFlags(i) & VertexBoundary) != 0;
    p.Fixed[i] = !(lap.Diagonal[i] > 0.0) || (boundary && o.Boundary == VectorFieldBoundary::NormalCurlFree);
  }
  r.Potential = SolvePoisson(p, b, scale, o, r);
  r.CurlFree.assign(r.Tangent.size(), 0.0);
  ParallelFor(topo.NumberOfTriangles(), o.NumberOfThreads, [&](std::int64_t begin, std::int64_t end) {
    for (std::int64_t t = begin; t < end; ++t)
    {
      if (f.Areas[t] == 0.0)
      {
        continue;
      }
      const Vec3 n(&f.Normals[3 * t]);
      Vec3 g = Vec3::Zero();
      for (Index c = static_cast<Index>(3 * t); c < 3 * t + 3; ++c)
      {
        g += r.Potential[tri[c]] * n.cross(Side(points, tri, c));
      }
      Store(&r.CurlFree[3 * t], g / (2.0 * f.Areas[t]));
    }
  });
}

/// Whether every component is closed, manifold, oriented and of genus 0
/// (Euler characteristic 2), without zero-area triangles: no harmonic fields.
bool ClosedGenusZero(const MeshTopology& topo, const std::vector<Index>& component, Index degenerate)
{
  const TopologySummary& s = topo.Summary();
  if (!s.IsClosed() || !s.IsManifold() || !s.IsOriented() || degenerate > 0)
  {
    return false;
  }
  const MeshTopology::EdgeTable& edges = topo.Edges();
  std::vector<std::int64_t> euler(component.size(), 0); // by component id
  for (Index v = 0; v < topo.NumberOfVertices(); ++v)
  {
    euler[component[v]] += topo.Valence(v) > 0;
  }
  for (std::int64_t e = 0; e < edges.NumberOfEdges(); ++e)
  {
    --euler[component[edges.Vertices[2 * e]]];
  }
  for (Index t = 0; t < topo.NumberOfTriangles(); ++t)
  {
    ++euler[component[topo.TriangleList()[3 * static_cast<std::int64_t>(t)]]];
  }
  for (Index v = 0; v < topo.NumberOfVertices(); ++v)
  {
    if (component[v] == v && topo.Valence(v) > 0 && euler[v] != 2)
    {
      return false;
    }
  }
  return true;
}

/// On closed genus-0 components the rest X - grad u is all divergence-free:
/// its stream function (grad v = J^T (X - grad u) = -n x (X - grad u) on each
/// triangle) by integration from edge midpoint to edge midpoint, breadth
/// first over the triangles from one edge per component, then zero mean.
std::vector<double> IntegrateStreamFunction(const MeshTopology& topo, const double* points, const TriangleFrames& f,
  const EdgeGraph& graph, const VectorFieldDecomposition& r)
{
  const MeshTopology::EdgeTable& edges = topo.Edges();
  const IndexArray& tri = topo.TriangleList();
  const Index nt = topo.NumberOfTriangles();
  std::vector<double> v(static_cast<std::size_t>(edges.NumberOfEdges()), 0.0);
  std::vector<std::uint8_t> known(v.size(), 0), visited(nt, 0);
  const auto midpoint = [&](Index c) -> Vec3 { // (a Vec3, not an expression of temporaries)
    return 0.5 * (Point(points, tri[MeshTopology::Next(c)]) + Point(points, tri[MeshTopology::Prev(c)]));
  };
  std::vector<Index> queue, members;
  for (Index start = 0; start < nt; ++start)
  {
    if (visited[start])
    {
      continue;
    }
    known[graph.TriangleEdges[3 * static_cast<std::int64_t>(start)]] = 1;
    visited[start] = 1;
    queue.assign(1, start);
    members.clear();
    for (std::size_t q = 0; q < queue.size(); ++q)
    {
      const std::int64_t t = queue[q];
      const Vec3 n(&f.Normals[3 * t]);
      const Vec3 gradient = -n.cross(Vec3(&r.Tangent[3 * t]) - Vec3(&r.CurlFree[3 * t]));
      Index from = static_cast<Index>(3 * t);
      while (!known[graph.TriangleEdges[from]])
      {
        ++from;
      }
      for (Index c = static_cast<Index>(3 * t); c < 3 * t + 3; ++c)
      {
        const Index e = graph.TriangleEdges[c];
        if (!known[e])
        {
          v[e] = v[graph.TriangleEdges[from]] + gradient.dot(midpoint(c) - midpoint(from));
          known[e] = 1;
          members.push_back(e);
        }
        for (int s = 0; s < 2; ++s)
        {
          const Index across = edges.OppositeCorners[2 * static_cast<std::int64_t>(e) + s] / 3;
          if (!visited[across])
          {
            visited[across] = 1;
            queue.push_back(across);
          }
        }
      }
    }
    // Zero mean over the component (the lumped mass: a third of each triangle per edge).
    double sum = 0.0, mass = 0.0;
    for (const Index t : queue)
    {
      for (Index c = 3 * t; c < 3 * t + 3; ++c)
      {
        sum += f.Areas[t] / 3.0 * v[graph.TriangleEdges[c]];
        mass += f.Areas[t] / 3.0;
      }
    }
    members.push_back(graph.TriangleEdges[3 * static_cast<std::int64_t>(start)]);
    for (const Index e : members)
    {
      v[e] -= sum / mass;
    }
  }
  return v;
}

/// The nonconforming stream function by its Poisson system.
std::vector<double> SolveStreamFunction(const MeshTopology& topo, const double* points, const EdgeGraph& graph,
  const std::vector<Index>& vertexComponent, double scale, const VectorFieldOptions& o, VectorFieldDecomposition& r)
{
  const MeshTopology::EdgeTable& edges = topo.Edges();
  const IndexArray& tri = topo.TriangleList();
  const Index ne = static_cast<Index>(edges.NumberOfEdges());
  GraphLaplacian lap;
  AssembleNonconformingLaplacian(topo, graph, points, lap, o.NumberOfThreads);
  std::vector<double> b(ne, 0.0);
  std::vector<Index> component(ne);
  std::vector<double> midpoints(3 * static_cast<std::size_t>(ne));
  Poisson p{ lap, std::vector<std::uint8_t>(ne, 0), component, midpoints.data() };
  ParallelFor(ne, o.NumberOfThreads, [&](std::int64_t begin, std::int64_t end) {
    for (Index e = static_cast<Index>(begin); e < end; ++e)
    {
      for (int s = 0; s < 2; ++s)
      {
        const Index c = edges.OppositeCorners[2 * static_cast<std::int64_t>(e) + s];
        if (c >= 0)
        {
          b[e] += Vec3(&r.Tangent[3 * static_cast<std::int64_t>(c / 3)]).dot(Side(points, tri, c));
        }
      }
      const Index a = edges.Vertices[2 * static_cast<std::int64_t>(e)], c = edges.Vertices[2 * static_cast<std::int64_t>(e) + 1];
      component[e] = vertexComponent[a];
      Store(&midpoints[3 * static_cast<std::size_t>(e)], 0.5 * (Point(points, a) + Point(points, c)));
      const bool boundary = edges.FaceCount[e] == 1;
      p.Fixed[e] = !(lap.Diagonal[e] > 0.0) || edges.FaceCount[e] > 2 ||
        (boundary && o.Boundary == VectorFieldBoundary::TangentDivergenceFree);
    }
  });
  return SolvePoisson(p, b, scale, o, r);
}

/// The divergence-free part: the nonconforming stream function v (solved,
/// or integrated where there are no harmonic fields) and J grad v =
/// sum_k v_k e_k / A per triangle.
void DivergenceFreePart(const MeshTopology& topo, const double* points, const TriangleFrames& f,
  const std::vector<Index>& vertexComponent, double scale, const VectorFieldOptions& o, VectorFieldDecomposition& r)
{
  const IndexArray& tri = topo.TriangleList();
  EdgeGraph graph;
  graph.Build(topo);
  r.StreamFunction = o.Integrate && ClosedGenusZero(topo, vertexComponent, r.DegenerateTriangles)
    ? IntegrateStreamFunction(topo, points, f, graph, r)
    : SolveStreamFunction(topo, points, graph, vertexComponent, scale, o, r);
  r.DivergenceFree.assign(r.Tangent.size(), 0.0);
  ParallelFor(topo.NumberOfTriangles(), o.NumberOfThreads, [&](std::int64_t begin, std::int64_t end) {
    for (std::int64_t t = begin; t < end; ++t)
    {
      if (f.Areas[t] == 0.0)
      {
        continue;
      }
      Vec3 g = Vec3::Zero();
      for (Index c = static_cast<Index>(3 * t); c < 3 * t + 3; ++c)
      {
        g += r.StreamFunction[graph.TriangleEdges[c]] * Side(points, tri, c);
      }
      Store(&r.DivergenceFree[3 * t], g / f.Areas[t]);
    }
  });
}

/// The harmonic remainder, the energies and the inner products.
void HarmonicPart(const TriangleFrames& f, int threads, VectorFieldDecomposition& r)
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
      const double a = f.Areas[t];
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

} // namespace

void DecomposeVectorField(const MeshTopology& topo, const double* points, const double* vectors,
  const VectorFieldOptions& o, VectorFieldDecomposition& r)
{
  r = VectorFieldDecomposition();
  const TriangleFrames frames = MakeFrames(topo, points, o.NumberOfThreads);
  r.DegenerateTriangles = static_cast<Index>(std::count(frames.Areas.begin(), frames.Areas.end(), 0.0));
  ProjectToTangent(frames, vectors, r, o.NumberOfThreads);
  // The size of the potentials: the largest vector times the extent.
  double largest = 0.0;
  for (std::size_t k = 0; k < r.Tangent.size(); ++k)
  {
    largest = std::max(largest, std::abs(r.Tangent[k]));
  }
  Eigen::AlignedBox3d box;
  for (Index v = 0; v < topo.NumberOfVertices(); ++v)
  {
    if (topo.Valence(v) > 0)
    {
      box.extend(Point(points, v));
    }
  }
  const double scale = largest * (box.isEmpty() ? 1.0 : std::max(box.diagonal().norm(), 1e-300));
  const std::vector<Index> component = VertexComponents(topo);
  CurlFreePart(topo, points, frames, component, scale, o, r);
  DivergenceFreePart(topo, points, frames, component, scale, o, r);
  HarmonicPart(frames, o.NumberOfThreads, r);
  r.Areas = frames.Areas;
}

std::vector<double> TriangleVectorsFromPoints(const MeshTopology& topo, const double* pointVectors)
{
  const IndexArray& tri = topo.TriangleList();
  std::vector<double> out(tri.size(), 0.0);
  for (std::size_t c = 0; c < tri.size(); ++c)
  {
    const std::size_t t = c / 3;
    for (int k = 0; k < 3; ++k)
    {
      out[3 * t + k] += pointVectors[3 * static_cast<std::int64_t>(tri[c]) + k] / 3.0;
    }
  }
  return out;
}

std::vector<double> PointValuesFromTriangles(
  const MeshTopology& topo, const double* points, const double* triangleValues, int components)
{
  const Index nv = topo.NumberOfVertices();
  const IndexArray& tri = topo.TriangleList();
  std::vector<double> out(static_cast<std::size_t>(components) * nv, 0.0);
  ParallelFor(nv, topo.NumberOfThreads(), [&](std::int64_t begin, std::int64_t end) {
    for (Index v = static_cast<Index>(begin); v < end; ++v)
    {
      double* sum = &out[static_cast<std::size_t>(components) * v];
      double weight = 0.0;
      for (const Index* c = topo.CornersBegin(v); c != topo.CornersEnd(v); ++c)
      {
        const std::int64_t t = *c / 3;
        const Vec3 a = Point(points, tri[3 * t]), b = Point(points, tri[3 * t + 1]), d = Point(points, tri[3 * t + 2]);
        const double area = 0.5 * (b - a).cross(d - a).norm();
        if (area > 0.0) // (NaN: left out)
        {
          for (int k = 0; k < components; ++k)
          {
            sum[k] += area * triangleValues[components * t + k];
          }
          weight += area;
        }
      }
      for (int k = 0; weight > 0.0 && k < components; ++k)
      {
        sum[k] /= weight;
      }
    }
  });
  return out;
}

std::vector<double> PointValuesFromEdges(const MeshTopology& topo, const double* edgeValues)
{
  const MeshTopology::EdgeTable& edges = topo.Edges();
  const Index nv = topo.NumberOfVertices();
  std::vector<double> out(nv, std::numeric_limits<double>::quiet_NaN());
  for (Index v = 0; v < nv; ++v)
  {
    const std::int64_t first = edges.NeighborOffsets[v], last = edges.NeighborOffsets[v + 1];
    if (last > first)
    {
      double sum = 0.0;
      for (std::int64_t k = first; k < last; ++k)
      {
        sum += edgeValues[edges.NeighborEdges[k]];
      }
      out[v] = sum / static_cast<double>(last - first);
    }
  }
  return out;
}

} // namespace beltrami
