#include "Maps/Parameterization.h"

#include "Maps/MapOptimization.h"
#include "Maps/ParameterizationSystem.h"
#include "Mesh/EdgePaths.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <new>
#include <sstream>

namespace beltrami
{

using namespace detail;

BoundaryBasis::BoundaryBasis(Index numberOfVertices, std::vector<Index> boundary,
  std::vector<Index> free, std::vector<double> basis, std::vector<double> offset)
  : Vertices(numberOfVertices)
  , Boundary(std::move(boundary))
  , Free(std::move(free))
  , Basis(std::move(basis))
  , Offset(std::move(offset))
{
}

BoundaryBasis::BoundaryBasis(Index numberOfVertices, std::vector<Index> boundary, std::vector<Index> free,
  Map map, Map pullBack)
  : Vertices(numberOfVertices)
  , Boundary(std::move(boundary))
  , Free(std::move(free))
  , Implicit(std::move(map))
  , ImplicitPullBack(std::move(pullBack))
{
}

void BoundaryBasis::Apply(const double* boundaryUV, double* uv) const
{
  std::fill(uv, uv + 2 * static_cast<std::size_t>(Vertices), 0.0); // points in no triangle
  const Eigen::Index nb = static_cast<Eigen::Index>(Boundary.size());
  const Eigen::Index nf = static_cast<Eigen::Index>(Free.size());
  Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor>> p(boundaryUV, nb, 2);
  Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor> u(nf, 2);
  if (Implicit)
  {
    Implicit(boundaryUV, u.data());
  }
  else
  {
    u = Eigen::Map<const Eigen::MatrixXd>(Basis.data(), nf, nb) * p;
  }
  for (Eigen::Index k = 0; k < nf; ++k)
  {
    uv[2 * Free[k]] = u(k, 0) + (Offset.empty() ? 0.0 : Offset[2 * k]);
    uv[2 * Free[k] + 1] = u(k, 1) + (Offset.empty() ? 0.0 : Offset[2 * k + 1]);
  }
  for (Eigen::Index k = 0; k < nb; ++k)
  {
    uv[2 * Boundary[k]] = p(k, 0);
    uv[2 * Boundary[k] + 1] = p(k, 1);
  }
}

void BoundaryBasis::PullBack(const double* gradient, double* boundaryGradient) const
{
  const Eigen::Index nb = static_cast<Eigen::Index>(Boundary.size());
  const Eigen::Index nf = static_cast<Eigen::Index>(Free.size());
  Eigen::Matrix<double, Eigen::Dynamic, 2> gf(nf, 2);
  for (Eigen::Index k = 0; k < nf; ++k)
  {
    gf(k, 0) = gradient[2 * Free[k]];
    gf(k, 1) = gradient[2 * Free[k] + 1];
  }
  Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor> gb(nb, 2);
  if (ImplicitPullBack)
  {
    const Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor> in = gf;
    ImplicitPullBack(in.data(), gb.data());
  }
  else
  {
    gb = Eigen::Map<const Eigen::MatrixXd>(Basis.data(), nf, nb).transpose() * gf;
  }
  for (Eigen::Index k = 0; k < nb; ++k)
  {
    boundaryGradient[2 * k] = gb(k, 0) + gradient[2 * Boundary[k]];
    boundaryGradient[2 * k + 1] = gb(k, 1) + gradient[2 * Boundary[k] + 1];
  }
}

namespace
{
/// The waypoints joined by the shortest edge paths between consecutive ones.
std::vector<Index> JoinWaypoints(
  const MeshTopology& topo, const double* points, const std::vector<Index>& waypoints, std::string& error)
{
  std::vector<Index> path{ waypoints.front() };
  for (std::size_t k = 1; k < waypoints.size(); ++k)
  {
    const std::vector<Index> leg = ShortestEdgePath(topo, points, waypoints[k - 1], waypoints[k]);
    if (leg.empty())
    {
      error = "no path along mesh edges joins points " + std::to_string(waypoints[k - 1]) + " and " +
        std::to_string(waypoints[k]);
      return {};
    }
    path.insert(path.end(), leg.begin() + 1, leg.end());
  }
  return path;
}
} // namespace

std::string AppendLineConstraint(const MeshTopology& topo, const double* points, const LineConstraint& line,
  std::vector<PointConstraint>& constraints)
{
  if (line.Path.size() < 2)
  {
    return "a line needs at least two points";
  }
  std::string error;
  const std::vector<Index> path = line.ShortestPaths ? JoinWaypoints(topo, points, line.Path, error) : line.Path;
  if (!error.empty())
  {
    return error;
  }
  if (!std::isfinite(line.From[0]) || !std::isfinite(line.From[1]) || !std::isfinite(line.To[0]) ||
    !std::isfinite(line.To[1]) || (line.From[0] == line.To[0] && line.From[1] == line.To[1]))
  {
    return "the target segment needs two distinct, finite end points";
  }
  const Index n = topo.NumberOfVertices();
  const auto& edges = topo.Graph();
  const auto joined = [&](Index a, Index b) {
    return std::binary_search(edges.Neighbors.data() + edges.NeighborOffsets[a],
      edges.Neighbors.data() + edges.NeighborOffsets[a + 1], b);
  };
  std::vector<double> length(path.size(), 0.0);
  std::vector<Index> sorted(path.begin(), path.end());
  std::sort(sorted.begin(), sorted.end());
  if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end())
  {
    return "a point appears twice on the line";
  }
  for (std::size_t i = 0; i < path.size(); ++i)
  {
    if (path[i] < 0 || path[i] >= n || topo.Valence(path[i]) == 0)
    {
      return "point " + std::to_string(path[i]) + " is not on the surface";
    }
    if (i == 0)
    {
      continue;
    }
    const Index a = path[i - 1], b = path[i];
    if (!joined(a, b))
    {
      return "points " + std::to_string(a) + " and " + std::to_string(b) +
        " are not joined by a mesh edge (give the line as a path along edges, e.g. a geodesic path)";
    }
    length[i] = length[i - 1] + (Point(points, b) - Point(points, a)).norm();
  }
  const double total = length.back();
  if (!(total > 0.0) || !std::isfinite(total))
  {
    return "the line has no length";
  }
  // A point whose neighbours on the path share an edge is a detour of a
  // path along edges: the three are a triangle, which a straight line
  // through all three would collapse (or flip).  It is left free, the line
  // passing along the edge between its neighbours.
  std::vector<std::size_t> kept{ 0 };
  for (std::size_t i = 1; i + 1 < path.size(); ++i)
  {
    if (!joined(path[kept.back()], path[i + 1]))
    {
      kept.push_back(i);
    }
  }
  kept.push_back(path.size() - 1);
  for (const std::size_t i : kept)
  {
    const double t = length[i] / total;
    PointConstraint c;
    c.Vertices = { { path[i], -1, -1 } };
    c.Target[0] = line.From[0] + t * (line.To[0] - line.From[0]);
    c.Target[1] = line.From[1] + t * (line.To[1] - line.From[1]);
    constraints.push_back(c);
  }
  return {};
}

bool CheckDiskTopology(const MeshTopology& topo, std::string& error)
{
  const TopologySummary& s = topo.Summary();
  std::ostringstream os;
  if (topo.NumberOfTriangles() == 0)
  {
    error = "the input has no triangles";
    return false;
  }
  const Index components = topo.CountComponents();
  const std::int64_t twiceGenus = 2 - s.EulerCharacteristic - s.NumberOfBoundaryLoops;
  if (!s.IsManifold() || !s.IsOriented() || components != 1 || s.IsClosed() ||
    twiceGenus != 0)
  {
    os << "a parameterization needs one connected, manifold, consistently oriented surface of genus 0 "
          "with at least one boundary loop (a disk, possibly with holes); the input is: "
       << topo.Describe();
    if (s.IsClosed() && s.IsManifold())
    {
      os << ". Cut the closed surface open first (e.g. Clip, or remove a triangle)";
    }
    error = os.str();
    return false;
  }
  return true;
}

namespace
{

ParameterizationResult Fail(std::string error)
{
  ParameterizationResult r;
  r.Error = std::move(error);
  return r;
}

void AppendWarning(std::string& warning, const std::string& text)
{
  warning += (warning.empty() ? "" : "; ") + text;
}

ParameterizationResult ParameterizeUnguarded(
  const MeshTopology& topo, const double* points, const ParameterizationOptions& options);

} // namespace

ParameterizationResult Parameterize(
  const MeshTopology& topo, const double* points, const ParameterizationOptions& options)
{
  try
  {
    return ParameterizeUnguarded(topo, points, options);
  }
  catch (const std::bad_alloc&)
  {
    return Fail("Cannot parameterize: out of memory (the sparse factorization of a mesh of n vertices "
                "needs about 2-3 kB per vertex).");
  }
}

namespace
{

/// Point constraints on used vertices, with weights that sum to 1 and finite targets.
std::string CheckConstraints(const std::vector<PointConstraint>& constraints, const std::vector<std::uint8_t>& used)
{
  const Index n = static_cast<Index>(used.size());
  for (std::size_t k = 0; k < constraints.size(); ++k)
  {
    const PointConstraint& c = constraints[k];
    double sum = 0.0;
    bool any = false;
    for (int j = 0; j < 3; ++j)
    {
      if (c.Vertices[j] < 0)
      {
        continue;
      }
      if (c.Vertices[j] >= n || !used[c.Vertices[j]] || !std::isfinite(c.Weights[j]))
      {
        return "Point constraint " + std::to_string(k) + " refers to a point that is not on the surface.";
      }
      sum += c.Weights[j];
      any = true;
    }
    if (!any || std::abs(sum - 1.0) > 1e-6 || !std::isfinite(c.Target[0]) || !std::isfinite(c.Target[1]))
    {
      return "Point constraint " + std::to_string(k) + " needs barycentric weights that sum to 1 and a finite target.";
    }
  }
  return {};
}

/// The checks of the input and the options: the message of the first
/// problem, empty if there is none; `used` marks the vertices in a triangle.
std::string CheckInput(const MeshTopology& topo, const double* points, const ParameterizationOptions& options,
  std::vector<std::uint8_t>& used)
{
  std::string error;
  if (!CheckDiskTopology(topo, error))
  {
    return "Cannot parameterize: " + error + ".";
  }
  const Index n = topo.NumberOfVertices();
  used.assign(n, 0);
  for (Index v = 0; v < n; ++v)
  {
    used[v] = topo.Valence(v) > 0;
    if (used[v] && !Point(points, v).allFinite())
    {
      return "Cannot parameterize: point " + std::to_string(v) + " has non-finite coordinates.";
    }
  }
  const bool natural = options.Boundary == ParameterizationBoundary::Natural;
  const bool mixSearch = options.OptimizeMix;
  if (!std::isfinite(options.ConformalWeight) || !std::isfinite(options.AuthalicWeight) ||
    (!mixSearch && options.ConformalWeight == 0.0 && options.AuthalicWeight == 0.0))
  {
    return "The conformal and authalic weights must be finite and not both 0.";
  }
  if (natural && (options.AuthalicWeight != 0.0 || mixSearch))
  {
    return "Natural boundaries are defined for the conformal energy only (thesis section 5.4.2): "
           "set the authalic weight to 0 and do not optimise the mix, or fix the boundary.";
  }
  if (natural && options.BoundaryOptimizationSteps > 0)
  {
    return "Boundary optimisation needs a fixed boundary (it moves the fixed boundary points).";
  }
  if (mixSearch && !(options.OptimalRange[0] <= options.OptimalRange[1]))
  {
    return "The search range of the optimal mix is empty.";
  }
  return CheckConstraints(options.Constraints, used);
}

/// The two boundary vertices farthest apart (all boundary loops) and their
/// squared distance: exact up to 20000 boundary vertices, else a double
/// sweep (farthest from any vertex, then farthest from that one).
double FarthestBoundaryPair(const std::vector<std::vector<Index>>& loops, const double* points, int threads,
  Index& pa, Index& pb)
{
  std::vector<Index> boundary;
  for (const auto& loop : loops)
  {
    boundary.insert(boundary.end(), loop.begin(), loop.end());
  }
  pa = pb = boundary[0];
  double far = -1.0;
  if (boundary.size() <= 20000)
  {
    std::vector<double> best(boundary.size(), -1.0);
    std::vector<Index> partner(boundary.size(), -1);
    ParallelFor(static_cast<std::int64_t>(boundary.size()), threads, [&](std::int64_t b, std::int64_t e) {
      for (std::int64_t i = b; i < e; ++i)
      {
        for (std::size_t j = i + 1; j < boundary.size(); ++j)
        {
          const double d = (Point(points, boundary[i]) - Point(points, boundary[j])).squaredNorm();
          if (d > best[i])
          {
            best[i] = d;
            partner[i] = boundary[j];
          }
        }
      }
    });
    for (std::size_t i = 0; i < boundary.size(); ++i)
    {
      if (best[i] > far)
      {
        far = best[i];
        pa = boundary[i];
        pb = partner[i];
      }
    }
    return far;
  }
  for (int sweep = 0; sweep < 2; ++sweep)
  {
    const Index from = sweep == 0 ? boundary[0] : pa;
    far = -1.0;
    for (Index v : boundary)
    {
      const double d = (Point(points, v) - Point(points, from)).squaredNorm();
      if (d > far)
      {
        far = d;
        (sweep == 0 ? pa : pb) = v;
      }
    }
  }
  return far;
}

/// The natural map is defined up to a similarity: with one point constraint,
/// translate it onto its target; with none, fit the map into [0,1]^2 by a
/// uniform scale and a translation (the energy does not change).
void PlaceNaturalMap(const ParameterizationOptions& options, const std::vector<std::uint8_t>& used,
  std::vector<double>& uv)
{
  const Index n = static_cast<Index>(used.size());
  if (options.Constraints.size() == 1)
  {
    const PointConstraint& c = options.Constraints[0];
    Vec2 at(0, 0);
    for (int j = 0; j < 3; ++j)
    {
      if (c.Vertices[j] >= 0)
      {
        at += c.Weights[j] * UV(uv.data(), c.Vertices[j]);
      }
    }
    for (Index v = 0; v < n; ++v)
    {
      uv[2 * v] += used[v] ? c.Target[0] - at.x() : 0.0;
      uv[2 * v + 1] += used[v] ? c.Target[1] - at.y() : 0.0;
    }
  }
  else if (options.Constraints.empty())
  {
    Vec2 lo(HUGE_VAL, HUGE_VAL), hi(-HUGE_VAL, -HUGE_VAL);
    for (Index v = 0; v < n; ++v)
    {
      if (used[v])
      {
        lo = lo.cwiseMin(UV(uv.data(), v));
        hi = hi.cwiseMax(UV(uv.data(), v));
      }
    }
    const double extent = std::max(hi.x() - lo.x(), hi.y() - lo.y());
    for (Index v = 0; v < n; ++v)
    {
      if (used[v] && extent > 0.0)
      {
        uv[2 * v] = (uv[2 * v] - lo.x()) / extent;
        uv[2 * v + 1] = (uv[2 * v + 1] - lo.y()) / extent;
      }
    }
  }
}

/// The natural conformal map (eq. 5.7): the two farthest boundary points
/// pinned at (0,0) and (d,0), d their 3D distance; with two or more point
/// constraints the pins' positions are unknowns too (the constraints then
/// fix the similarity that the pins fix otherwise).  An error message, or
/// empty with `uv` set.
std::string MapNatural(const MeshTopology& topo, const double* points, const ParameterizationOptions& options,
  const std::vector<std::vector<Index>>& loops, const std::vector<std::uint8_t>& used, int threads,
  ParameterizationResult& result, std::vector<double>& uv)
{
  const Index n = topo.NumberOfVertices();
  std::vector<Index> prev(n, -1);
  for (Index v = 0; v < n; ++v)
  {
    if (topo.BoundaryNext(v) >= 0)
    {
      prev[topo.BoundaryNext(v)] = v;
    }
  }
  Index pa = -1, pb = -1;
  const double far = FarthestBoundaryPair(loops, points, threads, pa, pb);
  if (!(far > 0.0))
  {
    return "Cannot parameterize: the boundary points all coincide.";
  }
  result.PinnedVertices = { pa, pb };
  Index degenerate = 0;
  const RowMatrix rows = NaturalSystem(topo, points, threads, prev, degenerate);
  result.DegenerateTriangles = degenerate;
  const bool freePins = options.Constraints.size() >= 2;
  std::vector<std::uint8_t> kind(2 * static_cast<std::size_t>(n), KindFactor);
  Eigen::MatrixXd fixed = Eigen::MatrixXd::Zero(2 * n, 1);
  for (Index v = 0; v < n; ++v)
  {
    if (!used[v])
    {
      kind[2 * v] = kind[2 * v + 1] = KindFixed;
    }
  }
  for (int d = 0; d < 2; ++d)
  {
    kind[2 * pa + d] = kind[2 * pb + d] = freePins ? KindExtra : KindFixed;
  }
  fixed(2 * pb, 0) = std::sqrt(far);
  ParameterizationSolver solver;
  std::string error;
  // u and v share the cotangent matrix and are coupled on the boundary only.
  if (!solver.Setup(rows, kind, fixed, true, VertexOrder(topo, points, threads), true, threads, error))
  {
    return "Cannot parameterize: " + error + ".";
  }
  std::vector<ConstraintRow> constraints;
  if (freePins)
  {
    AddConstraintRows(options, true, constraints);
  }
  Eigen::MatrixXd solution = fixed;
  if (!solver.Solve(constraints, solution, error))
  {
    return "Cannot parameterize: " + error + ".";
  }
  for (Index v = 0; v < n; ++v)
  {
    uv[2 * v] = used[v] ? solution(2 * v, 0) : 0.0;
    uv[2 * v + 1] = used[v] ? solution(2 * v + 1, 0) : 0.0;
  }
  PlaceNaturalMap(options, used, uv);
  return {};
}

/// The unknowns of a fixed-boundary map (one per vertex, u and v as two
/// columns) and the solves over them.
struct FixedBoundarySystem
{
  const MeshTopology& Topology;
  const double* Points;
  int Threads;
  std::vector<std::uint8_t> Kind;
  Eigen::MatrixXd Fixed;
  std::vector<int> FixedList;
  std::vector<Index> FreeList;
  std::vector<Index> Order;
  std::vector<ConstraintRow> Constraints;
  std::shared_ptr<RowMatrix> Rows;                  ///< of the last Solve
  std::shared_ptr<ParameterizationSolver> Solver;   ///< of the last Solve

  FixedBoundarySystem(const MeshTopology& topo, const double* points, int threads, const std::vector<std::uint8_t>& used)
    : Topology(topo)
    , Points(points)
    , Threads(threads)
    , Kind(topo.NumberOfVertices(), KindFactor)
    , Fixed(Eigen::MatrixXd::Zero(topo.NumberOfVertices(), 2))
  {
    for (Index v = 0; v < topo.NumberOfVertices(); ++v)
    {
      if (!used[v])
      {
        Kind[v] = KindUnused;
      }
    }
  }

  void Fix(Index v, double u, double w)
  {
    Kind[v] = KindFixed;
    Fixed(v, 0) = u;
    Fixed(v, 1) = w;
    FixedList.push_back(v);
  }

  /// Fixes the boundary (given positions on every loop, or the outer loop on
  /// a circle or square); an error message, or empty.
  std::string FixBoundary(const ParameterizationOptions& options, const std::vector<std::vector<Index>>& loops,
    const std::vector<Index>& outer)
  {
    if (options.Boundary == ParameterizationBoundary::Given)
    {
      if (!options.GivenUV)
      {
        return "Given boundary positions were requested but none were supplied.";
      }
      for (const auto& loop : loops)
      {
        for (Index v : loop)
        {
          const double u = options.GivenUV[2 * v], w = options.GivenUV[2 * v + 1];
          if (!std::isfinite(u) || !std::isfinite(w))
          {
            return "The given boundary position of point " + std::to_string(v) + " is not finite.";
          }
          Fix(v, u, w);
        }
      }
    }
    else
    {
      if (options.Boundary == ParameterizationBoundary::Square && outer.size() < 4)
      {
        return "A square boundary needs at least 4 boundary points.";
      }
      std::vector<double> placed(2 * static_cast<std::size_t>(Topology.NumberOfVertices()), 0.0);
      std::array<std::size_t, 4> corners{};
      const bool chosen =
        options.Boundary == ParameterizationBoundary::Square && options.Corners == SquareCorners::Sharpest;
      if (chosen)
      {
        corners = ChooseSquareCorners(Topology, Points, outer);
      }
      PlaceBoundaryLoop(outer, Points, options.Boundary, options.Spacing, placed.data(), chosen ? &corners : nullptr);
      for (Index v : outer)
      {
        Fix(v, placed[2 * v], placed[2 * v + 1]);
      }
    }
    for (Index v = 0; v < Topology.NumberOfVertices(); ++v)
    {
      if (Kind[v] == KindFactor)
      {
        FreeList.push_back(v);
      }
    }
    AddConstraintRows(options, false, Constraints);
    return {};
  }

  /// One solve of the energy lambda E_A + mu E_chi into `out` (2 per
  /// vertex); with `responses`, also its impulse responses (section 5.4.2)
  /// and, under point constraints, the map of a zero boundary (`offset`,
  /// free vertices x (u, v)).
  bool Solve(double lambda, double mu, std::vector<double>& out, Eigen::MatrixXd* responses,
    Eigen::MatrixXd* offset, ParameterizationResult& result, std::string& error)
  {
    Index degenerate = 0;
    Rows = std::make_shared<RowMatrix>(VertexSystem(Topology, Points, lambda, mu, Threads, degenerate));
    result.DegenerateTriangles = degenerate;
    Solver = std::make_shared<ParameterizationSolver>(); // kept for an implicit basis
    ParameterizationSolver& solver = *Solver;
    const RowMatrix& rows = *Rows;
    Eigen::MatrixXd solution = Fixed;
    if (Order.empty())
    {
      Order = VertexOrder(Topology, Points, Threads);
    }
    if (!solver.Setup(rows, Kind, Fixed, mu == 0.0, Order, false, Threads, error) ||
      !solver.Solve(Constraints, solution, error))
    {
      return false;
    }
    const Index n = Topology.NumberOfVertices();
    out.assign(2 * static_cast<std::size_t>(n), 0.0);
    for (Index v = 0; v < n; ++v)
    {
      out[2 * v] = solution(v, 0);
      out[2 * v + 1] = solution(v, 1);
    }
    if (responses)
    {
      ParameterizationSolver::ConstraintProjection projection;
      if (!solver.Project(Constraints, projection, error))
      {
        return false;
      }
      *responses = projection.Project(solver.ImpulseResponses(rows, FixedList));
      *offset = projection.Offset;
    }
    return true;
  }

  /// The boundary basis of the last Solve kept as its factorization (a
  /// symmetric system): a map and a pull-back of one solve each.
  std::unique_ptr<BoundaryBasis> ImplicitBasis(std::string& error)
  {
    auto projection = std::make_shared<ParameterizationSolver::ConstraintProjection>();
    if (!Solver->Project(Constraints, *projection, error))
    {
      return nullptr;
    }
    auto coupling = std::make_shared<Eigen::SparseMatrix<double>>(Solver->FixedCoupling(*Rows, FixedList));
    using Rows2 = Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor>;
    const Eigen::Index nb = coupling->cols(), nf = coupling->rows();
    std::shared_ptr<const ParameterizationSolver> solver = Solver;
    BoundaryBasis::Map map = [solver, coupling, projection, nb, nf](const double* in, double* out) {
      const Eigen::MatrixXd x0 = solver->Factor.Solve(-(*coupling * Eigen::Map<const Rows2>(in, nb, 2)));
      Eigen::Map<Rows2>(out, nf, 2) = projection->Project(x0) + projection->Offset;
    };
    // B^T g = -A_FB^T A_FF^-1 P^T g (A_FF symmetric).
    BoundaryBasis::Map pullBack = [solver, coupling, projection, nb, nf](const double* in, double* out) {
      const Eigen::MatrixXd y = solver->Factor.Solve(projection->ProjectTransposed(Eigen::Map<const Rows2>(in, nf, 2)));
      Eigen::Map<Rows2>(out, nb, 2) = -(coupling->transpose() * y);
    };
    return std::make_unique<BoundaryBasis>(Topology.NumberOfVertices(),
      std::vector<Index>(FixedList.begin(), FixedList.end()), FreeList, std::move(map), std::move(pullBack));
  }

  /// Section 5.5.1: the conformal and authalic maps, blended by the l of
  /// the search range that minimises the chosen energy (and so are their
  /// impulse responses, eq. 5.8, if asked for).
  bool SolveOptimalMix(const ParameterizationOptions& options, std::vector<double>& uv, Eigen::MatrixXd* responses,
    Eigen::MatrixXd* offset, ParameterizationResult& result, std::string& error)
  {
    std::vector<double> uvA, uvX;
    Eigen::MatrixXd responsesX, offsetX;
    if (!Solve(1.0, 0.0, uvA, responses, offset, result, error) ||
      !Solve(0.0, 1.0, uvX, responses ? &responsesX : nullptr, &offsetX, result, error))
    {
      return false;
    }
    const double a3 = TotalArea3D(Topology, Points, Threads), a2 = TotalArea2D(Topology, uvA.data(), Threads);
    const double s = a2 > 0.0 ? std::sqrt(a3 / a2) : 1.0;
    const std::vector<double> poly =
      MixEnergyPolynomial(Topology, Points, uvA.data(), uvX.data(), s, options.OptimalEnergy);
    const double l = MinimizePolynomial(poly, options.OptimalRange[0], options.OptimalRange[1]);
    result.OptimalMix = l;
    for (std::size_t k = 0; k < uv.size(); ++k)
    {
      uv[k] = l * uvA[k] + (1.0 - l) * uvX[k];
    }
    if (responses)
    {
      *responses = l * *responses + (1.0 - l) * responsesX;
      *offset = l * *offset + (1.0 - l) * offsetX;
    }
    return true;
  }
};

/// A map with a fixed boundary (section 5.3), optionally the optimal mix
/// (5.5.1), the boundary basis and boundary optimisation (5.5.2).  An error
/// message, or empty with `uv` set.
std::string MapFixedBoundary(const MeshTopology& topo, const double* points, const ParameterizationOptions& options,
  const std::vector<std::vector<Index>>& loops, const std::vector<std::uint8_t>& used, int threads,
  ParameterizationResult& result, std::vector<double>& uv)
{
  FixedBoundarySystem system(topo, points, threads, used);
  std::string error = system.FixBoundary(options, loops, result.OuterBoundary);
  if (!error.empty())
  {
    return error;
  }
  const bool wantBasis = options.KeepBoundaryBasis || options.BoundaryOptimizationSteps > 0;
  const double basisBytes = 8.0 * system.FreeList.size() * system.FixedList.size();
  // Beyond the limit the basis stays the factorization: symmetric systems only.
  const bool implicit = wantBasis && basisBytes > options.MaximumBasisBytes;
  if (implicit && (options.AuthalicWeight != 0.0 || options.OptimizeMix))
  {
    std::ostringstream os;
    os << "The boundary basis would need " << basisBytes / (1 << 20) << " MiB (" << system.FreeList.size()
       << " free x " << system.FixedList.size() << " boundary points), more than the limit of "
       << options.MaximumBasisBytes / (1 << 20) << " MiB; beyond it the basis is kept as the factorization, "
       << "which needs the conformal energy alone (authalic weight 0, no optimal mix).";
    return os.str();
  }
  Eigen::MatrixXd responses, offset;
  Eigen::MatrixXd* wanted = wantBasis && !implicit ? &responses : nullptr;
  const bool solved = options.OptimizeMix
    ? system.SolveOptimalMix(options, uv, wanted, &offset, result, error)
    : system.Solve(options.ConformalWeight, options.AuthalicWeight, uv, wanted, &offset, result, error);
  if (!solved)
  {
    return "Cannot parameterize: " + error + ".";
  }
  const Index n = topo.NumberOfVertices();
  std::unique_ptr<BoundaryBasis> basis;
  if (implicit)
  {
    basis = system.ImplicitBasis(error);
    if (!basis)
    {
      return "Cannot parameterize: " + error + ".";
    }
  }
  else if (wantBasis)
  {
    std::vector<double> shift; // 2 per free vertex, interleaved (none without constraints)
    for (Eigen::Index k = 0; !system.Constraints.empty() && k < offset.rows(); ++k)
    {
      shift.push_back(offset(k, 0));
      shift.push_back(offset(k, 1));
    }
    basis = std::make_unique<BoundaryBasis>(n,
      std::vector<Index>(system.FixedList.begin(), system.FixedList.end()), std::move(system.FreeList),
      std::vector<double>(responses.data(), responses.data() + responses.size()), std::move(shift));
  }
  for (Index v = 0; v < n; ++v)
  {
    if (!used[v])
    {
      uv[2 * v] = uv[2 * v + 1] = 0.0;
    }
  }
  if (basis && options.BoundaryOptimizationSteps > 0)
  {
    OptimizeBoundary(topo, points, *basis, options, uv, result);
  }
  if (options.KeepBoundaryBasis)
  {
    result.Basis = std::move(basis);
  }
  return {};
}

ParameterizationResult ParameterizeUnguarded(
  const MeshTopology& topo, const double* points, const ParameterizationOptions& given)
{
  // Line constraints become point constraints (section 5.4.1).
  ParameterizationOptions options = given;
  for (std::size_t k = 0; k < given.Lines.size(); ++k)
  {
    const std::string lineError = AppendLineConstraint(topo, points, given.Lines[k], options.Constraints);
    if (!lineError.empty())
    {
      return Fail("Line constraint " + std::to_string(k) + ": " + lineError);
    }
  }
  options.Lines.clear();
  std::vector<std::uint8_t> used;
  std::string error = CheckInput(topo, points, options, used);
  if (!error.empty())
  {
    return Fail(error);
  }
  const int threads = ResolveThreadCount(options.NumberOfThreads);
  ParameterizationResult result;
  const std::vector<std::vector<Index>> loops = topo.BoundaryLoops();
  result.OuterBoundary = loops[LongestLoop(loops, points)];
  std::vector<double> uv(2 * static_cast<std::size_t>(topo.NumberOfVertices()), 0.0);
  error = options.Boundary == ParameterizationBoundary::Natural
    ? MapNatural(topo, points, options, loops, used, threads, result, uv)
    : MapFixedBoundary(topo, points, options, loops, used, threads, result, uv);
  if (!error.empty())
  {
    return Fail(error);
  }
  for (double value : uv)
  {
    if (!std::isfinite(value))
    {
      return Fail("Cannot parameterize: the solution is not finite (degenerate triangles?).");
    }
  }
  if (result.DegenerateTriangles)
  {
    AppendWarning(result.Warning, std::to_string(result.DegenerateTriangles) +
        " zero-area triangles were left out of the energy");
  }
  result.UV = std::move(uv);
  return result;
}

} // namespace

} // namespace beltrami
