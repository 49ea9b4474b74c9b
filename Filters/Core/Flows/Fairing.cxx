#include "Flows/Fairing.h"

#include "Flows/FairingAnisotropy.h"
#include "Flows/FairingInvariants.h"
#include "Solvers/ConjugateGradient.h"
#include "Solvers/GraphSolvers.h"
#include "Mesh/Curvatures.h"
#include "Mesh/Laplacian.h"
#include "Mesh/MeshMeasures.h"
#include "Mesh/RingGeometry.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace beltrami
{

using namespace detail;

namespace
{

/// The Laplacian of a step and what it is applied to.
struct Stage
{
  const GraphLaplacian& L;
  std::vector<std::uint8_t> Fixed; ///< rows that must not move
  std::vector<double> Omega;       ///< per-row weight (may be < 0 for anisotropy)
  const Index* Order = nullptr;    ///< LocalityOrder of L's graph, if known
};

/// y = L x = -M^-1 S x (rows without mass: 0).
void ApplyLaplacian(const GraphLaplacian& L, const double* x, double* y, int threads)
{
  L.ApplyStiffness(x, y, 3, threads);
  ParallelFor(L.NumberOfVertices, threads, [&](std::int64_t b, std::int64_t e) {
    for (std::int64_t i = b; i < e; ++i)
    {
      const double s = L.Mass[i] > 0.0 ? -1.0 / L.Mass[i] : 0.0;
      for (int c = 0; c < 3; ++c)
      {
        y[3 * i + c] *= s;
      }
    }
  });
}

/// The flow velocity without the time step: W L X (order 1) or -W L L X (order 2).
std::vector<double> Velocity(const Stage& st, int order, const double* x, int threads)
{
  const std::size_t size = 3 * static_cast<std::size_t>(st.L.NumberOfVertices);
  std::vector<double> v(size), tmp(order == 2 ? size : 0);
  ApplyLaplacian(st.L, x, v.data(), threads);
  if (order == 2)
  {
    // L is undefined at held vertices (boundaries, constraints): L^2 uses L = 0 there.
    for (Index i = 0; i < st.L.NumberOfVertices; ++i)
    {
      for (int c = 0; st.Fixed[i] && c < 3; ++c)
      {
        v[3 * i + c] = 0.0;
      }
    }
    ApplyLaplacian(st.L, v.data(), tmp.data(), threads);
    for (std::size_t k = 0; k < size; ++k)
    {
      v[k] = -tmp[k];
    }
  }
  for (Index i = 0; i < st.L.NumberOfVertices; ++i)
  {
    for (int c = 0; c < 3; ++c)
    {
      v[3 * i + c] *= st.Fixed[i] ? 0.0 : st.Omega[i];
    }
  }
  return v;
}

void ExplicitStep(const Stage& st, int order, double dt, double* x, int threads)
{
  const std::vector<double> v = Velocity(st, order, x, threads);
  for (std::size_t k = 0; k < v.size(); ++k)
  {
    x[k] += dt * v[k];
  }
}

/// Largest stable explicit time step (Gershgorin: rho(W M^-1 S) <= 2 max w S_ii / a_i;
/// for the umbrella this is the thesis' lambda*dt < 1).
double StabilityLimit(const Stage& st, int order)
{
  double m = 0.0;
  for (Index i = 0; i < st.L.NumberOfVertices; ++i)
  {
    if (!st.Fixed[i] && st.L.Mass[i] > 0.0)
    {
      m = std::max(m, std::abs(st.Omega[i]) * st.L.Diagonal[i] / st.L.Mass[i]);
    }
  }
  if (!(m > 0.0))
  {
    return std::numeric_limits<double>::infinity();
  }
  return order == 1 ? 1.0 / m : 0.5 / (m * m);
}

ConjugateGradientResult SolveOrderTwo(const Stage& st, const FairingOptions& opt, const std::vector<double>& m,
  const std::vector<double>& invMass, const std::vector<std::uint8_t>& fixed, const std::vector<double>& scale,
  const std::vector<double>& b, double* x);

/// One backward Euler step in the symmetric form of Fairing.h.  Rows with a
/// negative weight (inverse diffusion of the anisotropic flow) are advanced
/// explicitly and then held, so the system stays positive definite.
void ImplicitStep(const Stage& st, const FairingOptions& opt, double* x, FairingReport& report)
{
  const GraphLaplacian& L = st.L;
  const Index n = L.NumberOfVertices;
  const int threads = opt.NumberOfThreads;
  const int order = opt.Order;
  const double dt = opt.TimeStep;
  std::vector<std::uint8_t> fixed = st.Fixed;
  bool anyNegative = false;
  for (Index i = 0; i < n; ++i)
  {
    anyNegative = anyNegative || (!fixed[i] && st.Omega[i] < 0.0);
  }
  if (anyNegative)
  {
    const std::vector<double> v = Velocity(st, order, x, threads);
    for (Index i = 0; i < n; ++i)
    {
      if (!fixed[i] && st.Omega[i] < 0.0)
      {
        for (int c = 0; c < 3; ++c)
        {
          x[3 * i + c] += dt * v[3 * i + c];
        }
      }
    }
  }
  std::vector<double> m(n, 0.0), invMass(n, 0.0);
  Index numFree = 0;
  for (Index i = 0; i < n; ++i)
  {
    // The inner M^-1 of L^2: zero at held vertices, where L is taken as 0.
    invMass[i] = L.Mass[i] > 0.0 && !st.Fixed[i] ? 1.0 / L.Mass[i] : 0.0;
    if (fixed[i] || !(st.Omega[i] > 0.0) || !(L.Mass[i] > 0.0))
    {
      fixed[i] = 1;
      continue;
    }
    m[i] = L.Mass[i] / st.Omega[i];
    ++numFree;
  }
  if (numFree == 0)
  {
    return;
  }
  const std::size_t size = 3 * static_cast<std::size_t>(n);
  std::vector<double> b(size);
  Vec3 center = Vec3::Zero();
  for (Index i = 0; i < n; ++i)
  {
    center += Point(x, i);
  }
  center /= n;
  std::vector<double> scale(3, 0.0);
  for (Index i = 0; i < n; ++i)
  {
    for (int c = 0; c < 3; ++c)
    {
      b[3 * i + c] = m[i] * x[3 * i + c];
      if (!fixed[i])
      {
        const double d = m[i] * (x[3 * i + c] - center[c]);
        scale[c] += d * d;
      }
    }
  }
  for (double& s : scale)
  {
    s = std::sqrt(s);
  }
  ShiftedLaplacianProblem sl = L.Problem(3);
  sl.Shift = m.data();
  sl.Factor = dt;
  sl.Fixed = fixed.data();
  sl.Scale = scale;
  sl.Tolerance = opt.SolverTolerance;
  sl.MaximumIterations = opt.MaximumSolverIterations;
  sl.NumberOfThreads = threads;
  ConjugateGradientResult r;
  if (order == 1)
  {
    // A graph Laplacian plus a diagonal: the fast solver (renumbered rows,
    // single-precision corrections of a double-precision residual).
    sl.Order = st.Order;
    r = SolveShiftedLaplacian(sl, b.data(), x);
  }
  else
  {
    // M + dt S M^-1 S: with unit row weights and the inner M^-1 zero exactly
    // at the rows kept fixed, the complex-shift solver applies.
    bool squared = true;
    for (Index i = 0; squared && i < n; ++i)
    {
      squared = fixed[i] ? invMass[i] == 0.0 : std::abs(m[i] * invMass[i] - 1.0) <= 1e-12;
    }
    if (squared)
    {
      r = SolveSquaredLaplacian(sl, b.data(), x);
    }
    if (!r.Converged)
    {
      const int before = r.Iterations;
      r = SolveOrderTwo(st, opt, m, invMass, fixed, scale, b, x);
      r.Iterations += before;
    }
  }
  report.Iterations.push_back(r.Iterations);
  report.LargestResidual = std::max(report.LargestResidual, r.RelativeResidual);
  report.Converged = report.Converged && r.Converged;
}

/// The order-2 system (M W^-1 + dt S M^-1 S) X' = b, through its action.
ConjugateGradientResult SolveOrderTwo(const Stage& st, const FairingOptions& opt, const std::vector<double>& m,
  const std::vector<double>& invMass, const std::vector<std::uint8_t>& fixed, const std::vector<double>& scale,
  const std::vector<double>& b, double* x)
{
  const GraphLaplacian& L = st.L;
  const Index n = L.NumberOfVertices;
  const int threads = opt.NumberOfThreads;
  const double dt = opt.TimeStep;
  std::vector<double> tmp(3 * static_cast<std::size_t>(n)), diag(n);
  for (Index i = 0; i < n; ++i)
  {
    double s2 = L.Diagonal[i] * L.Diagonal[i] * invMass[i];
    for (std::int64_t k = L.Offsets[i]; k < L.Offsets[i + 1]; ++k)
    {
      s2 += L.Weights[k] * L.Weights[k] * invMass[L.Neighbors[k]];
    }
    diag[i] = m[i] + dt * s2;
  }
  ConjugateGradientProblem pb;
  pb.Rows = n;
  pb.Columns = 3;
  pb.Diagonal = diag.data();
  pb.Fixed = fixed.data();
  pb.Scale = scale;
  pb.Tolerance = opt.SolverTolerance;
  pb.MaximumIterations = opt.MaximumSolverIterations;
  pb.NumberOfThreads = threads;
  pb.Apply = [&](const double* in, double* out) {
    L.ApplyStiffness(in, out, 3, threads);
    for (Index i = 0; i < n; ++i)
    {
      for (int c = 0; c < 3; ++c)
      {
        tmp[3 * i + c] = out[3 * i + c] * invMass[i];
      }
    }
    L.ApplyStiffness(tmp.data(), out, 3, threads);
    ParallelFor(n, threads, [&](std::int64_t s, std::int64_t e) {
      for (std::int64_t k = 3 * s; k < 3 * e; ++k)
      {
        out[k] = m[k / 3] * in[k] + dt * out[k];
      }
    });
  };
  return SolveConjugateGradient(pb, b.data(), x);
}

/// Points with a NaN or infinite coordinate are held (VertexRoles) and their
/// triangles are left out of the operator; their zero weights would still
/// carry the NaN into every product (0 * NaN), so while it lives they take
/// part as the origin, and they get their own values back after.
class NonFinitePointsAsOrigin
{
public:
  NonFinitePointsAsOrigin(double* x, Index n)
    : X(x)
  {
    for (Index i = 0; i < n; ++i)
    {
      if (!Point(x, i).allFinite())
      {
        Saved.emplace_back(i, Point(x, i));
        std::fill(x + 3 * i, x + 3 * i + 3, 0.0);
      }
    }
  }
  ~NonFinitePointsAsOrigin()
  {
    for (const auto& [i, p] : Saved)
    {
      std::copy(p.data(), p.data() + 3, X + 3 * i);
    }
  }
  NonFinitePointsAsOrigin(const NonFinitePointsAsOrigin&) = delete;
  NonFinitePointsAsOrigin& operator=(const NonFinitePointsAsOrigin&) = delete;

private:
  double* X;
  std::vector<std::pair<Index, Vec3>> Saved;
};

void Integrate(const Stage& st, const FairingOptions& opt, double* x, FairingReport& report)
{
  const NonFinitePointsAsOrigin guard(x, st.L.NumberOfVertices);
  switch (opt.Integration)
  {
    case FairingIntegration::Implicit:
      ImplicitStep(st, opt, x, report);
      break;
    case FairingIntegration::Explicit:
    {
      const double limit = StabilityLimit(st, opt.Order);
      report.StabilityLimit = report.StabilityLimit > 0.0 ? std::min(report.StabilityLimit, limit) : limit;
      report.ExplicitUnstable = report.ExplicitUnstable || opt.TimeStep > limit * (1.0 + 1e-12);
      ExplicitStep(st, opt.Order, opt.TimeStep, x, opt.NumberOfThreads);
      break;
    }
    case FairingIntegration::TaubinLambdaMu:
      ExplicitStep(st, 1, opt.TaubinLambda, x, opt.NumberOfThreads);
      ExplicitStep(st, 1, opt.TaubinMu, x, opt.NumberOfThreads);
      break;
  }
}

LaplacianWeights WeightsOf(FairingOperator op)
{
  switch (op)
  {
    case FairingOperator::Umbrella:
      return LaplacianWeights::Umbrella;
    case FairingOperator::ScaleDependentUmbrella:
      return LaplacianWeights::InverseEdgeLength;
    default:
      return LaplacianWeights::Cotangent;
  }
}

/// Which part of a displacement d at a vertex of normal n is kept.
enum class Keep
{
  Normal,    ///< (d.n) n
  Tangential ///< d - (d.n) n
};

/// Moves x[i] by the `keep` part of d[i] (both 3 per vertex), with the
/// vertex normals of x before the move; vertices without a normal (no area,
/// NaN) or with a non-finite d[i] do not move.
void MoveAlongNormals(const MeshTopology& topo, double* x, const double* d, Keep keep, int threads)
{
  const Index n = topo.NumberOfVertices();
  std::vector<double> normals(3 * static_cast<std::size_t>(n));
  CurvatureOutputs no;
  no.Normals = normals.data();
  CurvatureOptions co;
  co.NumberOfThreads = threads;
  ComputeCurvatures(topo, static_cast<const double*>(x), co, no);
  for (Index i = 0; i < n; ++i)
  {
    const Vec3 nn = Point(normals.data(), i);
    const Vec3 di = Point(d, i);
    if (nn.allFinite() && di.allFinite())
    {
      const Vec3 along = di.dot(nn) * nn;
      const Vec3 move = keep == Keep::Normal ? along : Vec3(di - along);
      for (int c = 0; c < 3; ++c)
      {
        x[3 * i + c] += move[c];
      }
    }
  }
}

/// A copy of x after one implicit order-1 step of `time` with the `kind`
/// Laplacian (assembled into `lap` at x; `order` gives its LocalityOrder or
/// null): the pre-mollified geometries of the anisotropic weights and of
/// OperatorMollification.
template <typename OrderOf>
std::vector<double> SmoothedCopy(const MeshTopology& topo, const double* x, LaplacianWeights kind, double time,
  const std::vector<std::uint8_t>& held, const std::vector<double>& weight, const FairingOptions& opt,
  GraphLaplacian& lap, OrderOf&& order)
{
  std::vector<double> copy(x, x + 3 * static_cast<std::size_t>(topo.NumberOfVertices()));
  AssembleSurfaceLaplacian(topo, copy.data(), kind, lap, opt.NumberOfThreads);
  FairingOptions so = opt;
  so.Integration = FairingIntegration::Implicit;
  so.Order = 1;
  so.TimeStep = time;
  FairingReport ignored;
  ImplicitStep(Stage{ lap, held, weight, order() }, so, copy.data(), ignored);
  return copy;
}

/// What the flows may move: hard constraints (user-fixed or zero weight),
/// soft weights clamped to [0, 1], boundary vertices, and vertices the flows
/// cannot move (non-manifold, duplicate faces, non-finite: kept fixed).
struct VertexRoles
{
  std::vector<std::uint8_t> Fixed, Boundary;
  std::vector<double> Weight;
  bool HardConstraints = false;
};

VertexRoles ClassifyVertices(const MeshTopology& topo, const double* x, const FairingOptions& opt,
  const FairingConstraints& cons, FairingReport& report)
{
  const Index n = topo.NumberOfVertices();
  VertexRoles r;
  r.Fixed.assign(n, 0);
  r.Boundary.assign(n, 0);
  r.Weight.assign(n, 1.0);
  for (Index i = 0; i < n; ++i)
  {
    const std::uint8_t flags = topo.VertexFlags(i);
    r.Boundary[i] = (flags & VertexBoundary) != 0;
    if (cons.Weights)
    {
      const double w = cons.Weights[i];
      r.Weight[i] = std::isfinite(w) ? std::clamp(w, 0.0, 1.0) : 1.0;
    }
    const bool user = (cons.Fixed && cons.Fixed[i]) || r.Weight[i] == 0.0;
    r.HardConstraints = r.HardConstraints || user;
    const bool unusable = (flags & (VertexNonManifold | VertexDuplicateFace | VertexIsolated)) ||
      !Point(x, i).allFinite();
    report.UnusableVertices += unusable && !(flags & VertexIsolated);
    r.Fixed[i] = user || unusable || (r.Boundary[i] && opt.Boundary == FairingBoundary::Fixed);
  }
  return r;
}

/// Section 3.3.1: the invariant restored after every step (Automatic: the
/// volume of closed oriented surfaces without hard constraints), with its
/// initial value; remarks for the user go to `warn`.
InvariantState ChooseInvariant(const MeshTopology& topo, const double* x, const FairingOptions& opt,
  const VertexRoles& roles, std::ostringstream& warn, FairingReport& report)
{
  const Index n = topo.NumberOfVertices();
  const TopologySummary& info = topo.Summary();
  InvariantState inv;
  inv.Kind = opt.Invariant;
  const bool closed = info.IsClosed() && info.IsManifold() && info.IsOriented();
  if (inv.Kind == FairingInvariant::Automatic)
  {
    inv.Kind = closed && !roles.HardConstraints ? FairingInvariant::Volume : FairingInvariant::None;
  }
  if (inv.Kind == FairingInvariant::Volume && !closed)
  {
    warn << "Volume preservation needs a closed, manifold, consistently oriented surface; this one is "
         << topo.Describe() << ": no invariant is preserved. ";
    inv.Kind = FairingInvariant::None;
  }
  const bool referenced =
    inv.Kind == FairingInvariant::HeightFieldVolume || inv.Kind == FairingInvariant::RevolutionVolume;
  if (referenced)
  {
    inv.PlaneNormal = Vec3(opt.ReferencePlaneNormal[0], opt.ReferencePlaneNormal[1], opt.ReferencePlaneNormal[2]);
    if (!(inv.PlaneNormal.norm() > 0.0))
    {
      inv.PlaneNormal = Vec3::UnitZ();
    }
    inv.PlaneNormal.normalize();
    // The reference plane passes through the mean of the boundary (of all points if closed).
    Vec3 sum = Vec3::Zero();
    Index count = 0;
    for (Index i = 0; i < n; ++i)
    {
      if (roles.Boundary[i] && Point(x, i).allFinite())
      {
        sum += Point(x, i);
        ++count;
      }
    }
    inv.PlaneOrigin = count ? Vec3(sum / count) : VertexCentroid(topo, x);
  }
  if (inv.Kind == FairingInvariant::RevolutionVolume)
  {
    // The axis passes through the area centroid (on the axis of a surface of revolution).
    AreaAndCentroid(topo, x, opt.NumberOfThreads, &inv.PlaneOrigin);
  }
  if (roles.HardConstraints && inv.Kind != FairingInvariant::None)
  {
    warn << "The invariant is restored by scaling, which also moves the fixed points (section 3.3.1). ";
  }
  report.InvariantUsed = inv.Kind;
  inv.Initial = MeasureInvariant(inv, topo, x, opt.NumberOfThreads, nullptr);
  report.InitialInvariant = report.FinalInvariant = inv.Initial;
  return inv;
}

/// The operator's geometry (OperatorMollification): x moved by the normal
/// part of one implicit umbrella step.  On a noisy scan the cotangents of the
/// noisy triangles are noise too; the copy damps the noise across the
/// surface and keeps the sampling, so a flat region's copy is the region
/// itself and flat regions still never move.
std::vector<double> MollifiedOperatorPoints(const MeshTopology& topo, const double* x,
  const std::vector<std::uint8_t>& held, const std::vector<double>& weight, const FairingOptions& opt)
{
  GraphLaplacian U;
  std::vector<double> step = SmoothedCopy(topo, x, LaplacianWeights::Umbrella, opt.OperatorMollification, held,
    weight, opt, U, [] { return static_cast<const Index*>(nullptr); });
  std::vector<double> regular(x, x + 3 * static_cast<std::size_t>(topo.NumberOfVertices()));
  for (std::size_t k = 0; k < step.size(); ++k)
  {
    step[k] -= x[k];
  }
  MoveAlongNormals(topo, regular.data(), step.data(), Keep::Normal, opt.NumberOfThreads);
  return regular;
}

/// Section 3.6, by operator splitting: the tangential part (at the new
/// surface) of an umbrella step, which evens out the sampling.  The umbrella
/// is dimensionless: its step is lambda*dt in units of the mean edge length
/// squared (L_umbrella ~ h^2/4 Laplace, L_K ~ Laplace/2), at most 1 so that
/// it stays a local relaxation.
void RegulariseSampling(const MeshTopology& topo, double* x, const std::vector<std::uint8_t>& fixed,
  const std::vector<double>& weight, const FairingOptions& opt)
{
  const int threads = opt.NumberOfThreads;
  GraphLaplacian U;
  AssembleSurfaceLaplacian(topo, x, LaplacianWeights::Umbrella, U, threads);
  const double h = MeanEdgeLength(topo, x);
  const double relax = std::min(1.0, 2.0 * opt.TimeStep / (h * h));
  const Stage tangential{ U, fixed, weight };
  std::vector<double> v = Velocity(tangential, 1, x, threads);
  for (double& vk : v)
  {
    vk *= relax;
  }
  MoveAlongNormals(topo, x, v.data(), Keep::Tangential, threads);
}

/// The curve-smoothing pass along the detected feature edges (directions
/// `along` from the anisotropic weights).
void SmoothFeatures(const MeshTopology& topo, double* x, const std::vector<Vec3>& along, const VertexRoles& roles,
  const FairingOptions& opt, GraphLaplacian& curveL, FairingReport& report)
{
  const Index n = topo.NumberOfVertices();
  std::vector<std::vector<Index>> chains;
  std::vector<std::uint8_t> onCurve;
  FeatureChains(topo, x, along, chains, onCurve);
  CurveGraph features;
  features.Build(n, {}, chains);
  AssembleCurveLaplacian(features, x, LaplacianWeights::InverseEdgeLength, curveL);
  Stage curve{ curveL, roles.Fixed, roles.Weight };
  for (Index i = 0; i < n; ++i)
  {
    curve.Fixed[i] = roles.Fixed[i] || roles.Boundary[i] || !onCurve[i];
  }
  Integrate(curve, opt, x, report);
}

/// The counts and the warning sentence of a finished run.
void FinishReport(const MeshTopology& topo, const VertexRoles& roles, const FairingOptions& opt,
  std::ostringstream& warn, FairingReport& report)
{
  for (Index i = 0; i < topo.NumberOfVertices(); ++i)
  {
    report.FixedVertices += roles.Fixed[i] && topo.Valence(i) > 0;
  }
  if (report.ExplicitUnstable)
  {
    warn << "Explicit integration with time step " << opt.TimeStep
         << " is above the stability limit (about " << report.StabilityLimit
         << "): the result oscillates; use implicit integration or a smaller step. ";
  }
  if (!report.Converged)
  {
    warn << "The linear solver did not reach the tolerance " << opt.SolverTolerance << " (relative residual "
         << report.LargestResidual << "). ";
  }
  report.Warning = warn.str();
}

FairingReport FairClosedOrFixed(const MeshTopology& topo, double* x, const FairingOptions& opt,
  const FairingConstraints& cons, const ProgressCallback& progress)
{
  FairingReport report;
  const Index n = topo.NumberOfVertices();
  const int threads = opt.NumberOfThreads;
  const VertexRoles roles = ClassifyVertices(topo, x, opt, cons, report);
  const std::vector<std::uint8_t>& fixed = roles.Fixed;
  const std::vector<double>& weight = roles.Weight;
  std::ostringstream warn;
  const InvariantState inv = ChooseInvariant(topo, x, opt, roles, warn, report);

  const std::vector<std::vector<Index>> loops =
    opt.Boundary == FairingBoundary::SmoothCurve ? topo.BoundaryLoops() : std::vector<std::vector<Index>>{};
  CurveGraph boundaryCurves;
  boundaryCurves.Build(n, loops, {});
  GraphLaplacian L, curveL;
  // The solver's renumbering of the surface graph, the same for every step.
  std::vector<Index> order;
  const auto localOrder = [&]() {
    if (order.empty())
    {
      order = LocalityOrder(n, L.Offsets, L.Neighbors);
    }
    return order.data();
  };
  // Rows that do not move in the surface stages.
  std::vector<std::uint8_t> held(n);
  for (Index i = 0; i < n; ++i)
  {
    held[i] = fixed[i] || roles.Boundary[i];
  }
  for (int step = 0; step < opt.NumberOfIterations; ++step)
  {
    std::vector<double> omega = weight;
    std::vector<Vec3> along;
    if (opt.Anisotropic)
    {
      // Curvatures of a pre-mollified copy (section 3.7.1 cites [PR99]): one
      // isotropic implicit curvature-flow step of the same size, so that the
      // weights see the shape rather than the noise.
      const std::vector<double> mollified = opt.Mollification > 0.0
        ? SmoothedCopy(topo, x, LaplacianWeights::Cotangent, opt.TimeStep * opt.Mollification, held, weight, opt, L,
            [&] { return localOrder(); })
        : std::vector<double>(x, x + 3 * static_cast<std::size_t>(n));
      const std::vector<double> a = AnisotropicWeights(topo, mollified.data(), opt,
        opt.SmoothFeatureCurves ? &along : nullptr, report.FeatureVertices);
      for (Index i = 0; i < n; ++i)
      {
        omega[i] *= a[i];
      }
    }
    // Boundary loops first (they do not depend on the interior), then the
    // interior with the new boundary as fixed values (section 3.5.2).
    if (!loops.empty())
    {
      AssembleCurveLaplacian(boundaryCurves, x, WeightsOf(opt.Operator), curveL);
      Stage curve{ curveL, fixed, weight };
      for (Index i = 0; i < n; ++i)
      {
        curve.Fixed[i] = fixed[i] || boundaryCurves.Offsets[i + 1] - boundaryCurves.Offsets[i] < 2;
      }
      Integrate(curve, opt, x, report);
    }
    // The operator's geometry: the current positions (the thesis'
    // linearisation, sections 3.4.3/3.5.3), or a mollified copy.
    std::vector<double> regular;
    if (opt.OperatorMollification > 0.0 && opt.Operator != FairingOperator::Umbrella)
    {
      regular = MollifiedOperatorPoints(topo, x, held, weight, opt);
    }
    AssembleSurfaceLaplacian(topo, regular.empty() ? x : regular.data(), WeightsOf(opt.Operator), L, threads);
    report.DegenerateTriangles = std::max(report.DegenerateTriangles, L.DegenerateTriangles);
    const bool solves = opt.Integration == FairingIntegration::Implicit && opt.Order == 1;
    const Stage surface{ L, held, omega, solves ? localOrder() : nullptr };
    Integrate(surface, opt, x, report);
    if (opt.Operator == FairingOperator::CurvatureFlowAndSampling)
    {
      RegulariseSampling(topo, x, surface.Fixed, weight, opt);
    }
    if (opt.Anisotropic && opt.SmoothFeatureCurves)
    {
      SmoothFeatures(topo, x, along, roles, opt, curveL, report);
    }
    if (inv.Kind != FairingInvariant::None)
    {
      report.FinalInvariant = RestoreInvariant(inv, topo, x, threads);
    }
    if (progress && !progress(static_cast<double>(step + 1) / opt.NumberOfIterations))
    {
      report.Completed = false;
      break;
    }
  }
  FinishReport(topo, roles, opt, warn, report);
  return report;
}

} // namespace

FairingReport FairSurface(const MeshTopology& topo, double* points, const FairingOptions& options,
  const FairingConstraints& cons, const ProgressCallback& progress)
{
  FairingOptions opt = options;
  opt.Order = std::clamp(opt.Order, 1, 2);
  opt.NumberOfIterations = std::max(0, opt.NumberOfIterations);
  opt.TimeStep = std::isfinite(opt.TimeStep) ? std::max(0.0, opt.TimeStep) : 0.0;
  if (opt.Units == LengthUnit::MeanEdgeLength && topo.NumberOfTriangles() > 0)
  {
    const double h = MeanEdgeLength(topo, points);
    if (!(h > 0.0) || !std::isfinite(h))
    {
      FairingReport failed;
      failed.Error = "The mean edge length of the input is " + std::to_string(h) + ": cannot scale the time step.";
      return failed;
    }
    if (opt.Operator != FairingOperator::Umbrella)
    {
      opt.TimeStep *= opt.Order == 2 ? h * h * h * h : h * h; // L: 1/length^2, L^2: 1/length^4
    }
    opt.FeatureThreshold /= h;
    opt.Units = LengthUnit::Physical;
  }
  if (opt.Boundary != FairingBoundary::VirtualVertex || topo.Summary().NumberOfBoundaryLoops == 0)
  {
    return FairClosedOrFixed(topo, points, opt, cons, progress);
  }
  // Section 3.5.2: close each boundary loop with a fan of virtual triangles to
  // a virtual vertex at its barycentre, smooth the closed surface, drop them.
  const Index n = topo.NumberOfVertices();
  const std::vector<std::vector<Index>> loops = topo.BoundaryLoops();
  IndexArray triangles = topo.TriangleList();
  std::vector<double> x(points, points + 3 * static_cast<std::size_t>(n));
  Index next = n;
  for (const auto& loop : loops)
  {
    if (loop.size() < 3)
    {
      continue;
    }
    Vec3 center = Vec3::Zero();
    for (Index v : loop)
    {
      center += Point(points, v);
    }
    center /= static_cast<double>(loop.size());
    x.insert(x.end(), center.data(), center.data() + 3);
    for (std::size_t k = 0; k < loop.size(); ++k)
    {
      // The loop runs with the surface on its left: the virtual triangle
      // uses the boundary edge in the opposite direction.
      triangles.insert(triangles.end(), { loop[(k + 1) % loop.size()], loop[k], next });
    }
    ++next;
  }
  const MeshTopology closed(next, std::move(triangles), opt.NumberOfThreads);
  std::vector<std::uint8_t> fixed;
  std::vector<double> weights;
  FairingConstraints extended;
  if (cons.Fixed)
  {
    fixed.assign(cons.Fixed, cons.Fixed + n);
    fixed.resize(next, 0);
    extended.Fixed = fixed.data();
  }
  if (cons.Weights)
  {
    weights.assign(cons.Weights, cons.Weights + n);
    weights.resize(next, 1.0);
    extended.Weights = weights.data();
  }
  opt.Boundary = FairingBoundary::Fixed; // anything left open (e.g. non-manifold) stays fixed
  FairingReport report = FairClosedOrFixed(closed, x.data(), opt, extended, progress);
  std::copy(x.begin(), x.begin() + 3 * static_cast<std::size_t>(n), points);
  return report;
}

} // namespace beltrami
