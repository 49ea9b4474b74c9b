// Beltrami core: the last passes of a remesh's optimisation at its
// slivers (Optimizer::MendSlivers): the free vertices of triangles below 20
// degrees moved towards the middle of their neighbours where that raises
// the smallest angle around them, the swaps after.
#include "Remeshing/RemeshOptimizer.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

namespace beltrami::detail
{

/// The cosine of the smallest angle of v's faces with v at x (in the
/// metric at v, if any).
double Optimizer::LargestCosineAround(Index v, const Vec3& x) const
{
  double largest = -1.0;
  const bool metric = !VertexMetric.empty();
  const Mat3 u = metric ? MetricFactor({ v }) : Mat3::Identity();
  M.ForEachOutgoing(v, [&](Index h) {
    const Vec3 a = M.Position(M.Head(h)), b = M.Position(M.Tail(HalfEdgeMesh::Prev(h)));
    largest = std::max(largest, metric ? LargestCosine(Vec3::Zero(), u * (a - x), u * (b - x)) : LargestCosine(x, a, b));
  });
  return largest;
}

/// The move of v to the middle of its neighbours, in the plane of the
/// input under it.
Vec3 Optimizer::ShiftToNeighbours(Index v) const
{
  Vec3 middle = Vec3::Zero();
  int count = 0;
  M.ForEachOutgoing(v, [&](Index h) {
    middle += M.Position(M.Head(h));
    ++count;
  });
  const Vec3 shift = middle / std::max(1, count) - M.Position(v);
  return shift - shift.dot(InputNormals[v]) * InputNormals[v];
}

/// A free vertex towards the middle of its neighbours (ShiftToNeighbours,
/// put back on the input), the whole way or a half or a quarter of it,
/// where that raises the smallest angle of its faces; where none does,
/// towards one of its neighbours or away from it (a half, a quarter or an
/// eighth of the way, in the plane of the input under it), the move that
/// raises it most: a vertex in the middle of a cap's long side whose edge
/// cannot be swapped (the other diagonal is an edge already: the few
/// vertices around a needle's tip) leaves the line towards the needle's
/// other side, or, where that would fold the cap (three samples of a seam
/// straight along a finger thinner than the spacing), away from it.
bool Optimizer::MoveToRounder(Index v)
{
  const Vec3 x = M.Position(v), shift = ShiftToNeighbours(v), normal = FanNormal(v);
  const double before = LargestCosineAround(v, x);
  for (double step = 1.0; step > 0.2; step *= 0.5)
  {
    double w[3], moved = 0.0;
    const Index t = NearestOnSurface(x + step * shift, R.Triangle[v], step * shift.norm(), w);
    // (Its faces within 120 degrees of their fan's normal rather than 60:
    // the fans at tips thinner than the spacing turn that far, and the move
    // only makes rounder triangles, folding none.)
    if (t >= 0 && LargestCosineAround(v, SurfacePoint(Topology, Points, t, w)) < before - 1e-9 &&
      Place(v, t, w, moved, &normal, -0.5))
    {
      return true;
    }
  }
  struct Candidate
  {
    double Cosine;
    Index Triangle;
    double W[3];
  };
  std::vector<Candidate> candidates;
  M.ForEachOutgoing(v, [&](Index h) {
    const Vec3 towards = M.Position(M.Head(h)) - x;
    const Vec3 along = towards - towards.dot(InputNormals[v]) * InputNormals[v];
    for (double step = 0.5; step > 0.1; step *= 0.5)
    {
      for (const double sign : { 1.0, -1.0 })
      {
        Candidate c;
        c.Triangle = NearestOnSurface(x + sign * step * along, R.Triangle[v], step * along.norm(), c.W);
        c.Cosine = c.Triangle >= 0 ? LargestCosineAround(v, SurfacePoint(Topology, Points, c.Triangle, c.W)) : 1.0;
        if (c.Cosine < before - 1e-9)
        {
          candidates.push_back(c);
        }
      }
    }
  });
  // (the roundest first that folds nothing: the roundest may turn a cap
  // inside out)
  std::sort(candidates.begin(), candidates.end(),
    [](const Candidate& a, const Candidate& b) { return a.Cosine < b.Cosine; });
  for (const Candidate& c : candidates)
  {
    double moved = 0.0;
    if (Place(v, c.Triangle, c.W, moved, &normal, -0.5))
    {
      return true;
    }
  }
  return false;
}

/// Moves the free vertices of triangles with an angle below `degrees` where
/// that raises the smallest angle around them (MoveToRounder), then swaps
/// (SwapSlivers); a few rounds, for what the last relaxation left.
std::int64_t Optimizer::MendSlivers(double degrees)
{
  const double bound = std::cos(degrees * M_PI / 180.0);
  std::int64_t mended = 0;
  for (int round = 0; round < 3; ++round)
  {
    std::int64_t moves = 0;
    for (Index f = 0; f < M.NumberOfFaces(); ++f)
    {
      const Index v[3] = { M.Tail(3 * f), M.Tail(3 * f + 1), M.Tail(3 * f + 2) };
      if (FaceLargestCosine(f) <= bound)
      {
        continue;
      }
      for (const Index u : v)
      {
        moves += Moves[u] == Free && MoveToRounder(u);
      }
    }
    mended += moves + SwapSlivers();
    if (moves == 0)
    {
      break;
    }
  }
  return mended;
}

} // namespace beltrami::detail
