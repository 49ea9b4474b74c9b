#include "Mesh/VectorFields.h"

#include "Mesh/Geometry.h"
#include "Mesh/Laplacian.h"
#include "Mesh/MeshMeasures.h"
#include "Mesh/VectorFieldsDetail.h"
#include "Solvers/GraphSolvers.h"
#include "Solvers/NestedDissection.h"
#include "Solvers/SparseFactorization.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <utility>

namespace beltrami
{

using namespace detail;

namespace
{

/// One Poisson system of the decomposition, prepared once per surface:
/// K x = b on the rows of the Laplacian (true stiffness: twice the
/// assembler's normalization), the fixed rows kept at 0, one row pinned in
/// each component with none fixed (the solution then gets zero mean there:
/// the function is defined up to a constant).  Factorized by a sparse
/// Cholesky in nested-dissection order; where that fails or misses the
/// tolerance, conjugate gradients preconditioned by multigrid.
class PoissonSystem
{
public:
  /// `laplacian` (moved in) on the graph of `positions` (3 per row: where
  /// each unknown lives, for the elimination order). `multigrid`: the rows
  /// are a surface's vertices, solved by conjugate gradients on their
  /// geometric multigrid instead of factorized (the factorization is the
  /// fallback, made when the multigrid solve misses the tolerance). Not for
  /// the edges' system: on the graph of the edge midpoints the surface
  /// hierarchy took 445 iterations (eight, 324k vertices).
  PoissonSystem(GraphLaplacian laplacian, std::vector<std::uint8_t> fixed, std::vector<Index> component,
    const double* positions, bool multigrid, const VectorFieldOptions& options)
    : L(std::move(laplacian))
    , Fixed(std::move(fixed))
    , Component(std::move(component))
    , Options(options)
    , Vertices(multigrid ? positions : nullptr)
  {
    PinFloatingComponents();
    if (!multigrid && !AllFixed())
    {
      Factorize(positions);
    }
  }

  /// The solution of K x = b (zero mean on the floating components): by
  /// multigrid, else the factorization, else conjugate gradients on
  /// BoomerAMG (where the factorization failed).
  std::vector<double> Solve(const std::vector<double>& b, double scale, VectorFieldDecomposition& r)
  {
    const Index n = L.NumberOfVertices;
    std::vector<double> x(n, 0.0);
    if (AllFixed())
    {
      return x; // nothing to solve (no triangle with area)
    }
    double residual = 1.0;
    bool converged = true; // the last solver's own verdict
    if (Vertices)
    {
      // Multigrid for as many iterations as good meshes take; where it
      // converges more slowly than a factorization solves (the anisotropic
      // triangles of a latitude-longitude grid: 239 iterations and 5.0 s at
      // 258k points, factorized 1.1 s), the factorization instead.
      residual = SolveIteratively(b, scale, Preconditioning::GeometricMultigrid, FirstIterations, x, r, converged);
      const double expected = FirstIterations * std::log(Options.Tolerance) / std::log(residual);
      if (!(residual <= Options.Tolerance) && residual < 1.0 && expected <= MostIterations)
      {
        residual = SolveIteratively(
          b, scale, Preconditioning::GeometricMultigrid, MostIterations - FirstIterations, x, r, converged);
      }
      if (!(residual <= Options.Tolerance) && !Factor)
      {
        Factorize(Vertices);
      }
    }
    if (!(residual <= Options.Tolerance) && Factor)
    {
      Eigen::MatrixXd rhs(n, 1);
      for (Index i = 0; i < n; ++i)
      {
        rhs(i, 0) = Fixed[i] ? 0.0 : b[i];
      }
      const Eigen::MatrixXd solution = Factor->Solve(rhs);
      x.assign(solution.data(), solution.data() + n);
      residual = Refine(b, x);
      converged = true;
    }
    if (!(residual <= Options.Tolerance))
    {
      std::fill(x.begin(), x.end(), 0.0);
      residual = SolveIteratively(b, scale, Preconditioning::Multigrid, 20000, x, r, converged);
    }
    r.Converged = r.Converged && converged;
    r.Residual = std::max(r.Residual, residual);
    RemoveMeans(x);
    return x;
  }

  const GraphLaplacian& Laplacian() const { return L; }

private:
  /// Pins one row in each component that no fixed row anchors.
  void PinFloatingComponents()
  {
    const Index n = L.NumberOfVertices;
    std::vector<std::uint8_t> anchored(Component.size(), 0);
    Floating.assign(Component.size(), 0);
    for (Index i = 0; i < n; ++i)
    {
      if (Fixed[i] && L.Diagonal[i] > 0.0)
      {
        anchored[Component[i]] = 1;
      }
    }
    for (Index i = 0; i < n; ++i)
    {
      const Index c = Component[i];
      if (!anchored[c] && L.Diagonal[i] > 0.0)
      {
        anchored[c] = Floating[c] = 1;
        Fixed[i] = 1;
      }
    }
  }

  bool AllFixed() const
  {
    return std::all_of(Fixed.begin(), Fixed.end(), [](std::uint8_t f) { return f != 0; });
  }

  /// x from conjugate gradients from x, at most `iterations` of them: with
  /// the surface's geometric multigrid (the rows are vertices; its
  /// hierarchy built once) or BoomerAMG; the relative residual, and the
  /// solver's verdict in `converged`.
  double SolveIteratively(const std::vector<double>& b, double scale, Preconditioning preconditioner,
    int iterations, std::vector<double>& x, VectorFieldDecomposition& r, bool& converged)
  {
    ShiftedLaplacianProblem pb = L.Problem(1);
    pb.Factor = 2.0;
    pb.Fixed = Fixed.data();
    pb.Scale.assign(1, scale);
    pb.Tolerance = Options.Tolerance;
    pb.MaximumIterations = iterations;
    pb.NumberOfThreads = Options.NumberOfThreads;
    pb.Preconditioner = preconditioner;
    pb.Points = Vertices;
    pb.KeptHierarchy = &Hierarchy;
    const ConjugateGradientResult result = SolveShiftedLaplacian(pb, b.data(), x.data());
    r.Iterations += result.Iterations;
    converged = result.Converged;
    return RelativeResidual(b, x);
  }

  /// The matrix (the fixed rows identity rows) and its factorization; no
  /// factorization where it fails.
  void Factorize(const double* positions)
  {
    const Index n = L.NumberOfVertices;
    Outer.assign(static_cast<std::size_t>(n) + 1, 0);
    Inner.reserve(static_cast<std::size_t>(L.Offsets[n]) + n);
    Values.reserve(Inner.capacity());
    for (Index i = 0; i < n; ++i) // column i (symmetric): the free neighbours and the diagonal, ascending
    {
      bool diagonal = false;
      for (std::int64_t k = L.Offsets[i]; !Fixed[i] && k < L.Offsets[i + 1]; ++k)
      {
        const Index j = L.Neighbors[k];
        if (!diagonal && j > i)
        {
          Inner.push_back(i);
          Values.push_back(2.0 * L.Diagonal[i]);
          diagonal = true;
        }
        if (!Fixed[j])
        {
          Inner.push_back(j);
          Values.push_back(-2.0 * L.Weights[k]);
        }
      }
      if (!diagonal)
      {
        Inner.push_back(i);
        Values.push_back(Fixed[i] ? 1.0 : 2.0 * L.Diagonal[i]);
      }
      Outer[i + 1] = static_cast<int>(Inner.size());
    }
    const SparseFactorization::MatrixView a(
      n, n, static_cast<Eigen::Index>(Inner.size()), Outer.data(), Inner.data(), Values.data());
    const std::vector<Index> order =
      NestedDissectionOrder(n, L.Offsets, L.Neighbors, positions, Options.NumberOfThreads);
    Factor = std::make_unique<SparseFactorization>();
    if (!Factor->Compute(a, true, std::vector<int>(order.begin(), order.end()), false, Options.NumberOfThreads))
    {
      Factor.reset();
    }
  }

  /// The relative residual of K x = b on the free rows (NaN x: 1);
  /// `residual` (optional): b - K x there, 0 on the fixed rows.
  double RelativeResidual(const std::vector<double>& b, const std::vector<double>& x,
    Eigen::MatrixXd* residual = nullptr) const
  {
    std::vector<double> y(x.size());
    L.ApplyStiffness(x.data(), y.data(), 1, Options.NumberOfThreads);
    double r = 0.0, size = 0.0;
    for (std::size_t i = 0; i < x.size(); ++i)
    {
      const double ri = Fixed[i] ? 0.0 : b[i] - 2.0 * y[i];
      r += ri * ri;
      size += Fixed[i] ? 0.0 : b[i] * b[i];
      if (residual)
      {
        (*residual)(static_cast<Eigen::Index>(i), 0) = ri;
      }
    }
    const double relative = size > 0.0 ? std::sqrt(r / size) : std::sqrt(r);
    return std::isfinite(relative) ? relative : 1.0;
  }

  /// Iterative refinement of the factorization's solution x (at most three
  /// corrections x += K^-1 (b - K x), while they lower the residual): on a
  /// locally refined mesh the edges' system is so ill-conditioned that the
  /// triangular solves alone miss the tolerance (cylinder_locally_refined
  /// after two Loop subdivisions), where an iterative solver then took
  /// hundreds of iterations.  The relative residual.
  double Refine(const std::vector<double>& b, std::vector<double>& x) const
  {
    const Eigen::Index n = static_cast<Eigen::Index>(x.size());
    Eigen::MatrixXd residual(n, 1);
    double relative = RelativeResidual(b, x, &residual);
    for (int step = 0; step < 3 && !(relative <= Options.Tolerance); ++step)
    {
      const Eigen::MatrixXd correction = Factor->Solve(residual);
      std::vector<double> refined(x);
      for (Eigen::Index i = 0; i < n; ++i)
      {
        refined[i] += Fixed[i] ? 0.0 : correction(i, 0);
      }
      Eigen::MatrixXd next(n, 1);
      const double lower = RelativeResidual(b, refined, &next);
      if (!(lower < relative))
      {
        break;
      }
      x.swap(refined);
      residual.swap(next);
      relative = lower;
    }
    return relative;
  }

  /// Zero mean (mass-weighted) on the floating components.
  void RemoveMeans(std::vector<double>& x) const
  {
    const Index n = L.NumberOfVertices;
    std::vector<double> sum(Component.size(), 0.0), mass(Component.size(), 0.0);
    for (Index i = 0; i < n; ++i)
    {
      sum[Component[i]] += L.Mass[i] * x[i];
      mass[Component[i]] += L.Mass[i];
    }
    for (Index i = 0; i < n; ++i)
    {
      const Index c = Component[i];
      if (Floating[c] && mass[c] > 0.0)
      {
        x[i] -= sum[c] / mass[c];
      }
    }
  }

  GraphLaplacian L;
  std::vector<std::uint8_t> Fixed;    ///< boundary conditions, rows without coupling, the pins
  std::vector<Index> Component;       ///< per row: its component's id (a vertex id)
  std::vector<std::uint8_t> Floating; ///< per component id: pinned (no boundary condition)
  VectorFieldOptions Options;
  std::vector<int> Outer, Inner;      ///< the factorized matrix (compressed columns), kept for it
  std::vector<double> Values;
  std::unique_ptr<SparseFactorization> Factor;
  /// Multigrid: the rows' points (the surface's, kept alive by the
  /// caller), for the geometric multigrid; else null.
  const double* Vertices;
  std::shared_ptr<const SurfaceHierarchy> Hierarchy; ///< built by the first multigrid solve
  /// The multigrid's first pass: good meshes converge within it (13-24
  /// iterations on the benchmark meshes). A second pass follows where the
  /// rate so far promises convergence within MostIterations in all (CG's
  /// rate can slow down: a latitude sphere of 57k points met the promise
  /// and then took 206), else, or when it misses, the factorization.
  static constexpr int FirstIterations = 30;
  static constexpr int MostIterations = 80;
};

} // namespace

struct VectorFieldDecomposer::Internals
{
  Internals(const MeshTopology& topo, const double* points, const VectorFieldOptions& o);

  const MeshTopology& Topology;
  /// Coordinates far from unit size (FarScaleExponent e != 0) are worked
  /// on as the points times 2^-e (exactly), and the results scaled back:
  /// otherwise squared areas overflow or vanish (all triangles zero-area
  /// beyond about 1e+-77).
  int Exponent;
  std::vector<double> Scaled; ///< the points times 2^-Exponent (when not 0)
  const double* Points;       ///< those worked on
  VectorFieldOptions Options;
  TriangleFrames Frames;
  Index DegenerateTriangles = 0;
  std::vector<Index> Component; ///< per vertex: its component's id
  double Extent = 1.0;          ///< the bounding box's diagonal
  std::unique_ptr<PoissonSystem> Potential;
  EdgeGraph Graph;
  bool Integrate = false;       ///< no harmonic fields: the stream function integrated
  std::unique_ptr<PoissonSystem> Stream;

  /// The stream function of X - grad u (r's Tangent and CurlFree),
  /// integrated (detail::IntegrateStreamFunction).
  std::vector<double> IntegratedStreamFunction(const VectorFieldDecomposition& r) const;
};

VectorFieldDecomposer::Internals::Internals(const MeshTopology& topo, const double* points, const VectorFieldOptions& o)
  : Topology(topo)
  , Exponent(FarScaleExponent(UsedPointsBox(topo, points)))
  , Scaled(Exponent ? PointsTimesPowerOfTwo(points, topo.NumberOfVertices(), -Exponent) : std::vector<double>())
  , Points(Exponent ? Scaled.data() : points)
  , Options(o)
  , Frames(MakeFrames(topo, Points, o.NumberOfThreads))
  , DegenerateTriangles(static_cast<Index>(std::count(Frames.Areas.begin(), Frames.Areas.end(), 0.0)))
  , Component(topo.ComponentRoots())
{
  const Index nv = topo.NumberOfVertices();
  const Eigen::AlignedBox3d box = UsedPointsBox(topo, Points);
  Extent = box.isEmpty() ? 1.0 : std::max(box.diagonal().norm(), 1e-300);
  GraphLaplacian cotangent;
  AssembleSurfaceLaplacian(topo, Points, LaplacianWeights::Cotangent, cotangent, o.NumberOfThreads);
  std::vector<std::uint8_t> fixed = FixedVertices(topo, Frames, cotangent, o.Boundary);
  // One field on many vertices: multigrid. A factorization costs more
  // than the multigrid's set-up and solve (bunny Loop-subdivided, 151k
  // vertices: 0.80 s against 0.48 s for the whole decomposition; equal at
  // 38k) but makes each further field's solve a tenth of it.
  const bool multigrid = !o.ManyFields && nv >= o.MultigridVertices;
  Potential =
    std::make_unique<PoissonSystem>(std::move(cotangent), std::move(fixed), Component, Points, multigrid, o);
  Integrate = o.Integrate && detail::NoHarmonicFields(topo, Component, DegenerateTriangles);
  Graph.Build(topo, !Integrate); // the integration needs each triangle's edges alone
  if (Integrate)
  {
    return;
  }
  const MeshTopology::EdgeTable& edges = topo.Edges();
  const Index ne = static_cast<Index>(edges.NumberOfEdges());
  GraphLaplacian nonconforming;
  AssembleNonconformingLaplacian(topo, Graph, Points, nonconforming, o.NumberOfThreads);
  std::vector<std::uint8_t> fixedEdges = FixedEdges(topo, Frames, nonconforming, o.Boundary);
  std::vector<Index> component(ne);
  std::vector<double> midpoints(3 * static_cast<std::size_t>(ne));
  for (Index e = 0; e < ne; ++e)
  {
    const Index a = edges.Vertices[2 * static_cast<std::int64_t>(e)], b = edges.Vertices[2 * static_cast<std::int64_t>(e) + 1];
    component[e] = Component[a];
    Store(&midpoints[3 * static_cast<std::size_t>(e)], 0.5 * (Point(Points, a) + Point(Points, b)));
  }
  Stream = std::make_unique<PoissonSystem>(
    std::move(nonconforming), std::move(fixedEdges), std::move(component), midpoints.data(), false, o);
}

std::vector<double> VectorFieldDecomposer::Internals::IntegratedStreamFunction(
  const VectorFieldDecomposition& r) const
{
  std::vector<double> rest(r.Tangent.size());
  for (std::size_t k = 0; k < rest.size(); ++k)
  {
    rest[k] = r.Tangent[k] - r.CurlFree[k];
  }
  return detail::IntegrateStreamFunction(Topology, Points, Frames, Graph, Options.Boundary, rest);
}

VectorFieldDecomposer::VectorFieldDecomposer(
  const MeshTopology& topology, const double* points, const VectorFieldOptions& options)
  : I(std::make_unique<Internals>(topology, points, options))
{
}

VectorFieldDecomposer::~VectorFieldDecomposer() = default;

void VectorFieldDecomposer::Decompose(const double* vectors, VectorFieldDecomposition& r) const
{
  const MeshTopology& topo = I->Topology;
  const int threads = I->Options.NumberOfThreads;
  r = VectorFieldDecomposition();
  r.DegenerateTriangles = I->DegenerateTriangles;
  ProjectToTangent(I->Frames, vectors, r, threads);
  double largest = 0.0; // the size of the potentials: the largest vector times the extent
  for (const double x : r.Tangent)
  {
    largest = std::max(largest, std::abs(x));
  }
  // A field far from unit size (whose squared norms overflow or vanish) is
  // decomposed as the field times 2^-f, exactly; the results scaled back.
  int f = 0;
  if (largest > 0.0 && std::isfinite(largest))
  {
    std::frexp(largest, &f);
    f = std::abs(f) > 60 ? f : 0;
  }
  TimesPowerOfTwo(r.Tangent.data(), r.Tangent.size(), -f);
  const double scale = std::ldexp(largest, -f) * I->Extent;
  r.Potential = I->Potential->Solve(PotentialRightHandSide(topo, I->Points, I->Frames, threads, r), scale, r);
  GradientPart(topo, I->Points, I->Frames, threads, r);
  r.Integrated = I->Integrate;
  r.StreamFunction = I->Integrate ? I->IntegratedStreamFunction(r)
                                  : I->Stream->Solve(StreamRightHandSide(topo, I->Points, threads, r), scale, r);
  RotatedGradientPart(topo, I->Points, I->Frames, I->Graph, threads, r);
  HarmonicPart(I->Frames, threads, r);
  r.Areas = I->Frames.Areas;
  ScaleBack(I->Exponent, f, r);
}

void DecomposeVectorField(const MeshTopology& topo, const double* points, const double* vectors,
  const VectorFieldOptions& o, VectorFieldDecomposition& r)
{
  VectorFieldDecomposer(topo, points, o).Decompose(vectors, r);
}

std::vector<double> PointValuesFromTriangles(
  const MeshTopology& topo, const std::vector<double>& areas, const double* triangleValues, int components)
{
  const Index nv = topo.NumberOfVertices();
  std::vector<double> out(static_cast<std::size_t>(components) * nv, 0.0);
  ParallelFor(nv, topo.NumberOfThreads(), [&](std::int64_t begin, std::int64_t end) {
    for (Index v = static_cast<Index>(begin); v < end; ++v)
    {
      double* sum = &out[static_cast<std::size_t>(components) * v];
      double weight = 0.0;
      for (const Index* c = topo.CornersBegin(v); c != topo.CornersEnd(v); ++c)
      {
        const std::int64_t t = *c / 3;
        for (int k = 0; k < components; ++k)
        {
          sum[k] += areas[t] * triangleValues[components * t + k];
        }
        weight += areas[t];
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
