#include "Drawing/Visibility.h"

#include "Mesh/TriangleTree.h"

#include <algorithm>
#include <cmath>
#include <mutex>
#include <utility>

namespace beltrami
{

struct OcclusionIndex
{
  explicit OcclusionIndex(const LineDrawingGeometry& geo)
    : Tree(geo.Points.data(), geo.Triangles.data(), geo.Triangles.size() / 3)
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
  }
  TriangleTree Tree;
  std::vector<std::int64_t> Offsets;
  std::vector<Index> Faces;
};

const OcclusionIndex& LineDrawingGeometry::Occluders() const
{
  if (!Occlusion)
  {
    Occlusion = std::make_shared<const OcclusionIndex>(*this);
  }
  return *Occlusion;
}

namespace
{

/// The occlusion test of points on the surface for one view.
class Eye
{
public:
  Eye(const LineDrawingGeometry& geo, const LineView& view)
    : Geo(geo)
    , Occluders(geo.Occluders())
    , View(view)
  {
    // Orthographic: towards the viewer, past everything (the box diagonal is
    // 100 automatic feature sizes).
    const double reach = 300.0 * std::max(geo.AutomaticFeatureSize(), 1e-300);
    Toward = -reach * view.Direction.normalized();
  }
  /// The vertices of the faces around the corners of faces[0] and faces[1]
  /// (-1: none): a ray from a point of them does not test the triangles that have one (the two rings of
  /// faces around f).  A contour's ray grazes the surface, and the
  /// piecewise-flat surface near it, within its chordal error of the smooth
  /// one, crossed it up to two triangles away (a torus of 100 x 50 quads
  /// seen at 13 degrees: one ring left out hid pieces of its contours).
  void Around(const Index faces[2], std::vector<Index>& skip) const
  {
    skip.clear();
    for (int k = 0; k < 6; ++k)
    {
      const Index f = faces[k / 3];
      if (f < 0)
      {
        continue;
      }
      const Index v = Geo.Triangles[3 * static_cast<std::int64_t>(f) + k % 3];
      for (std::int64_t i = Occluders.Offsets[v]; i < Occluders.Offsets[v + 1]; ++i)
      {
        const Index* t = Geo.Triangles.data() + 3 * static_cast<std::int64_t>(Occluders.Faces[i]);
        skip.insert(skip.end(), t, t + 3);
      }
    }
    std::sort(skip.begin(), skip.end());
    skip.erase(std::unique(skip.begin(), skip.end()), skip.end());
  }
  /// Whether point p of faces[0] or faces[1] is seen from the eye (`skip`:
  /// their Around, found on the first triangle met, if one is).
  bool Sees(const Vec3& p, const Index faces[2], std::vector<Index>& skip) const
  {
    const Vec3 d = View.Perspective ? Vec3(View.Position - p) : Toward;
    bool found = false;
    return !Occluders.Tree.Blocks(p, d, 1e-9, [&](Index t) {
      if (!found)
      {
        Around(faces, skip);
        found = true;
      }
      const Index* v = Geo.Triangles.data() + 3 * static_cast<std::int64_t>(t);
      return std::binary_search(skip.begin(), skip.end(), v[0]) || std::binary_search(skip.begin(), skip.end(), v[1]) ||
        std::binary_search(skip.begin(), skip.end(), v[2]);
    });
  }

private:
  const LineDrawingGeometry& Geo;
  const OcclusionIndex& Occluders;
  const LineView& View;
  Vec3 Toward;
};

/// Where the visibility changes along a piece of a line: (entry of
/// Connectivity that starts the piece, parameter along it), sorted.
using Switches = std::vector<std::pair<Index, double>>;

/// Per entry of Connectivity: whether its point is seen (each point tested
/// once, the triangles around the pieces on both its sides left out); and
/// the changes inside the pieces, found between samples at most `spacing`
/// apart by bisection to 2^-12 of the piece.
void TestPieces(const LineSet& lines, const Eye& eye, double spacing, int threads,
  std::vector<std::uint8_t>& seenAt, Switches& switches)
{
  const Index entries = static_cast<Index>(lines.Connectivity.size());
  seenAt.assign(static_cast<std::size_t>(entries), 1);
  ParallelFor(entries, threads, [&](std::int64_t begin, std::int64_t end) {
    std::vector<Index> skip;
    for (std::int64_t k = begin; k < end; ++k)
    {
      const Index sides[2] = { k > 0 ? lines.EdgeFace[k - 1] : -1, lines.EdgeFace[k] }; // (-1 past a line's ends)
      if (sides[0] >= 0 || sides[1] >= 0)
      {
        seenAt[k] = eye.Sees(Point(lines.Points.data(), lines.Connectivity[k]), sides, skip);
      }
    }
  }, {}, 0, 256);
  std::mutex lock;
  ParallelFor(entries, threads, [&](std::int64_t begin, std::int64_t end) {
    Switches mine;
    std::vector<Index> skip;
    for (std::int64_t k = begin; k < end; ++k)
    {
      const Index f = lines.EdgeFace[k];
      const Vec3 a = Point(lines.Points.data(), lines.Connectivity[k]);
      const Vec3 b = Point(lines.Points.data(), lines.Connectivity[f >= 0 ? k + 1 : k]);
      const int samples = static_cast<int>(std::clamp(std::ceil((b - a).norm() / spacing), 1.0, 1e4));
      if (f < 0 || (samples == 1 && seenAt[k] == seenAt[k + 1]))
      {
        continue; // a line's last point, or a piece seen (hidden) at both ends
      }
      const Index sides[2] = { f, -1 };
      bool before = seenAt[k] != 0;
      for (int j = 1; j <= samples; ++j)
      {
        double lo = static_cast<double>(j - 1) / samples, hi = static_cast<double>(j) / samples;
        const bool after = j == samples ? seenAt[k + 1] != 0 : eye.Sees(a + hi * (b - a), sides, skip);
        if (after == before)
        {
          continue;
        }
        for (int halving = 0; halving < 12; ++halving)
        {
          const double mid = 0.5 * (lo + hi);
          (eye.Sees(a + mid * (b - a), sides, skip) == before ? lo : hi) = mid;
        }
        mine.emplace_back(static_cast<Index>(k), 0.5 * (lo + hi));
        before = after;
      }
    }
    std::lock_guard<std::mutex> guard(lock);
    switches.insert(switches.end(), mine.begin(), mine.end());
  }, {}, 0, 1024);
  std::sort(switches.begin(), switches.end());
}

/// A point of a part being built: position, normal, strength, and the face
/// of the piece from it to the next point.
struct PartPoint
{
  double Values[7];
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
  p.Face = face;
  return p;
}

/// The point at parameter t between a and b (the normal renormalized).
PartPoint Between(const PartPoint& a, const PartPoint& b, double t)
{
  PartPoint p;
  for (int k = 0; k < 7; ++k)
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

LineSet SplitByVisibility(const LineSet& lines, const LineDrawingGeometry& geometry, const LineView& view,
  const VisibilityOptions& options)
{
  LineSet out;
  if (lines.EdgeFace.size() != lines.Connectivity.size())
  {
    out = lines; // (no faces: nothing to test)
    out.Hidden.assign(lines.Type.size(), 0);
    return out;
  }
  const Eye eye(geometry, view);
  std::vector<std::uint8_t> seenAt;
  Switches switches;
  TestPieces(lines, eye, std::max(geometry.AutomaticFeatureSize(), 1e-300), options.NumberOfThreads, seenAt,
    switches);
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
