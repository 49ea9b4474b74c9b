#include "Remeshing/Tips.h"

#include "Mesh/Geometry.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <functional>
#include <iterator>
#include <unordered_map>

namespace beltrami
{

/// The angle defect of interior vertex v: 2 pi minus its corners' angles.
double AngleDefect(const MeshTopology& topology, const double* points, Index v)
{
  double sum = 0.0;
  const Index* pairs = topology.RingPairsBegin(v);
  for (Index k = 0; k < topology.Valence(v); ++k)
  {
    const Vec3 p = Point(points, v), a = Point(points, pairs[2 * k]) - p, b = Point(points, pairs[2 * k + 1]) - p;
    sum += std::atan2(a.cross(b).norm(), a.dot(b));
  }
  return 2.0 * M_PI - sum;
}

namespace
{

/// How far interior vertex v stands out of its 1-ring: its distance to the
/// plane through the ring's centroid normal to the ring's vector area.
double HeightOverRing(const MeshTopology& topology, const double* points, Index v)
{
  const Index* pairs = topology.RingPairsBegin(v);
  Vec3 centroid = Vec3::Zero(), normal = Vec3::Zero();
  for (Index k = 0; k < topology.Valence(v); ++k)
  {
    centroid += Point(points, pairs[2 * k]);
  }
  centroid /= static_cast<double>(std::max<Index>(1, topology.Valence(v)));
  for (Index k = 0; k < topology.Valence(v); ++k)
  {
    normal += (Point(points, pairs[2 * k]) - centroid).cross(Point(points, pairs[2 * k + 1]) - centroid);
  }
  const double length = normal.norm();
  return length > 0.0 ? std::abs((Point(points, v) - centroid).dot(normal)) / length : 0.0;
}

/// Of `candidates` (strongest first), those a spacing apart from every
/// stronger one kept (`spacing` per vertex; a grid of the largest spacing's
/// cells finds the near ones).
template <typename Spacing>
std::vector<Index> KeepApart(
  const double* points, const std::vector<std::pair<double, Index>>& candidates, const Spacing& spacing)
{
  double cell = 0.0;
  for (const auto& [strength, v] : candidates)
  {
    cell = std::max(cell, spacing(v));
  }
  const auto key = [&](const Vec3& x, int d) {
    std::uint64_t k = 0;
    for (int axis = 0; axis < 3; ++axis, d /= 3)
    {
      const double index = std::clamp(std::floor(x[axis] / cell), -1e15, 1e15); // (any coordinate: a defined key)
      k = k << 21 | (static_cast<std::uint64_t>(static_cast<std::int64_t>(index) + d % 3 - 1) & 0x1fffff);
    }
    return k;
  };
  std::unordered_map<std::uint64_t, std::vector<Index>> kept; // by cell (key offset 13: the cell itself)
  std::vector<Index> out;
  for (const auto& [strength, v] : candidates)
  {
    const Vec3 x = Point(points, v);
    bool apart = true;
    for (int d = 0; d < 27 && apart; ++d)
    {
      const auto found = kept.find(key(x, d));
      for (std::size_t k = 0; found != kept.end() && k < found->second.size() && apart; ++k)
      {
        const Index w = found->second[k];
        apart = (x - Point(points, w)).norm() >= std::max(spacing(v), spacing(w));
      }
    }
    if (apart)
    {
      out.push_back(v);
      kept[key(x, 13)].push_back(v);
    }
  }
  return out;
}

/// The spikes of the input at the density's spacing: interior vertices that
/// stand out of their 1-ring by more than SpikeHeight spacings, the most of
/// their 1-ring; of those closer than a spacing, the one that stands out
/// most.  (A remesh passes near the ring, below the spike by its height:
/// the single far vertices of scans and terrains.)
constexpr double SpikeHeight = 0.25;
std::vector<Index> Spikes(const MeshTopology& topology, const double* points, const double* importance, double density)
{
  const Index n = topology.NumberOfVertices();
  const auto spacing = [&](Index v) { return SpacingAt(importance, density, v); };
  std::vector<double> height(n, 0.0);
  for (Index v = 0; v < n; ++v)
  {
    height[v] = topology.IsInterior(v) && topology.Valence(v) > 2 ? HeightOverRing(topology, points, v) : 0.0;
  }
  std::vector<std::pair<double, Index>> candidates; // (height in spacings, vertex)
  const MeshTopology::VertexGraph& graph = topology.Graph();
  for (Index v = 0; v < n; ++v)
  {
    bool highest = height[v] > SpikeHeight * spacing(v);
    for (std::int64_t k = graph.NeighborOffsets[v]; highest && k < graph.NeighborOffsets[v + 1]; ++k)
    {
      const Index w = graph.Neighbors[k];
      highest = height[w] < height[v] || (height[w] == height[v] && w > v);
    }
    if (highest)
    {
      candidates.emplace_back(height[v] / spacing(v), v);
    }
  }
  std::sort(candidates.begin(), candidates.end(), std::greater<>());
  return KeepApart(points, candidates, spacing);
}

/// The vertices to pin: the Spikes (with `density` > 0) and interior
/// vertices with an angle defect above `threshold` (0: none), sharpest
/// first, each a spacing from every spike and sharper one kept (two pinned
/// samples closer than the spacing would leave slivers beside their short
/// edge), and every `pinned` one (per vertex; may be null) a twentieth of
/// a spacing from those and each other (with `density` > 0: an
/// isosurface's cluster of vertices 0.005 apart, where its level passes a
/// grid point, gave two pinned samples one place in their chart's map; a
/// quarter of a spacing changed the error-driven counts on the corpus by
/// -50% to +12%, a tenth by up to +61%, this one the comb's by 4%).
std::vector<Index> TipVertices(const MeshTopology& topology, const double* points, double threshold,
  const double* defects, const std::uint8_t* pinned, const double* importance, double density)
{
  std::vector<Index> spikes = density > 0.0 ? Spikes(topology, points, importance, density) : std::vector<Index>();
  std::vector<std::uint8_t> taken(static_cast<std::size_t>(topology.NumberOfVertices()), 0);
  std::vector<std::pair<double, Index>> candidates; // (strength, vertex): the spikes before every cone
  for (Index v : spikes)
  {
    taken[v] = 1;
    candidates.emplace_back(HUGE_VAL, v);
  }
  std::vector<Index> forced;
  for (Index v = 0; (threshold > 0.0 || pinned) && v < topology.NumberOfVertices(); ++v)
  {
    if (taken[v] || !topology.IsInterior(v) || topology.Valence(v) == 0)
    {
      continue;
    }
    if (pinned && pinned[v])
    {
      forced.push_back(v);
    }
    else if (threshold > 0.0)
    {
      if (defects[v] > threshold)
      {
        candidates.emplace_back(defects[v], v);
      }
    }
  }
  std::stable_sort(candidates.begin(), candidates.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  std::vector<Index> tips;
  if (density <= 0.0) // (no spacing: every cone, every pinned vertex)
  {
    std::transform(candidates.begin(), candidates.end(), std::back_inserter(tips), [](const auto& c) { return c.second; });
    tips.insert(tips.end(), forced.begin(), forced.end());
    return tips;
  }
  tips = KeepApart(points, candidates, [&](Index v) { return SpacingAt(importance, density, v); });
  std::vector<std::pair<double, Index>> all; // the kept tips first, then the pinned vertices
  for (const Index v : tips)
  {
    all.emplace_back(HUGE_VAL, v);
  }
  for (const Index v : forced)
  {
    all.emplace_back(0.0, v);
  }
  return KeepApart(points, all, [&](Index v) { return 0.05 * SpacingAt(importance, density, v); });
}

/// Where each of `vertices` lies on the samples' paths: (path, position
/// along it) pairs per vertex, in the paths' order (one pass over them all,
/// where a pass per tip took 6.6 s on a noisy scan's 28,000 charts).
std::unordered_map<Index, std::vector<std::pair<std::size_t, std::size_t>>> PathPlaces(
  const std::vector<Index>& vertices, const SurfaceSamples& out)
{
  std::unordered_map<Index, std::vector<std::pair<std::size_t, std::size_t>>> places;
  for (const Index v : vertices)
  {
    places[v];
  }
  for (std::size_t p = 0; p < out.Paths.size() && !places.empty(); ++p)
  {
    const std::vector<Index>& along = out.Paths[p].Vertices;
    for (std::size_t i = 0; i < along.size(); ++i)
    {
      const auto at = places.find(along[i]);
      if (at != places.end())
      {
        at->second.push_back({ p, i });
      }
    }
  }
  return places;
}

/// Tip vertex v on a chart boundary (at `places` of the paths: PathPlaces):
/// the nearer of its path's samples on either side of it (not a corner; a
/// corner at v is there already) moves onto it, as a Tip that the
/// optimisation leaves (a seam that runs up a needle and down again would
/// otherwise leave its tip between two samples).
bool PinOnPath(const MeshTopology& topology, const double* points, Index v,
  const std::vector<std::pair<std::size_t, std::size_t>>& places, SurfaceSamples& out)
{
  bool moved = false;
  for (const auto& [p, i] : places)
  {
    SamplePath& path = out.Paths[p];
    // Of the samples on either side of the vertex (the order along the
    // path is kept: a farther one would cross them), the nearer movable one.
    const std::size_t above = static_cast<std::size_t>(
      std::upper_bound(path.SampleArc.begin(), path.SampleArc.end(), path.Arc[i]) - path.SampleArc.begin());
    std::size_t nearest = 0;
    double best = HUGE_VAL;
    for (std::size_t k = above > 0 ? above - 1 : 0; k <= above && k < path.Samples.size(); ++k)
    {
      const double d = std::abs(path.SampleArc[k] - path.Arc[i]);
      if (d < best && (out.Kind[path.Samples[k]] == SampleKind::Boundary || d == 0.0))
      {
        best = d;
        nearest = k;
      }
    }
    const Index s = path.Samples[nearest];
    if (best < HUGE_VAL && out.Kind[s] != SampleKind::Tip)
    {
      out.Triangle[s] = LocateOnPath(topology, path, path.Arc[i], &out.Barycentric[3 * s]);
      const Vec3 x = Point(points, v);
      std::copy(x.data(), x.data() + 3, &out.Positions[3 * s]);
      path.SampleArc[nearest] = path.Arc[i];
      out.Kind[s] = SampleKind::Tip;
      moved = true;
    }
  }
  return moved;
}

/// The corner before corner a around a vertex (pairs: RingPairsBegin, a
/// consistently oriented fan): the one whose next vertex is a's previous;
/// `valence` if none.
Index FanPredecessor(const Index* pairs, Index valence, Index a)
{
  Index p = 0;
  while (p < valence && pairs[2 * p] != pairs[2 * a + 1])
  {
    ++p;
  }
  return p;
}

/// A fan narrower than this (radians) at a tip: a strip less than a spacing
/// wide a spacing from the tip (2 sin(pi/6) = 1).  Needles (corners' angles
/// summing to less than twice this: a cone sharper than 39 degrees) have
/// their narrow fans sampled (PinFans).
constexpr double NarrowFan = M_PI / 3.0;

/// The point a `distance` from interior vertex v into the fan of its
/// corners in `chart` (pairs, corner positions around v), halfway across
/// the fan's angle (on the fan's triangle there, at most half way to its far
/// edge): its triangle and barycentric weights.  -1: no corner in the chart,
/// or a fan of NarrowFan or more.
Index MiddleOfFan(const MeshTopology& topology, const double* points, const AtlasResult& atlas, Index v, int chart,
  double distance, Vec3& x, double w[3])
{
  const Index valence = topology.Valence(v);
  const Index* corners = topology.CornersBegin(v);
  const Index* pairs = topology.RingPairsBegin(v);
  const auto inChart = [&](Index k) { return k < valence && atlas.ChartOfTriangle[corners[k] / 3] == chart; };
  Index start = 0; // a corner of the chart whose predecessor around v is not
  while (start < valence && !(inChart(start) && !inChart(FanPredecessor(pairs, valence, start))))
  {
    ++start;
  }
  if (start == valence)
  {
    return -1; // (the whole fan: v is no chart boundary vertex)
  }
  const Vec3 p = Point(points, v);
  const auto angle = [&](Index k) {
    const Vec3 a = Point(points, pairs[2 * k + 1]) - p, b = Point(points, pairs[2 * k]) - p;
    return std::atan2(a.cross(b).norm(), a.dot(b));
  };
  double total = 0.0;
  for (Index k = start, steps = 0; inChart(k) && steps < valence;
       k = MeshTopology::CornerAcross(pairs, valence, k), ++steps)
  {
    total += angle(k);
  }
  if (!(total > 0.0 && total < NarrowFan))
  {
    return -1;
  }
  Index k = start;
  double before = 0.0;
  while (before + angle(k) < 0.5 * total)
  {
    before += angle(k);
    k = MeshTopology::CornerAcross(pairs, valence, k);
  }
  // In triangle (v, previous, next): from the edge to `previous`, turned towards `next`.
  const Vec3 a = Point(points, pairs[2 * k + 1]) - p, b = Point(points, pairs[2 * k]) - p;
  const Vec3 u = a.normalized(), side = (b - b.dot(u) * u).normalized();
  const double phi = 0.5 * total - before;
  const Vec3 direction = std::cos(phi) * u + std::sin(phi) * side;
  // The ray p + r direction meets the far edge a..b at r = |a x b| / |direction x (b - a)|.
  const double area = a.cross(b).norm();
  if (!(area > 0.0))
  {
    return -1;
  }
  const double far = area / std::max(direction.cross(b - a).norm(), 1e-300);
  x = p + std::min(distance, 0.5 * far) * direction;
  // Barycentric weights of x in (v, previous, next), in the triangle's corner order.
  const Vec3 d = x - p;
  const double wa = d.cross(b).norm() / area, wb = a.cross(d).norm() / area;
  const Index corner = corners[k], t = corner / 3;
  w[corner % 3] = 1.0 - wa - wb;
  w[(corner + 2) % 3] = wa; // previous vertex
  w[(corner + 1) % 3] = wb; // next vertex
  return t;
}

/// Of `samples` (one chart's interior samples), one of the closest pair of
/// those still Interior and not `taken` (per sample): where the chart can
/// best spare one (the nearest one to a needle's tip would leave a hole in
/// the needle).  out.Kind.size() where fewer than two are left.
std::size_t MostCrowded(
  const std::vector<std::size_t>& samples, const std::vector<std::uint8_t>& taken, const SurfaceSamples& out)
{
  std::vector<std::size_t> free;
  Eigen::AlignedBox3d box;
  for (std::size_t s : samples)
  {
    if (out.Kind[s] == SampleKind::Interior && !taken[s])
    {
      free.push_back(s);
      box.extend(Point(out.Positions.data(), static_cast<Index>(s)));
    }
  }
  if (free.size() < 2)
  {
    return out.Kind.size();
  }
  int axis = 0; // the box's longest: a sweep along it meets few samples
  box.sizes().maxCoeff(&axis);
  const auto at = [&](std::size_t s) { return Point(out.Positions.data(), static_cast<Index>(s)); };
  std::sort(free.begin(), free.end(), [&](std::size_t a, std::size_t b) { return at(a)[axis] < at(b)[axis]; });
  std::size_t best = free[0];
  double closest = HUGE_VAL;
  for (std::size_t i = 0; i < free.size(); ++i)
  {
    for (std::size_t j = i + 1; j < free.size(); ++j)
    {
      const double gap = at(free[j])[axis] - at(free[i])[axis];
      if (gap * gap >= closest)
      {
        break;
      }
      const double d = (at(free[j]) - at(free[i])).squaredNorm();
      if (d < closest)
      {
        closest = d;
        best = free[i];
      }
    }
  }
  return best;
}

/// Tip vertex v on a chart boundary: each chart whose fan at v is narrow
/// (NarrowFan) and holds no interior sample within a spacing of v moves its
/// most crowded one (not `taken` before; then taken) to the middle of the
/// fan, a spacing from v (the seam that
/// runs up a needle and down again leaves a strip on either side too narrow
/// for a sample; without one the needle's remesh is a flat fin, its
/// triangles at the tip of angle 0).
void PinFans(const MeshTopology& topology, const double* points, const AtlasResult& atlas, Index v, double spacing,
  const std::vector<std::vector<std::size_t>>& interior, std::vector<std::uint8_t>& taken, SurfaceSamples& out)
{
  std::vector<int> charts;
  std::transform(topology.CornersBegin(v), topology.CornersEnd(v), std::back_inserter(charts),
    [&](Index c) { return atlas.ChartOfTriangle[c / 3]; });
  std::sort(charts.begin(), charts.end());
  charts.erase(std::unique(charts.begin(), charts.end()), charts.end());
  const Vec3 p = Point(points, v);
  for (const int chart : charts)
  {
    const bool near = std::any_of(interior[chart].begin(), interior[chart].end(),
      [&](std::size_t s) { return (Point(out.Positions.data(), static_cast<Index>(s)) - p).norm() < spacing; });
    Vec3 x;
    double w[3];
    const Index t = near ? -1 : MiddleOfFan(topology, points, atlas, v, chart, spacing, x, w);
    if (t >= 0)
    {
      const std::size_t moved = MostCrowded(interior[chart], taken, out);
      if (moved < out.Kind.size())
      {
        MoveSample(moved, x, t, w, SampleKind::Interior, out);
        taken[moved] = 1;
      }
    }
  }
}

} // namespace

/// Every tip vertex (TipVertices) takes the nearest sample, exactly at the
/// vertex, as a Tip (SamplingOptions::TipAngleDefect, PinnedVertices): an
/// interior sample of its chart where all its triangles are in one, else,
/// at a cone point, a sample of its chart boundary's path (PinOnPath) and,
/// at a needle's tip, an interior sample of each narrow fan around it
/// (PinFans).
std::int64_t PinTips(const MeshTopology& topology, const double* points, const AtlasResult& atlas, double threshold,
  const double* defects, const std::uint8_t* pinned, const double* importance, double density, SurfaceSamples& out)
{
  std::int64_t onPaths = 0;
  const std::vector<Index> tips = TipVertices(topology, points, threshold, defects, pinned, importance, density);
  std::vector<std::vector<std::size_t>> interior(tips.empty() ? 0 : atlas.Charts.size()); // per chart
  std::vector<std::uint8_t> taken(tips.empty() ? 0 : out.Kind.size(), 0); // moved into a needle's fan
  for (std::size_t s = 0; s < out.Kind.size() && !interior.empty(); ++s)
  {
    if (out.Kind[s] == SampleKind::Interior)
    {
      interior[out.Chart[s]].push_back(s);
    }
  }
  const auto places = PathPlaces(tips, out);
  for (const Index v : tips)
  {
    const Index corner = *topology.CornersBegin(v);
    const int chart = atlas.ChartOfTriangle[corner / 3];
    if (!std::all_of(topology.CornersBegin(v), topology.CornersEnd(v),
          [&](Index c) { return atlas.ChartOfTriangle[c / 3] == chart; }))
    {
      const double defect = threshold > 0.0 ? defects[v] : 0.0;
      if (defect > threshold)
      {
        // (a far vertex the error-driven mode pins: a path sample is near)
        onPaths += PinOnPath(topology, points, v, places.at(v), out) ? 1 : 0;
        if (density > 0.0 && defect > 2.0 * (M_PI - NarrowFan))
        {
          PinFans(topology, points, atlas, v, SpacingAt(importance, density, v), interior, taken, out);
        }
      }
      continue;
    }
    const double w[3] = { corner % 3 == 0 ? 1.0 : 0.0, corner % 3 == 1 ? 1.0 : 0.0, corner % 3 == 2 ? 1.0 : 0.0 };
    const std::size_t nearest = NearestInterior(interior[chart], Point(points, v), out);
    if (nearest < out.Kind.size()) // (else no interior sample left in the chart)
    {
      MoveSample(nearest, Point(points, v), corner / 3, w, SampleKind::Tip, out);
    }
  }
  return onPaths;
}

} // namespace beltrami
