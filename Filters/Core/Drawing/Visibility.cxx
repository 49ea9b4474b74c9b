#include "Drawing/Visibility.h"

#include "Mesh/TriangleTree.h"
#include "Solvers/Partition.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <numeric>
#include <unordered_map>
#include <utility>

namespace beltrami
{

/// The vertices of the triangles around each vertex (with itself), as key
/// ids: a ray from a point of face f does not test the triangles with a
/// vertex next to a corner of f (the two rings of faces around f).
struct OcclusionIndex
{
  OcclusionIndex(const LineDrawingGeometry& geo, int numThreads)
    : Geo(geo)
    , Tree(geo.FieldPoints(), geo.Triangles.data(), geo.Triangles.size() / 3, numThreads)
  {
    // The faces around each vertex (CSR).
    Offsets.assign(static_cast<std::size_t>(geo.NumberOfVertices()) + 1, 0);
    for (const Index v : geo.Triangles)
    {
      ++Offsets[v + 1];
    }
    for (std::size_t v = 1; v < Offsets.size(); ++v)
    {
      Offsets[v] += Offsets[v - 1];
    }
    Faces.resize(geo.Triangles.size());
    std::vector<std::int64_t> at(Offsets.begin(), Offsets.end() - 1);
    for (std::size_t c = 0; c < geo.Triangles.size(); ++c)
    {
      Faces[at[geo.Triangles[c]]++] = static_cast<Index>(c / 3);
    }
    if (geo.Split)
    {
      ShareGhostStars();
    }
  }
  /// The key ids of the vertices of the faces around v (v among them; its
  /// local faces, or for a ghost vertex its owner's).
  template <typename Visit>
  bool AnyAround(Index v, Visit&& visit) const
  {
    if (!GhostOffsets.empty() && GhostOffsets[v + 1] > GhostOffsets[v])
    {
      return std::any_of(GhostStars.begin() + GhostOffsets[v], GhostStars.begin() + GhostOffsets[v + 1], visit);
    }
    for (std::int64_t i = Offsets[v]; i < Offsets[v + 1]; ++i)
    {
      const Index* t = Geo.Triangles.data() + 3 * static_cast<std::int64_t>(Faces[i]);
      if (visit(Geo.KeyId(t[0])) || visit(Geo.KeyId(t[1])) || visit(Geo.KeyId(t[2])))
      {
        return true;
      }
    }
    return false;
  }
  const LineDrawingGeometry& Geo;
  TriangleTree Tree;
  std::vector<std::int64_t> Offsets;
  std::vector<Index> Faces;
  /// Split runs: the stars (key ids) of the ghost vertices, from their
  /// owners (CSR over the vertices; empty ranges for the owned ones).
  std::vector<std::int64_t> GhostOffsets, GhostStars;

private:
  /// A ghost vertex is in the star of one of this process' vertices, so its
  /// owner has a neighbour of it that it does not own: each process sends
  /// the stars of such vertices, and keeps those of its ghosts.
  void ShareGhostStars()
  {
    const Partition& split = *Geo.Split;
    std::vector<double> packed; // per vertex: key, count, keys
    std::vector<std::int64_t> star;
    for (Index v = 0; v < Geo.NumberOfVertices(); ++v)
    {
      bool shared = false;
      star.clear();
      for (std::int64_t i = Offsets[v]; split.IsOwned(v) && i < Offsets[v + 1]; ++i)
      {
        for (int c = 0; c < 3; ++c)
        {
          const Index u = Geo.Triangles[3 * static_cast<std::int64_t>(Faces[i]) + c];
          shared = shared || !split.IsOwned(u);
          star.push_back(Geo.KeyId(u));
        }
      }
      if (shared)
      {
        std::sort(star.begin(), star.end());
        star.erase(std::unique(star.begin(), star.end()), star.end());
        packed.push_back(static_cast<double>(Geo.KeyId(v))); // (global rows: exact in doubles)
        packed.push_back(static_cast<double>(star.size()));
        packed.insert(packed.end(), star.begin(), star.end());
      }
    }
    const std::vector<double> all = split.AllGather(packed);
    std::unordered_map<std::int64_t, Index> ghosts;
    for (Index v = 0; v < Geo.NumberOfVertices(); ++v)
    {
      if (!split.IsOwned(v))
      {
        ghosts.emplace(Geo.KeyId(v), v);
      }
    }
    std::vector<std::pair<Index, std::size_t>> found; // (ghost, where its star starts in `all`)
    for (std::size_t at = 0; at < all.size(); at += 2 + static_cast<std::size_t>(all[at + 1]))
    {
      const auto ghost = ghosts.find(static_cast<std::int64_t>(all[at]));
      if (ghost != ghosts.end())
      {
        found.emplace_back(ghost->second, at);
      }
    }
    std::sort(found.begin(), found.end());
    GhostOffsets.assign(static_cast<std::size_t>(Geo.NumberOfVertices()) + 1, 0);
    for (const auto& [v, at] : found)
    {
      const std::size_t count = static_cast<std::size_t>(all[at + 1]);
      GhostOffsets[v + 1] = static_cast<std::int64_t>(count);
      std::transform(all.begin() + at + 2, all.begin() + at + 2 + count, std::back_inserter(GhostStars),
        [](double key) { return static_cast<std::int64_t>(key); });
    }
    for (std::size_t v = 1; v < GhostOffsets.size(); ++v)
    {
      GhostOffsets[v] += GhostOffsets[v - 1];
    }
  }
};

const OcclusionIndex& LineDrawingGeometry::Occluders() const
{
  if (!Occlusion)
  {
    Occlusion = std::make_shared<const OcclusionIndex>(*this, Threads); // (split: collective)
  }
  return *Occlusion;
}

namespace
{

/// A point of a line to test, and the key ids of the corners of the faces
/// on either side of it (-1: none).
struct Query
{
  Vec3 P;
  std::int64_t Corners[6];
};
constexpr int ValuesPerQuery = 9;

/// The occlusion test of points on the surface for one view.
class Eye
{
public:
  Eye(const LineDrawingGeometry& geo, const LineSet& lines, const LineView& view, int threads)
    : Geo(geo)
    , Lines(lines)
    , Occluders(geo.Occluders())
    , View(view)
    , Threads(threads)
  {
    // Orthographic: towards the viewer, past everything (the box diagonal is
    // 100 automatic feature sizes).
    const double reach = 300.0 * std::max(geo.AutomaticFeatureSize(), 1e-300);
    Toward = -reach * view.Direction.normalized();
  }
  /// The test of point p of the pieces in faces[0] and faces[1] (-1: none)
  /// of the lines.
  Query At(const Vec3& p, const Index faces[2]) const
  {
    Query q{ p, { -1, -1, -1, -1, -1, -1 } };
    for (int k = 0; k < 6; ++k)
    {
      const Index f = faces[k / 3];
      if (f >= 0)
      {
        const std::int64_t c = 3 * static_cast<std::int64_t>(f) + k % 3;
        q.Corners[k] = Lines.FaceCorners.empty() ? Geo.KeyId(Geo.Triangles[c]) : Lines.FaceCorners[c];
      }
    }
    return q;
  }
  /// Per query: whether its point is seen from the eye (split runs:
  /// collective, each process' triangles tested, every process' queries).
  std::vector<std::uint8_t> See(const std::vector<Query>& queries) const
  {
    if (!Geo.Split)
    {
      std::vector<std::uint8_t> seen(queries.size());
      ParallelFor(static_cast<std::int64_t>(queries.size()), Threads, [&](std::int64_t begin, std::int64_t end) {
        for (std::int64_t i = begin; i < end; ++i)
        {
          seen[i] = !Blocked(queries[i]);
        }
      }, {}, 0, 256);
      return seen;
    }
    std::vector<double> packed;
    for (const Query& q : queries)
    {
      packed.insert(packed.end(), { q.P[0], q.P[1], q.P[2] });
      packed.insert(packed.end(), q.Corners, q.Corners + 6); // (global rows: exact in doubles)
    }
    const std::vector<double> counts = Geo.Split->AllGather({ static_cast<double>(queries.size()) });
    const std::vector<double> all = Geo.Split->AllGather(packed);
    std::vector<double> blocked(all.size() / ValuesPerQuery);
    ParallelFor(static_cast<std::int64_t>(blocked.size()), Threads, [&](std::int64_t begin, std::int64_t end) {
      for (std::int64_t i = begin; i < end; ++i)
      {
        const double* v = all.data() + ValuesPerQuery * i;
        Query q{ Vec3(v[0], v[1], v[2]), {} };
        std::transform(v + 3, v + 9, q.Corners, [](double c) { return static_cast<std::int64_t>(c); });
        blocked[i] = Blocked(q);
      }
    }, {}, 0, 256);
    Geo.Split->Max(blocked.data(), static_cast<int>(blocked.size()));
    const std::size_t first = static_cast<std::size_t>(
      std::accumulate(counts.begin(), counts.begin() + Geo.Split->Rank(), 0.0));
    std::vector<std::uint8_t> seen(queries.size());
    for (std::size_t i = 0; i < seen.size(); ++i)
    {
      seen[i] = blocked[first + i] == 0.0;
    }
    return seen;
  }

private:
  /// Whether a triangle here that the triangles around q's faces leave
  /// (a contour's ray grazes the surface, and the piecewise-flat surface
  /// near it, within its chordal error of the smooth one, crossed it up to
  /// two triangles away: a torus of 100 x 50 quads seen at 13 degrees with
  /// one ring left out hid pieces of its contours) lies between q and the eye.
  bool Blocked(const Query& q) const
  {
    const Vec3 d = View.Perspective ? Vec3(View.Position - q.P) : Toward;
    const auto corner = [&q](std::int64_t key) { return std::find(q.Corners, q.Corners + 6, key) != q.Corners + 6; };
    return Occluders.Tree.Blocks(q.P, d, 1e-9, [&](Index t) {
      const Index* v = Geo.Triangles.data() + 3 * static_cast<std::int64_t>(t);
      return Occluders.AnyAround(v[0], corner) || Occluders.AnyAround(v[1], corner) ||
        Occluders.AnyAround(v[2], corner);
    });
  }
  const LineDrawingGeometry& Geo;
  const LineSet& Lines;
  const OcclusionIndex& Occluders;
  const LineView& View;
  int Threads;
  Vec3 Toward;
};

/// Where the rays of the lines' points start: on the surface the fields
/// were measured on (FieldPoints).
const double* RayPoints(const LineSet& lines)
{
  return lines.FieldPoints.size() == lines.Points.size() ? lines.FieldPoints.data() : lines.Points.data();
}

/// Where the visibility changes along a piece of a line: (entry of
/// Connectivity that starts the piece, parameter along it), sorted.
using Switches = std::vector<std::pair<Index, double>>;

/// A stretch of the piece that starts at entry K, [Lo, Hi] of it, seen at
/// Lo (Before) and not at Hi or the other way round.
struct Change
{
  Index K;
  double Lo, Hi;
  bool Before;
};

/// The stretches of the pieces where the visibility changes, between
/// samples at most `spacing` apart (the ends: seenAt).
std::vector<Change> SampleChanges(const LineSet& lines, const Eye& eye, double spacing,
  const std::vector<std::uint8_t>& seenAt)
{
  std::vector<Query> queries;
  std::vector<std::pair<Index, int>> pieces; // (entry, samples) of the pieces sampled inside
  for (Index k = 0; k < static_cast<Index>(lines.Connectivity.size()); ++k)
  {
    const Index f = lines.EdgeFace[k];
    const Vec3 a = Point(RayPoints(lines), lines.Connectivity[k]);
    const Vec3 b = Point(RayPoints(lines), lines.Connectivity[f >= 0 ? k + 1 : k]);
    const int samples = static_cast<int>(std::clamp(std::ceil((b - a).norm() / spacing), 1.0, 1e4));
    if (f < 0 || (samples == 1 && seenAt[k] == seenAt[k + 1]))
    {
      continue; // a line's last point, or a piece seen (hidden) at both ends
    }
    pieces.emplace_back(k, samples);
    const Index sides[2] = { f, -1 };
    for (int j = 1; j < samples; ++j)
    {
      queries.push_back(eye.At(a + (static_cast<double>(j) / samples) * (b - a), sides));
    }
  }
  const std::vector<std::uint8_t> seen = eye.See(queries);
  std::vector<Change> changes;
  std::size_t at = 0;
  for (const auto& [k, samples] : pieces)
  {
    bool before = seenAt[k] != 0;
    for (int j = 1; j <= samples; ++j)
    {
      const bool after = j == samples ? seenAt[k + 1] != 0 : seen[at++] != 0;
      if (after != before)
      {
        changes.push_back({ k, static_cast<double>(j - 1) / samples, static_cast<double>(j) / samples, before });
      }
      before = after;
    }
  }
  return changes;
}

/// Per entry of Connectivity: whether its point is seen (each point tested
/// once, the triangles around the pieces on both its sides left out); and
/// the changes inside the pieces, found between samples at most `spacing`
/// apart by bisection to 2^-12 of the piece (split runs: collective, the
/// same rounds on every process).
void TestPieces(const LineSet& lines, const Eye& eye, double spacing, std::vector<std::uint8_t>& seenAt,
  Switches& switches)
{
  const Index entries = static_cast<Index>(lines.Connectivity.size());
  std::vector<Query> queries;
  std::vector<Index> tested;
  for (Index k = 0; k < entries; ++k)
  {
    const Index sides[2] = { k > 0 ? lines.EdgeFace[k - 1] : -1, lines.EdgeFace[k] }; // (-1 past a line's ends)
    if (sides[0] >= 0 || sides[1] >= 0)
    {
      queries.push_back(eye.At(Point(RayPoints(lines), lines.Connectivity[k]), sides));
      tested.push_back(k);
    }
  }
  seenAt.assign(static_cast<std::size_t>(entries), 1);
  const std::vector<std::uint8_t> seen = eye.See(queries);
  for (std::size_t i = 0; i < tested.size(); ++i)
  {
    seenAt[tested[i]] = seen[i];
  }
  std::vector<Change> changes = SampleChanges(lines, eye, spacing, seenAt);
  for (int halving = 0; halving < 12; ++halving)
  {
    queries.clear();
    for (const Change& c : changes)
    {
      const Vec3 a = Point(RayPoints(lines), lines.Connectivity[c.K]);
      const Vec3 b = Point(RayPoints(lines), lines.Connectivity[c.K + 1]);
      const Index sides[2] = { lines.EdgeFace[c.K], -1 };
      queries.push_back(eye.At(a + (0.5 * (c.Lo + c.Hi)) * (b - a), sides));
    }
    const std::vector<std::uint8_t> middle = eye.See(queries);
    for (std::size_t i = 0; i < changes.size(); ++i)
    {
      Change& c = changes[i];
      ((middle[i] != 0) == c.Before ? c.Lo : c.Hi) = 0.5 * (c.Lo + c.Hi);
    }
  }
  switches.clear();
  for (const Change& c : changes)
  {
    switches.emplace_back(c.K, 0.5 * (c.Lo + c.Hi));
  }
  std::sort(switches.begin(), switches.end());
}

/// A point of a part being built: position, normal, strength, field point, and the face
/// of the piece from it to the next point.
struct PartPoint
{
  double Values[10]; // position, normal, strength, field point
  Index Face;
};
struct Part
{
  std::vector<PartPoint> Points;
  bool Seen = true;
};

PartPoint PointOf(const LineSet& lines, Index entry, Index face)
{
  const Index i = lines.Connectivity[entry];
  PartPoint p;
  std::copy(lines.Points.begin() + 3 * i, lines.Points.begin() + 3 * i + 3, p.Values);
  std::copy(lines.Normals.begin() + 3 * i, lines.Normals.begin() + 3 * i + 3, p.Values + 3);
  p.Values[6] = lines.PointStrength[i];
  std::copy(RayPoints(lines) + 3 * i, RayPoints(lines) + 3 * i + 3, p.Values + 7);
  p.Face = face;
  return p;
}

/// The point at parameter t between a and b (the normal renormalized).
PartPoint Between(const PartPoint& a, const PartPoint& b, double t)
{
  PartPoint p;
  for (int k = 0; k < 10; ++k)
  {
    p.Values[k] = (1.0 - t) * a.Values[k] + t * b.Values[k];
  }
  const double n = std::sqrt(p.Values[3] * p.Values[3] + p.Values[4] * p.Values[4] + p.Values[5] * p.Values[5]);
  for (int k = 3; k < 6 && n > 0.0; ++k)
  {
    p.Values[k] /= n;
  }
  p.Face = a.Face;
  return p;
}

/// Line l cut into its seen and hidden parts.
std::vector<Part> CutLine(const LineSet& lines, Index l, const std::vector<std::uint8_t>& seenAt,
  const Switches& switches, Switches::const_iterator& at)
{
  std::vector<Part> parts;
  const Index first = lines.Offsets[l], last = lines.Offsets[l + 1] - 1;
  const auto start = [&](const PartPoint& p, bool seen) {
    parts.emplace_back();
    parts.back().Seen = seen;
    parts.back().Points.push_back(p);
  };
  start(PointOf(lines, first, lines.EdgeFace[first]), seenAt[first] != 0);
  for (Index k = first; k < last; ++k)
  {
    const PartPoint a = PointOf(lines, k, lines.EdgeFace[k]), b = PointOf(lines, k + 1, lines.EdgeFace[k + 1]);
    for (; at != switches.end() && at->first == k; ++at)
    {
      const PartPoint q = Between(a, b, at->second);
      parts.back().Points.push_back(q);
      start(q, !parts.back().Seen);
    }
    parts.back().Points.push_back(b);
  }
  const bool closed = lines.Closed[l] != 0;
  if (closed && parts.size() > 1 && parts.front().Seen == parts.back().Seen)
  {
    // A loop's last part goes on into its first.
    Part& tail = parts.back();
    tail.Points.insert(tail.Points.end(), parts.front().Points.begin() + 1, parts.front().Points.end());
    parts.front() = std::move(tail);
    parts.pop_back();
  }
  return parts;
}

double Length(const Part& part)
{
  double length = 0.0;
  for (std::size_t k = 1; k < part.Points.size(); ++k)
  {
    const double* a = part.Points[k - 1].Values;
    const double* b = part.Points[k].Values;
    length += std::sqrt((b[0] - a[0]) * (b[0] - a[0]) + (b[1] - a[1]) * (b[1] - a[1]) + (b[2] - a[2]) * (b[2] - a[2]));
  }
  return length;
}

void AppendPart(const Part& part, std::uint8_t type, bool closed, LineSet& out)
{
  double sum = 0.0;
  for (std::size_t k = 0; k < part.Points.size(); ++k)
  {
    const PartPoint& p = part.Points[k];
    const bool repeat = closed && k + 1 == part.Points.size(); // (a loop's first point again)
    const Index id = repeat ? out.Connectivity[out.Offsets.back()] : static_cast<Index>(out.PointStrength.size());
    if (!repeat)
    {
      out.Points.insert(out.Points.end(), p.Values, p.Values + 3);
      out.Normals.insert(out.Normals.end(), p.Values + 3, p.Values + 6);
      out.FieldPoints.insert(out.FieldPoints.end(), p.Values + 7, p.Values + 10);
      out.PointStrength.push_back(p.Values[6]);
      sum += p.Values[6];
    }
    out.Connectivity.push_back(id);
    out.EdgeFace.push_back(k + 1 < part.Points.size() ? p.Face : -1);
  }
  out.Offsets.push_back(static_cast<Index>(out.Connectivity.size()));
  out.Type.push_back(type);
  out.Closed.push_back(closed);
  out.Strength.push_back(sum / static_cast<double>(part.Points.size() - (closed ? 1 : 0)));
  out.Hidden.push_back(!part.Seen);
}

} // namespace

LineSet SplitByVisibility(const LineSet& given, const LineDrawingGeometry& geometry, const LineView& view,
  const VisibilityOptions& options)
{
  const bool faces = given.EdgeFace.size() == given.Connectivity.size();
  LineSet unknown;
  if (!faces)
  {
    unknown = given; // (no faces: nothing tested, every line kept as seen)
    unknown.EdgeFace.assign(given.Connectivity.size(), -1);
  }
  const LineSet& lines = faces ? given : unknown;
  const Eye eye(geometry, lines, view, options.NumberOfThreads);
  std::vector<std::uint8_t> seenAt;
  Switches switches;
  TestPieces(lines, eye, std::max(geometry.AutomaticFeatureSize(), 1e-300), seenAt, switches);
  LineSet out;
  out.FaceCorners = lines.FaceCorners;
  auto at = switches.cbegin();
  for (Index l = 0; l < lines.NumberOfLines(); ++l)
  {
    const std::vector<Part> parts = CutLine(lines, l, seenAt, switches, at);
    const bool whole = parts.size() == 1 && lines.Closed[l] != 0;
    // (A line whole passed the chaining's length test already.)
    const bool pruned = parts.size() > 1 && lines.Type[l] != static_cast<std::uint8_t>(LineType::Boundary) &&
      lines.Type[l] != static_cast<std::uint8_t>(LineType::Crease);
    for (const Part& part : parts)
    {
      if ((part.Seen || options.KeepHidden) && part.Points.size() >= 2 &&
        (!pruned || Length(part) >= options.MinimumLength))
      {
        AppendPart(part, lines.Type[l], whole, out);
      }
    }
  }
  return out;
}

} // namespace beltrami
