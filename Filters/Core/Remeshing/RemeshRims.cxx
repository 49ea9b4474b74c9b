// Beltrami core: the remesh's corners on the surface's boundary that only
// seams made, moved along it after the stitching rounds where their
// triangles are slivers (Optimizer::RoundRimCorners).
#include "Remeshing/RemeshOptimizer.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

namespace beltrami::detail
{

namespace
{

/// The surface's boundary loops as closed paths (first vertex == last) with
/// their arc lengths, and per surface vertex its loop and place in it.
struct RimLoops
{
  std::vector<SamplePath> Loops;
  std::vector<int> LoopOf;   ///< per surface vertex, -1 off the boundary
  std::vector<Index> Place;  ///< per surface vertex: its index in its loop's Vertices

  RimLoops(const MeshTopology& topology, const double* points)
    : LoopOf(topology.NumberOfVertices(), -1), Place(topology.NumberOfVertices(), -1)
  {
    for (std::vector<Index>& loop : topology.BoundaryLoops())
    {
      SamplePath path;
      path.Vertices = std::move(loop);
      path.Vertices.push_back(path.Vertices.front());
      path.Arc.assign(path.Vertices.size(), 0.0);
      for (std::size_t i = 0; i + 1 < path.Vertices.size(); ++i)
      {
        LoopOf[path.Vertices[i]] = static_cast<int>(Loops.size());
        Place[path.Vertices[i]] = static_cast<Index>(i);
        path.Arc[i + 1] = path.Arc[i] + (Point(points, path.Vertices[i + 1]) - Point(points, path.Vertices[i])).norm();
      }
      Loops.push_back(std::move(path));
    }
  }

  /// The loop and arc length of a point on the boundary (in `triangle` at
  /// barycentric weights w); loop -1 where the point is not on one edge or
  /// vertex of a loop.
  std::pair<int, double> ArcOf(const MeshTopology& topology, Index triangle, const double* w) const
  {
    Index on[2] = { -1, -1 };
    double weight[2] = { 0.0, 0.0 };
    int count = 0;
    for (int k = 0; k < 3; ++k)
    {
      if (w[k] > 1e-9)
      {
        if (count == 2)
        {
          return { -1, 0.0 };
        }
        on[count] = topology.CornerVertex(3 * triangle + k);
        weight[count++] = w[k];
      }
    }
    const int loop = count > 0 ? LoopOf[on[0]] : -1;
    if (loop < 0 || (count == 2 && LoopOf[on[1]] != loop))
    {
      return { -1, 0.0 };
    }
    const SamplePath& path = Loops[loop];
    Index a = Place[on[0]];
    if (count == 1)
    {
      return { loop, path.Arc[a] };
    }
    Index b = Place[on[1]];
    const Index n = static_cast<Index>(path.Vertices.size()) - 1;
    double t = weight[1] / (weight[0] + weight[1]); // of the way from on[0] to on[1]
    if ((a + 1) % n != b)
    {
      std::swap(a, b);
      t = 1.0 - t;
      if ((a + 1) % n != b)
      {
        return { -1, 0.0 };
      }
    }
    return { loop, path.Arc[a] + t * (path.Arc[a + 1] - path.Arc[a]) };
  }
};

/// The input vertex a sample lies on (its weight 1), or -1.
Index SampleVertex(const MeshTopology& topology, Index triangle, const double* w)
{
  for (int k = 0; k < 3; ++k)
  {
    if (w[k] > 1.0 - 1e-9)
    {
      return topology.CornerVertex(3 * triangle + k);
    }
  }
  return -1;
}

/// An arc length of a closed loop of `length` in [0, length).
double Wrapped(double arc, double length)
{
  return std::fmod(std::fmod(arc, length) + length, length);
}

/// The point of loop `rim` at arc length `arc` (any: wrapped).
Vec3 LoopPoint(const MeshTopology& topology, const double* points, const SamplePath& rim, double arc)
{
  double w[3];
  const Index t = LocateOnPath(topology, rim, Wrapped(arc, rim.Arc.back()), w);
  return SurfacePoint(topology, points, t, w);
}

/// The largest distance of the vertices of loop `rim` between arcs `from`
/// and from + span (forwards) from the chords of a vertex at x (at arc
/// `place` between them) to the loop's points at from and from + span.
double RimSag(const MeshTopology& topology, const double* points, const SamplePath& rim, double from, double span,
  double place, const Vec3& x)
{
  const double length = rim.Arc.back();
  const std::size_t n = rim.Vertices.size() - 1;
  const Vec3 behind = LoopPoint(topology, points, rim, from), ahead = LoopPoint(topology, points, rim, from + span);
  const double start = Wrapped(from, length);
  std::size_t j = static_cast<std::size_t>(std::upper_bound(rim.Arc.begin(), rim.Arc.end(), start) - rim.Arc.begin()) % n;
  double sag = 0.0;
  for (double along = Wrapped(rim.Arc[j] - start, length); along < span && along < length;
       along += rim.Arc[j + 1] - rim.Arc[j], j = (j + 1) % n)
  {
    const Vec3 p = Point(points, rim.Vertices[j]);
    sag = std::max(sag, from + along < place ? SegmentDistance(p, behind, x) : SegmentDistance(p, x, ahead));
  }
  return sag;
}

} // namespace

/// Whether corner sample v may slide along the surface's boundary: it lies
/// on a vertex of a boundary loop where no feature line ends (no other kept
/// edge), and that vertex is not pinned (a seam's end, or a loop's start).
bool Optimizer::SlidingRimCorner(Index v, const std::uint8_t* featureEdges, const std::uint8_t* pinned) const
{
  if (R.Kind[v] != SampleKind::Corner || Moves[v] != Fixed || !M.IsBoundaryVertex(v))
  {
    return false;
  }
  const Index c = SampleVertex(Topology, R.Triangle[v], &R.Barycentric[3 * v]);
  if (c < 0 || (pinned && pinned[c]) || Topology.IsInterior(c))
  {
    return false;
  }
  const MeshTopology::EdgeTable& edges = Topology.Edges();
  int kept = 0;
  for (std::int64_t k = edges.NeighborOffsets[c]; k < edges.NeighborOffsets[c + 1]; ++k)
  {
    kept += IsKeptEdge(edges, edges.NeighborEdges[k], featureEdges);
  }
  return kept == 2;
}

std::int64_t Optimizer::RoundRimCorners(const std::uint8_t* featureEdges, const std::uint8_t* pinned, double maxSag)
{
  const double bar = std::cos(RimCornerDegrees * M_PI / 180.0);
  std::vector<Index> sliding;
  for (Index v = 0; v < M.NumberOfVertices(); ++v)
  {
    if (SlidingRimCorner(v, featureEdges, pinned) && LargestCosineAround(v, M.Position(v)) > bar)
    {
      sliding.push_back(v);
    }
  }
  if (sliding.empty())
  {
    return 0;
  }
  const RimLoops rims(Topology, Points);
  const auto arcOf = [&](Index u) { return rims.ArcOf(Topology, R.Triangle[u], &R.Barycentric[3 * u]); };
  std::int64_t moves = 0;
  for (const Index v : sliding)
  {
    // Its neighbours along the remesh's boundary: the head of its boundary
    // half-edge and the tail of the boundary half-edge into it.
    Index last = -1;
    M.ForEachOutgoing(v, [&](Index h) { last = h; });
    const Index next = M.Head(M.OutgoingHalfEdge(v)), previous = M.Tail(HalfEdgeMesh::Prev(last));
    const auto [loop, arc] = arcOf(v);
    const auto [loopNext, arcNext] = arcOf(next);
    const auto [loopPrevious, arcPrevious] = arcOf(previous);
    if (loop < 0 || loopNext != loop || loopPrevious != loop || next == previous)
    {
      continue;
    }
    // The gaps to the neighbours behind and ahead of v along the loop.
    const SamplePath& rim = rims.Loops[loop];
    const double length = rim.Arc.back();
    const auto ahead = [&](double from, double to) { return std::fmod(to - from + 2.0 * length, length); };
    double gapAhead = ahead(arc, arcNext), gapBehind = ahead(arcPrevious, arc);
    if (gapAhead + gapBehind > length) // the remesh's boundary runs against the loop
    {
      gapAhead = ahead(arc, arcPrevious);
      gapBehind = ahead(arcNext, arc);
    }
    if (!(gapAhead + gapBehind < length))
    {
      continue;
    }
    // Of the places a fifth to four fifths of the way from the neighbour
    // behind to the one ahead, the one whose triangles have the largest
    // smallest angle (where larger than here) and whose chords to them keep
    // within the line's sag bound (or within theirs now) of the loop's
    // points between them: a corner of the rim is not cut.
    const double from = arc - gapBehind, span = gapAhead + gapBehind;
    const double bound =
      std::max(maxSag * 0.5 * span, RimSag(Topology, Points, rim, from, span, from + gapBehind, M.Position(v)));
    double best = LargestCosineAround(v, M.Position(v)), bestArc = arc;
    for (int k = 2; k <= 8; ++k)
    {
      const double place = from + 0.1 * k * span;
      double w[3];
      const Vec3 x = SurfacePoint(Topology, Points, LocateOnPath(Topology, rim, Wrapped(place, length), w), w);
      const double cosine = LargestCosineAround(v, x);
      if (cosine < best && RimSag(Topology, Points, rim, from, span, place, x) <= bound)
      {
        best = cosine;
        bestArc = Wrapped(place, length);
      }
    }
    double moved = 0.0, w[3];
    if (bestArc != arc && Place(v, LocateOnPath(Topology, rim, bestArc, w), w, moved))
    {
      ++moves;
    }
  }
  if (moves > 0)
  {
    for (Index v = 0; v < M.NumberOfVertices(); ++v)
    {
      Moves[v] = M.IsBoundaryVertex(v) && Moves[v] != Free ? Fixed : Moves[v]; // (their paths' arcs are stale)
    }
  }
  return moves;
}

} // namespace beltrami::detail
