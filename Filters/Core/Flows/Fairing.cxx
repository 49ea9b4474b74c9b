#include "Flows/Fairing.h"

#include "Flows/FairingAnisotropy.h"
#include "Flows/FairingInvariants.h"
#include "Flows/FairingStepChoice.h"
#include "Flows/FairingSteps.h"
#include "Mesh/Laplacian.h"
#include "Mesh/MeshMeasures.h"
#include "Mesh/RingGeometry.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <tuple>

namespace beltrami
{

using namespace detail;

namespace
{

/// A distributed run's view of its piece of the surface (FairSurface with a
/// Partition; empty otherwise).
struct DistributedSurface
{
  const Partition* Split = nullptr;
  /// The triangles this process counts in global measures: those whose
  /// corner of lowest global row it owns (each triangle on one process).
  std::unique_ptr<MeshTopology> Counted;
  /// Over all processes: closed, manifold and consistently oriented at every
  /// point (judged by each point's owner, which holds its whole star).
  bool Closed = false;
  /// The mean length of the edges, each counted on one process.
  double MeanEdgeLength = 0.0;

  DistributedSurface(const MeshTopology& topo, const double* x, const Partition* split, int threads)
    : Split(split)
  {
    if (!split)
    {
      return;
    }
    const IndexArray& tri = topo.TriangleList();
    IndexArray counted;
    for (Index t = 0; t < topo.NumberOfTriangles(); ++t)
    {
      const Index* c = tri.data() + 3 * t;
      const Index first = *std::min_element(
        c, c + 3, [&](Index a, Index b) { return split->GlobalRow(a) < split->GlobalRow(b); });
      if (split->IsOwned(first))
      {
        counted.insert(counted.end(), c, c + 3);
      }
    }
    Counted = std::make_unique<MeshTopology>(topo.NumberOfVertices(), std::move(counted), threads);
    double open = 0.0; // open points
    constexpr std::uint8_t openFlags = VertexBoundary | VertexNonManifold | VertexInconsistent | VertexDuplicateFace;
    for (Index i = 0; i < topo.NumberOfVertices(); ++i)
    {
      open += split->IsOwned(i) && (topo.VertexFlags(i) & openFlags);
    }
    Closed = split->Sum(open) == 0.0;
    MeanEdgeLength = beltrami::MeanEdgeLength(topo, x, split);
  }
};

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

/// The one Laplacian assembler; distributed, the ghosts' masses are their
/// owners' (a ghost's own triangles are not all on this process).
void Assemble(const MeshTopology& topo, const double* x, LaplacianWeights kind, GraphLaplacian& lap, int threads,
  const Partition* split)
{
  AssembleSurfaceLaplacian(topo, x, kind, lap, threads);
  if (split)
  {
    split->UpdateGhosts(lap.Mass.data(), 1);
  }
}

/// A copy of x after one implicit order-1 step of `time` with the `kind`
/// Laplacian (assembled into `lap` at x; `order` gives its LocalityOrder or
/// null): the pre-mollified geometries of the anisotropic weights and of
/// OperatorMollification.
template <typename OrderOf>
std::vector<double> SmoothedCopy(const MeshTopology& topo, const double* x, LaplacianWeights kind, double time,
  const std::vector<std::uint8_t>& held, const std::vector<double>& weight, const FairingOptions& opt,
  GraphLaplacian& lap, OrderOf&& order, const Partition* split)
{
  std::vector<double> copy(x, x + 3 * static_cast<std::size_t>(topo.NumberOfVertices()));
  Assemble(topo, copy.data(), kind, lap, opt.NumberOfThreads, split);
  FairingOptions so = opt;
  so.Integration = FairingIntegration::Implicit;
  so.Order = 1;
  so.TimeStep = time;
  FairingReport ignored;
  ImplicitStep(Stage{ lap, held, weight, order(), nullptr, split }, so, copy.data(), ignored);
  return copy;
}


/// Reads the axis and plane constraints (a non-zero finite direction; the
/// axis first) of the vertices that are not fixed.  Without any (and not
/// distributed, where every process exchanges them), no arrays.
Motions ReadMotions(const FairingConstraints& cons, const std::vector<std::uint8_t>& fixed, bool distributed)
{
  const Index n = static_cast<Index>(fixed.size());
  Motions m;
  if (!cons.AxisDirections && !cons.PlaneNormals && !distributed)
  {
    return m;
  }
  m.Kind.assign(n, Motions::Free);
  m.Direction.assign(n, Vec3::Zero());
  for (Index i = 0; i < n && (cons.AxisDirections || cons.PlaneNormals); ++i)
  {
    for (const auto& [array, kind] : { std::pair{ cons.AxisDirections, Motions::OnAxis },
           std::pair{ cons.PlaneNormals, Motions::OnPlane } })
    {
      const Vec3 d = array ? Point(array, i) : Vec3::Zero();
      if (!fixed[i] && m.Kind[i] == Motions::Free && d.allFinite() && d.norm() > 0.0)
      {
        m.Kind[i] = kind;
        m.Direction[i] = d.normalized();
        m.Any = true;
      }
    }
  }
  return m;
}

VertexRoles ClassifyVertices(const MeshTopology& topo, const double* x, const FairingOptions& opt,
  const FairingConstraints& cons, const Partition* split, FairingReport& report)
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
    report.UnusableVertices += unusable && !(flags & VertexIsolated) && (!split || split->IsOwned(i));
    r.Fixed[i] = user || unusable || (r.Boundary[i] && opt.Boundary == FairingBoundary::Fixed);
  }
  if (split)
  {
    // A ghost's star is not all here: it takes its owner's roles.
    split->UpdateGhosts(r.Fixed);
    split->UpdateGhosts(r.Boundary);
    split->UpdateGhosts(r.Weight);
  }
  r.Moves = ReadMotions(cons, r.Fixed, split != nullptr);
  if (split)
  {
    split->UpdateGhosts(r.Moves.Kind);
    static_assert(sizeof(Vec3) == 3 * sizeof(double), "Vec3: 3 packed doubles");
    split->UpdateGhosts(reinterpret_cast<double*>(r.Moves.Direction.data()), 3);
    r.Moves.Any = split->Max(r.Moves.Any ? 1.0 : 0.0) > 0.0;
    r.HardConstraints = split->Max(r.HardConstraints ? 1.0 : 0.0) > 0.0;
  }
  r.HardConstraints = r.HardConstraints || r.Moves.Any;
  return r;
}

/// A closed surface whose signed volume is at most this times its area to
/// the power 1.5 encloses next to nothing (a sphere: 0.094; a plate a
/// thousandth of its width thick: 5e-4).
constexpr double NoVolume = 1e-6;

/// Section 3.3.1: the invariant restored after every step (Automatic: the
/// volume of closed oriented surfaces without hard constraints), with its
/// initial value; remarks for the user go to `warn`.
InvariantState ChooseInvariant(const MeshTopology& topo, const double* x, const FairingOptions& opt,
  const VertexRoles& roles, const DistributedSurface& pieces, std::ostringstream& warn, FairingReport& report)
{
  const TopologySummary& info = topo.Summary();
  InvariantState inv;
  inv.Kind = opt.Invariant;
  inv.Split = pieces.Split;
  inv.Counted = pieces.Counted.get();
  const bool closed = pieces.Split ? pieces.Closed : info.IsClosed() && info.IsManifold() && info.IsOriented();
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
    const auto [onBoundary, count] = MeanPoint(topo, x, pieces.Split, [&](Index i) { return roles.Boundary[i] != 0; });
    inv.PlaneOrigin = count > 0.0
      ? onBoundary
      : MeanPoint(topo, x, pieces.Split, [&](Index i) { return topo.Valence(i) > 0; }).first;
  }
  if (inv.Kind == FairingInvariant::RevolutionVolume)
  {
    // The axis passes through the area centroid (on the axis of a surface of revolution).
    InvariantState area = inv;
    area.Kind = FairingInvariant::Area;
    MeasureInvariant(area, topo, x, opt.NumberOfThreads, &inv.PlaneOrigin);
  }
  if (roles.HardConstraints && inv.Kind != FairingInvariant::None)
  {
    warn << "The invariant is restored by scaling, which also moves the fixed and the axis- or plane-constrained "
            "points (section 3.3.1). ";
  }
  inv.Initial = MeasureInvariant(inv, topo, x, opt.NumberOfThreads, nullptr);
  if (inv.Kind == FairingInvariant::Volume)
  {
    // A closed surface that passes through itself can enclose next to no
    // signed volume (a Bohemian dome: 4e-10 of an area of 20): its volume
    // restored by scaling shrank it 8-30 times.
    InvariantState area = inv;
    area.Kind = FairingInvariant::Area;
    const double a = MeasureInvariant(area, topo, x, opt.NumberOfThreads, nullptr);
    if (std::isfinite(inv.Initial) && std::abs(inv.Initial) <= NoVolume * std::pow(a, 1.5))
    {
      warn << "The surface encloses next to no volume (" << inv.Initial << ", its area " << a
           << ": it passes through itself): no invariant is preserved. ";
      inv.Kind = FairingInvariant::None;
      inv.Initial = MeasureInvariant(inv, topo, x, opt.NumberOfThreads, nullptr);
    }
  }
  report.InvariantUsed = inv.Kind;
  report.InitialInvariant = report.FinalInvariant = inv.Initial;
  return inv;
}

/// The operator's geometry (OperatorMollification): x moved by the normal
/// part of one implicit umbrella step.  On a noisy scan the cotangents of the
/// noisy triangles are noise too; the copy damps the noise across the
/// surface and keeps the sampling, so a flat region's copy is the region
/// itself and flat regions still never move.
std::vector<double> MollifiedOperatorPoints(const MeshTopology& topo, const double* x,
  const std::vector<std::uint8_t>& held, const std::vector<double>& weight, const FairingOptions& opt,
  const Partition* split)
{
  GraphLaplacian U;
  std::vector<double> step = SmoothedCopy(topo, x, LaplacianWeights::Umbrella, opt.OperatorMollification, held,
    weight, opt, U, [] { return static_cast<const Index*>(nullptr); }, split);
  std::vector<double> regular(x, x + 3 * static_cast<std::size_t>(topo.NumberOfVertices()));
  for (std::size_t k = 0; k < step.size(); ++k)
  {
    step[k] -= x[k];
  }
  MoveAlongNormals(UnitNormals(topo, x, opt.NumberOfThreads), regular.data(), step.data(), Keep::Normal);
  if (split)
  {
    split->UpdateGhosts(regular.data(), 3); // the ghosts' normals are not all here
  }
  return regular;
}

/// The operator of a step at x: its Laplacian assembled at x, or at the
/// mollified copy of x (OperatorMollification).
void AssembleOperator(const MeshTopology& topo, const double* x, const std::vector<std::uint8_t>& held,
  const std::vector<double>& weight, const FairingOptions& opt, GraphLaplacian& L, const Partition* split)
{
  std::vector<double> regular;
  if (opt.OperatorMollification > 0.0 && opt.Operator != FairingOperator::Umbrella)
  {
    regular = MollifiedOperatorPoints(topo, x, held, weight, opt, split);
  }
  Assemble(topo, regular.empty() ? x : regular.data(), WeightsOf(opt.Operator), L, opt.NumberOfThreads, split);
}

/// Section 3.6, by operator splitting: the tangential part (at the new
/// surface) of an umbrella step, which evens out the sampling.  The umbrella
/// is dimensionless: its step is lambda*dt in units of the mean edge length
/// squared (L_umbrella ~ h^2/4 Laplace, L_K ~ Laplace/2), at most 1 so that
/// it stays a local relaxation.
void RegulariseSampling(const MeshTopology& topo, double* x, const std::vector<std::uint8_t>& fixed,
  const std::vector<double>& weight, const Motions& moves, const FairingOptions& opt, const Partition* split)
{
  const std::vector<double> before(x, x + 3 * static_cast<std::size_t>(topo.NumberOfVertices()));
  const int threads = opt.NumberOfThreads;
  GraphLaplacian U;
  Assemble(topo, x, LaplacianWeights::Umbrella, U, threads, split);
  const double h = MeanEdgeLength(topo, x, split);
  const double relax = std::min(1.0, 2.0 * opt.TimeStep / (h * h));
  const Stage tangential{ U, fixed, weight, nullptr, nullptr, split };
  std::vector<double> v = Velocity(tangential, Powers::Single(1), x, threads);
  for (double& vk : v)
  {
    vk *= relax;
  }
  MoveAlongNormals(UnitNormals(topo, x, threads), x, v.data(), Keep::Tangential);
  moves.KeepAllowed(before, x);
  if (split)
  {
    split->UpdateGhosts(x, 3); // the ghosts' normals are not all here
  }
}

/// Distributed, a curve stage's ghost rows take their owners' masses and
/// roles (their curve neighbours are not all here).
void ShareCurveRows(const Partition* split, GraphLaplacian& curveL, std::vector<std::uint8_t>& fixed)
{
  if (split)
  {
    split->UpdateGhosts(curveL.Mass.data(), 1);
    split->UpdateGhosts(fixed);
  }
}

/// The curve-smoothing pass along the detected feature edges (directions
/// `along` from the anisotropic weights).
bool SmoothFeatures(const MeshTopology& topo, double* x, const std::vector<Vec3>& along, const VertexRoles& roles,
  const FairingOptions& opt, GraphLaplacian& curveL, FairingReport& report, const Partition* split)
{
  const Index n = topo.NumberOfVertices();
  std::vector<std::vector<Index>> chains;
  std::vector<std::uint8_t> onCurve;
  FeatureChains(topo, x, along, chains, onCurve);
  CurveGraph features;
  features.Build(n, {}, chains);
  AssembleCurveLaplacian(features, x, LaplacianWeights::InverseEdgeLength, curveL);
  Stage curve{ curveL, roles.Fixed, roles.Weight, nullptr, &roles.Moves, split };
  for (Index i = 0; i < n; ++i)
  {
    curve.Fixed[i] = roles.Fixed[i] || roles.Boundary[i] || !onCurve[i];
  }
  ShareCurveRows(split, curveL, curve.Fixed);
  return Integrate(curve, opt, x, report);
}

/// A combination's step that is not positive definite ends the run at the
/// last defined step, with an error at the first step (nothing was done).
void UndefinedStep(int step, int steps, std::ostringstream& warn, FairingReport& report)
{
  std::ostringstream why;
  why << "The combination of orders would amplify some frequencies of this mesh more than " << MaximumGain
      << "-fold or without bound in one step (1 + dt p(w) < " << 1.0 / MaximumGain
      << ": the implicit step is not defined or nearly singular); use a smaller time step or a smaller negative "
         "weight";
  if (step == 0)
  {
    report.Error = why.str() + ". The points are unchanged.";
  }
  else
  {
    warn << why.str() << ": stopped after " << step << " of " << steps << " steps. ";
  }
  report.Completed = false;
}

/// A chosen step's run whose moves are coherent (MoveCoherence above
/// MostCoherentMove in space or MostCoherentNormalMove along the normals)
/// changed the shape rather than removing noise: the points go back to
/// `input`, as where the step's choice leaves them.
void LeaveCoherentMoves(const MeshTopology& topo, const std::vector<double>& input,
  const std::vector<std::uint8_t>& held, const Partition* split, double* x, std::ostringstream& warn,
  FairingReport& report)
{
  const MoveCorrelations coherence = MoveCoherence(topo, input.data(), x, held, split);
  const bool inSpace = coherence.InSpace > MostCoherentMove;
  if (!inSpace && !(coherence.AlongNormals > MostCoherentNormalMove))
  {
    return;
  }
  std::copy(input.begin(), input.end(), x);
  report.ChosenTimeStep = 0.0;
  report.EstimatedError = report.InputError;
  report.Iterations.clear();
  report.FinalInvariant = report.InitialInvariant;
  std::ostringstream said;
  said << "The step chosen moved neighbouring points together (the correlation of their moves"
       << (inSpace ? "" : " along the normals") << " over the edges "
       << (inSpace ? coherence.InSpace : coherence.AlongNormals)
       << ", where removing noise moves them independently): it changed the shape, whose detail "
          "smoothing cannot tell from noise here, so the surface was left as it is. Set TimeStep to smooth it. ";
  warn << said.str();
  report.StepWarning += said.str();
}

/// The counts and the warning sentence of a finished run.
void FinishReport(const MeshTopology& topo, const VertexRoles& roles, const FairingOptions& opt,
  const Partition* split, std::ostringstream& warn, FairingReport& report)
{
  for (Index i = 0; i < topo.NumberOfVertices(); ++i)
  {
    report.FixedVertices += roles.Fixed[i] && topo.Valence(i) > 0 && (!split || split->IsOwned(i));
  }
  if (split)
  {
    double counts[2] = { static_cast<double>(report.FixedVertices), static_cast<double>(report.UnusableVertices) };
    split->Sum(counts, 2);
    report.FixedVertices = static_cast<Index>(counts[0]);
    report.UnusableVertices = static_cast<Index>(counts[1]);
    report.DegenerateTriangles = static_cast<Index>(split->Max(report.DegenerateTriangles));
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

/// Section 3.5.2's boundary curves: the graph of the boundary edges (one
/// face; distributed, those at an owned point, whose star is all here, so
/// that a cut through the ring is no boundary).  Whether any process has
/// one (distributed: every process then takes part in the curve steps).
bool BoundaryCurves(const MeshTopology& topo, const Partition* split, CurveGraph& curves)
{
  const MeshTopology::EdgeTable& edges = topo.Edges();
  std::vector<std::vector<Index>> chains;
  for (std::int64_t e = 0; e < edges.NumberOfEdges(); ++e)
  {
    const Index a = edges.Vertices[2 * e], b = edges.Vertices[2 * e + 1];
    if (edges.FaceCount[e] == 1 && (!split || split->IsOwned(a) || split->IsOwned(b)))
    {
      chains.push_back({ a, b });
    }
  }
  curves.Build(topo.NumberOfVertices(), {}, chains);
  const double any = chains.empty() ? 0.0 : 1.0;
  return (split ? split->Max(any) : any) > 0.0;
}

/// `stepUnit`: the unit of the steps a chosen time step (TimeStep 0) is
/// searched in (h^(2k) for order k, 1 for the umbrella).
FairingReport FairClosedOrFixed(const MeshTopology& topo, double* x, const FairingOptions& given,
  const FairingConstraints& cons, const ProgressCallback& progress, const DistributedSurface& pieces,
  double stepUnit)
{
  FairingReport report;
  report.OperatorUsed = given.Operator;
  FairingOptions opt = given;
  const Index n = topo.NumberOfVertices();
  const int threads = opt.NumberOfThreads;
  const Partition* split = pieces.Split;
  opt.KeptHierarchy = std::make_shared<std::shared_ptr<const SurfaceHierarchy>>(); // this run's
  if (opt.Preconditioner == Preconditioning::GeometricMultigrid && !split && !opt.Hierarchy && n > 0)
  {
    const MeshTopology::VertexGraph& graph = topo.Graph();
    opt.Hierarchy = std::make_shared<const SurfaceHierarchy>(
      n, graph.NeighborOffsets.data(), graph.Neighbors.data(), x, threads);
  }
  const VertexRoles roles = ClassifyVertices(topo, x, opt, cons, split, report);
  const std::vector<std::uint8_t>& fixed = roles.Fixed;
  const std::vector<double>& weight = roles.Weight;
  std::ostringstream warn;
  const InvariantState inv = ChooseInvariant(topo, x, opt, roles, pieces, warn, report);

  CurveGraph boundaryCurves;
  const bool smoothsBoundary = opt.Boundary == FairingBoundary::SmoothCurve &&
    BoundaryCurves(topo, split, boundaryCurves);
  GraphLaplacian L, curveL, first;
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
  // Where the first step's solve starts: at x, or at the chosen step's own
  // run from x in the search (its result, met at once; ChooseStep).
  RunStart guess;
  std::vector<double> input; // the points before a chosen step's run (MostCoherentMove)
  if (opt.TimeStep == 0.0 && opt.Integration != FairingIntegration::TaubinLambdaMu && opt.NumberOfIterations > 0)
  {
    const OperatorAssembly assemble = [&](const double* p, const FairingOptions& o, GraphLaplacian& lap) {
      AssembleOperator(topo, p, held, weight, o, lap, split);
    };
    StepChoice choice = ChooseStep(topo, x, opt, roles, held, inv, assemble, stepUnit, order, split, warn, report);
    opt.TimeStep = choice.TimeStep;
    opt.NumberOfIterations = opt.TimeStep > 0.0 ? opt.NumberOfIterations : 0; // a clean mesh stays as it is
    guess = std::move(choice.Start);
    if (opt.TimeStep > 0.0)
    {
      input.assign(x, x + 3 * static_cast<std::size_t>(n));
    }
  }
  std::vector<double> start;
  // A combination with a negative weight: each step's start, kept in case
  // the step is not defined there (section 3.2.6's amplification).
  const bool amplifies = !Powers::Of(opt).NonNegative();
  for (int step = 0; step < opt.NumberOfIterations; ++step)
  {
    if (amplifies)
    {
      start.assign(x, x + 3 * static_cast<std::size_t>(n));
    }
    bool defined = true;
    std::vector<double> omega = weight;
    std::vector<Vec3> along;
    if (opt.Anisotropic)
    {
      // Curvatures of a pre-mollified copy (section 3.7.1 cites [PR99]): one
      // isotropic implicit curvature-flow step of the same size, so that the
      // weights see the shape rather than the noise.
      const std::vector<double> mollified = opt.Mollification > 0.0
        ? SmoothedCopy(topo, x, LaplacianWeights::Cotangent, opt.TimeStep * opt.Mollification, held, weight, opt, L,
            [&] { return localOrder(); }, split)
        : std::vector<double>(x, x + 3 * static_cast<std::size_t>(n));
      const std::vector<double> a = AnisotropicWeights(topo, mollified.data(), opt,
        opt.SmoothFeatureCurves ? &along : nullptr, report.FeatureVertices, split);
      for (Index i = 0; i < n; ++i)
      {
        omega[i] *= a[i];
      }
      if (split)
      {
        split->UpdateGhosts(omega); // the ghosts' curvatures are not all here
        if (opt.SmoothFeatureCurves) // (every process, an empty piece's too)
        {
          split->UpdateGhosts(reinterpret_cast<double*>(along.data()), 3);
        }
      }
    }
    // Boundary loops first (they do not depend on the interior), then the
    // interior with the new boundary as fixed values (section 3.5.2).
    if (smoothsBoundary)
    {
      AssembleCurveLaplacian(boundaryCurves, x, WeightsOf(opt.Operator), curveL);
      Stage curve{ curveL, fixed, weight, nullptr, &roles.Moves, split };
      for (Index i = 0; i < n; ++i)
      {
        curve.Fixed[i] = fixed[i] || boundaryCurves.Offsets[i + 1] - boundaryCurves.Offsets[i] < 2;
      }
      ShareCurveRows(split, curveL, curve.Fixed);
      defined = Integrate(curve, opt, x, report);
    }
    // The operator's geometry: the current positions (the thesis'
    // linearisation, sections 3.4.3/3.5.3), or a mollified copy (freed
    // before the solve).
    if (step > 0 && opt.KeepFirstOperator)
    {
      L = first; // section 3.4.3: relative to the input mesh
    }
    else
    {
      AssembleOperator(topo, x, held, weight, opt, L, split);
      if (opt.KeepFirstOperator && opt.NumberOfIterations > 1)
      {
        first = L;
      }
    }
    report.DegenerateTriangles = std::max(report.DegenerateTriangles, L.DegenerateTriangles);
    const Powers powers = Powers::Of(opt);
    const bool solves = opt.Integration == FairingIntegration::Implicit && (powers.Pure(1) || powers.Pure(2));
    const double* from = step == 0 && !guess.Points.empty() && !opt.Anisotropic ? guess.Points.data() : nullptr;
    const Stage surface{ L, held, std::move(omega), solves && !split ? localOrder() : nullptr, &roles.Moves, split,
      from };
    defined = defined && Integrate(surface, opt, x, report);
    if (from && !report.Iterations.empty())
    {
      report.Iterations.back() += guess.Iterations; // (the result's iterations: the search's run and these)
    }
    if (opt.Operator == FairingOperator::CurvatureFlowAndSampling)
    {
      RegulariseSampling(topo, x, surface.Fixed, weight, roles.Moves, opt, split);
    }
    if (opt.Anisotropic && opt.SmoothFeatureCurves)
    {
      defined = defined && SmoothFeatures(topo, x, along, roles, opt, curveL, report, split);
    }
    if (!defined)
    {
      std::copy(start.begin(), start.end(), x);
      UndefinedStep(step, opt.NumberOfIterations, warn, report);
      break;
    }
    if (inv.Kind != FairingInvariant::None)
    {
      report.FinalInvariant = RestoreInvariant(inv, topo, x, threads);
    }
    const bool stop = progress && !progress(static_cast<double>(step + 1) / opt.NumberOfIterations);
    if (split ? split->Max(stop ? 1.0 : 0.0) > 0.0 : stop) // (distributed: all stop together)
    {
      report.Completed = false;
      break;
    }
  }
  if (!input.empty() && report.Completed)
  {
    LeaveCoherentMoves(topo, input, held, split, x, warn, report);
  }
  FinishReport(topo, roles, opt, split, warn, report);
  return report;
}

/// A report whose chosen time step is in units of `unit` (the options' Units).
FairingReport InGivenUnits(FairingReport report, double unit)
{
  report.ChosenTimeStep /= unit;
  return report;
}

/// Order 0: finite weights, the highest non-zero one positive.
bool CheckOrderWeights(const FairingOptions& opt)
{
  const Powers p = Powers::Of(opt);
  bool finite = true;
  for (double c : p.C)
  {
    finite = finite && std::isfinite(c);
  }
  return finite && p.Degree > 0 && p.C[p.Degree - 1] > 0.0;
}

} // namespace

std::string DistributedFairingLimitation(const FairingOptions& opt)
{
  if (opt.Boundary == FairingBoundary::VirtualVertex)
  {
    return "boundaries closed by a virtual vertex";
  }
  return "";
}

FairingReport FairSurface(const MeshTopology& topo, double* points, const FairingOptions& options,
  const FairingConstraints& cons, const ProgressCallback& progress, const Partition* split)
{
  if (std::optional<FairingReport> sampled = FairWithSampledSearch(topo, points, options, cons, progress, split))
  {
    return std::move(*sampled);
  }
  if (options.Operator == FairingOperator::LeastEstimatedError)
  {
    return FairWithEitherOperator(topo, points, options, cons, progress, split);
  }
  if (split)
  {
    const std::string limit = DistributedFairingLimitation(options);
    if (!limit.empty())
    {
      FairingReport failed;
      failed.Error = "Distributed fairing does not support " + limit + ".";
      return failed;
    }
  }
  FairingOptions opt = options;
  opt.Order = std::clamp(opt.Order, 0, 4);
  opt.NumberOfIterations = std::max(0, opt.NumberOfIterations);
  opt.TimeStep = std::isfinite(opt.TimeStep) ? std::max(0.0, opt.TimeStep) : 0.0;
  const int degree = Powers::Of(opt).Degree;
  if (opt.Order == 0 && !CheckOrderWeights(opt))
  {
    FairingReport failed;
    failed.Error = "OrderWeights must be finite, with a positive weight on the highest order used.";
    return failed;
  }
  const DistributedSurface pieces(topo, points, split, opt.NumberOfThreads);
  // The unit of the time step in the mean edge length h (StepUnitOf), also
  // the scale a chosen step is searched at.
  double h = 0.0, unit = 1.0;
  const bool scaled = opt.Units == LengthUnit::MeanEdgeLength;
  if ((scaled || opt.TimeStep == 0.0) && (split || topo.NumberOfTriangles() > 0))
  {
    h = split ? pieces.MeanEdgeLength : MeanEdgeLength(topo, points);
    if (!(h > 0.0) || !std::isfinite(h))
    {
      FairingReport failed;
      failed.Error = "The mean edge length of the input is " + std::to_string(h) + ": cannot scale the time step.";
      return failed;
    }
    unit = StepUnitOf(h, degree, opt.Operator);
  }
  if (scaled && h > 0.0)
  {
    if (opt.Operator != FairingOperator::Umbrella)
    {
      opt.TimeStep *= unit;
      for (int k = 1; k <= 4; ++k)
      {
        opt.OrderWeights[k - 1] *= std::pow(h * h, k - degree);
      }
    }
    opt.FeatureThreshold /= h;
    opt.Units = LengthUnit::Physical;
  }
  if (opt.Boundary != FairingBoundary::VirtualVertex || topo.Summary().NumberOfBoundaryLoops == 0)
  {
    return InGivenUnits(FairClosedOrFixed(topo, points, opt, cons, progress, pieces, unit), scaled ? unit : 1.0);
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
  std::vector<double> axes, normals;
  for (auto [given, copy, to] : { std::tuple{ cons.AxisDirections, &axes, &extended.AxisDirections },
         std::tuple{ cons.PlaneNormals, &normals, &extended.PlaneNormals } })
  {
    if (given)
    {
      copy->assign(given, given + 3 * static_cast<std::size_t>(n));
      copy->resize(3 * static_cast<std::size_t>(next), 0.0);
      *to = copy->data();
    }
  }
  opt.Boundary = FairingBoundary::Fixed; // anything left open (e.g. non-manifold) stays fixed
  FairingReport report = InGivenUnits(FairClosedOrFixed(closed, x.data(), opt, extended, progress,
    DistributedSurface(closed, x.data(), nullptr, 0), unit), scaled ? unit : 1.0);
  std::copy(x.begin(), x.begin() + 3 * static_cast<std::size_t>(n), points);
  return report;
}

} // namespace beltrami
