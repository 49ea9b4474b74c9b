// Beltrami core, private to Flows/Fairing: one time step of the smoothing
// flows of chapter 3 - the flow's operator (a polynomial in the Laplacian,
// section 3.2.6), its velocity, and the explicit, Taubin and implicit steps
// with their solvers (hard, soft, axis and plane constraints: section 3.2.7).
#pragma once

#include "Flows/Fairing.h"
#include "Mesh/Geometry.h"
#include "Mesh/Laplacian.h"
#include "Solvers/Partition.h"

#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

namespace beltrami::detail
{

/// Section 3.2.7's axis and plane constraints: which part of a vertex's
/// motion is allowed.
struct Motions
{
  enum : std::uint8_t
  {
    Free = 0,
    OnAxis = 1, ///< only the component along Direction
    OnPlane = 2 ///< only the components normal to Direction
  };
  std::vector<std::uint8_t> Kind;
  std::vector<Vec3> Direction; ///< unit
  bool Any = false;

  /// v (3 values per vertex) reduced to its allowed part, in place.
  void Project(double* v) const
  {
    for (std::size_t i = 0; Any && i < Kind.size(); ++i)
    {
      if (Kind[i] != Free)
      {
        const Vec3 a(v[3 * i], v[3 * i + 1], v[3 * i + 2]);
        const Vec3 along = a.dot(Direction[i]) * Direction[i];
        const Vec3 kept = Kind[i] == OnAxis ? along : Vec3(a - along);
        std::copy(kept.data(), kept.data() + 3, v + 3 * i);
      }
    }
  }
  /// x = before + P (x - before): the allowed part of a move.
  void KeepAllowed(const std::vector<double>& before, double* x) const
  {
    if (!Any)
    {
      return;
    }
    std::vector<double> move(before.size());
    for (std::size_t k = 0; k < move.size(); ++k)
    {
      move[k] = x[k] - before[k];
    }
    Project(move.data());
    for (std::size_t k = 0; k < move.size(); ++k)
    {
      x[k] = before[k] + move[k];
    }
  }
};

/// The Laplacian of a step and what it is applied to.
struct Stage
{
  const GraphLaplacian& L;
  std::vector<std::uint8_t> Fixed; ///< rows that must not move
  std::vector<double> Omega;       ///< per-row weight (may be < 0 for anisotropy)
  const Index* Order = nullptr;    ///< LocalityOrder of L's graph, if known
  const Motions* Moves = nullptr;  ///< axis and plane constraints, if any
  /// A distributed run (see FairSurface): the rows this process owns are
  /// solved with the other processes' (one collective conjugate gradient);
  /// the other rows are ghosts, copies of their owners' rows.
  const Partition* Split = nullptr;
  /// Optional: where an order-2 solve starts (3 per row, near its result:
  /// the same points' run with a nearby step; ShiftedLaplacianProblem::Guess).
  const double* Guess = nullptr;
};

inline bool Constrained(const Stage& st)
{
  return st.Moves && st.Moves->Any;
}

/// The flow's operator, a polynomial in -L = M^-1 S: the velocity is
/// -sum_k C[k-1] (-L)^k X (order k: C[k-1] = 1, the others 0).
struct Powers
{
  double C[4] = { 0.0, 0.0, 0.0, 0.0 };
  int Degree = 0;

  static Powers Single(int order)
  {
    Powers p;
    p.C[order - 1] = 1.0;
    p.Degree = order;
    return p;
  }
  static Powers Of(const FairingOptions& o)
  {
    if (o.Order >= 1)
    {
      return Single(o.Order);
    }
    Powers p;
    for (int k = 1; k <= 4; ++k)
    {
      p.C[k - 1] = o.OrderWeights[k - 1];
      p.Degree = p.C[k - 1] != 0.0 ? k : p.Degree;
    }
    return p;
  }
  /// sum_k C[k-1] w^k.
  double operator()(double w) const
  {
    double sum = 0.0;
    for (int k = Degree; k >= 1; --k)
    {
      sum = (sum + C[k - 1]) * w;
    }
    return sum;
  }
  /// Only the term of order k, with a positive weight.
  bool Pure(int k) const
  {
    double others = 0.0;
    for (int j = 1; j <= 4; ++j)
    {
      others += j == k ? 0.0 : std::abs(C[j - 1]);
    }
    return Degree == k && C[k - 1] > 0.0 && others == 0.0;
  }
  bool NonNegative() const { return std::min({ C[0], C[1], C[2], C[3] }) >= 0.0; }
  /// The least and the largest value on [0, wmax] (wmax may be infinite).
  std::pair<double, double> Range(double wmax) const;
  /// The least of sign * p on [0, w] (w finite).
  double Least(double w, double sign = 1.0) const;
};

/// A step may amplify a frequency at most this much: beyond, its matrix is
/// nearly singular (or indefinite) and no solve is meaningful.
constexpr double MaximumGain = 100.0;

/// The flow velocity without the time step: -W sum_k C[k-1] (-L)^k X.
std::vector<double> Velocity(const Stage& st, const Powers& p, const double* x, int threads);

/// One backward Euler step (see ImplicitStep in FairingSteps.cxx); false
/// (nothing moved) when a combination's step is not defined.
bool ImplicitStep(const Stage& st, const FairingOptions& opt, double* x, FairingReport& report);

/// One step of the chosen integration; false when it is not defined (a
/// combination whose implicit step is not positive definite): nothing moved.
bool Integrate(const Stage& st, const FairingOptions& opt, double* x, FairingReport& report);

/// Which part of a displacement d at a vertex of normal n is kept.
enum class Keep
{
  Normal,    ///< (d.n) n
  Tangential ///< d - (d.n) n
};

/// Moves x[i] by the `keep` part of d[i] (both 3 per vertex), with
/// `normals` (UnitNormals of x before the move); vertices without a normal
/// (no area, NaN) or with a non-finite d[i] do not move.  `tangentialShare`
/// (Keep::Normal): that fraction of the tangential part is kept too.
void MoveAlongNormals(
  const std::vector<double>& normals, double* x, const double* d, Keep keep, double tangentialShare = 0.0);

/// The unit normals of the points (chapter 2's, ComputeCurvatures).
std::vector<double> UnitNormals(const MeshTopology& topo, const double* x, int threads);

/// What the flows may move: hard constraints (user-fixed or zero weight),
/// soft weights clamped to [0, 1], boundary vertices, and vertices the flows
/// cannot move (non-manifold, duplicate faces, non-finite: kept fixed).
struct VertexRoles
{
  std::vector<std::uint8_t> Fixed, Boundary;
  std::vector<double> Weight;
  Motions Moves; ///< axis and plane constraints of the vertices that are not fixed
  bool HardConstraints = false;
};

} // namespace beltrami::detail
