#include "Remeshing/SqueezedParts.h"

#include "Mesh/Geometry.h"
#include "Remeshing/SurfaceSampling.h"
#include "Support/DisjointSets.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>

namespace beltrami
{

namespace
{

/// The importance at barycentric weights w of `triangle` (1 without one).
double ImportanceAt(const MeshTopology& topology, const double* importance, Index triangle, const double* w)
{
  double value = 0.0;
  for (int k = 0; importance && k < 3; ++k)
  {
    value += w[k] * std::max(0.0, importance[topology.CornerVertex(3 * triangle + k)]);
  }
  return importance ? value : 1.0;
}

/// The area of triangle k of `chart`'s map.
double MapArea(const AtlasChart& chart, std::size_t k)
{
  const double* a = &chart.UV[2 * chart.Corners[3 * k]];
  const double* b = &chart.UV[2 * chart.Corners[3 * k + 1]];
  const double* c = &chart.UV[2 * chart.Corners[3 * k + 2]];
  return 0.5 * std::abs((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]));
}

/// A point where a sample may go: its triangle, weights, position and the
/// density's spacing there, and its distance (in spacings) to the nearest
/// sample or border point.
struct Candidate
{
  Index Triangle;
  double W[3];
  Vec3 X;
  double Spacing;
  double Distance;
};

/// Every candidate's distance reduced to at most its distance to x.
void Approach(std::vector<Candidate>& candidates, const Vec3& x)
{
  for (Candidate& k : candidates)
  {
    k.Distance = std::min(k.Distance, (k.X - x).norm() / k.Spacing);
  }
}

/// Whether the edge of `triangle` opposite its corner k borders the part
/// (`inPart` per surface triangle): a triangle across it is outside the
/// part, or none is (the surface's boundary).
bool BorderEdge(const MeshTopology& topology, const std::vector<std::uint8_t>& inPart, Index triangle, int k)
{
  const MeshTopology::EdgeTable& edges = topology.Edges();
  const std::int64_t e =
    edges.Find(topology.CornerVertex(3 * triangle + (k + 1) % 3), topology.CornerVertex(3 * triangle + (k + 2) % 3));
  for (int side = 0; side < 2; ++side)
  {
    const Index corner = edges.OppositeCorners[2 * e + side];
    if (corner < 0 || !inPart[corner / 3])
    {
      return true;
    }
  }
  return false;
}

/// The candidates of one part (its triangles; `inPart` flags them): a grid
/// of barycentric weights on each triangle, about three a spacing; those on
/// the part's border (where the halftone's and the chart boundaries'
/// samples are) at distance 0, every other one at its distance to them.
std::vector<Candidate> PartCandidates(const MeshTopology& topology, const double* points, const double* importance,
  double density, const std::vector<Index>& triangles, const std::vector<std::uint8_t>& inPart)
{
  std::vector<Candidate> out;
  std::vector<Vec3> border;
  const double centre[3] = { 1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0 };
  for (Index t : triangles)
  {
    const Vec3 a = Point(points, topology.CornerVertex(3 * t)), b = Point(points, topology.CornerVertex(3 * t + 1)),
               c = Point(points, topology.CornerVertex(3 * t + 2));
    const double longest = std::max({ (b - a).norm(), (c - b).norm(), (a - c).norm() });
    const double spacing = SpacingOf(density, ImportanceAt(topology, importance, t, centre));
    const int m = std::clamp(static_cast<int>(std::ceil(3.0 * longest / spacing)), 1, 16);
    const bool onBorder[3] = { BorderEdge(topology, inPart, t, 0), BorderEdge(topology, inPart, t, 1),
      BorderEdge(topology, inPart, t, 2) };
    for (int i = 0; i <= m; ++i)
    {
      for (int j = 0; i + j <= m; ++j)
      {
        Candidate k{ t, { double(i) / m, double(j) / m, double(m - i - j) / m }, Vec3::Zero(), 0.0, HUGE_VAL };
        k.X = k.W[0] * a + k.W[1] * b + k.W[2] * c;
        k.Spacing = SpacingOf(density, ImportanceAt(topology, importance, t, k.W));
        if ((i == 0 && onBorder[0]) || (j == 0 && onBorder[1]) || (i + j == m && onBorder[2]))
        {
          border.push_back(k.X);
        }
        out.push_back(k);
      }
    }
  }
  for (const Vec3& x : border)
  {
    Approach(out, x);
  }
  return out;
}

/// Up to `count` samples on one part (its triangles; `inPart` flags them),
/// fewer where no point is left half a spacing from the others and the
/// border.
void SamplePart(const MeshTopology& topology, const double* points, const double* importance, double density,
  const std::vector<Index>& triangles, const std::vector<std::uint8_t>& inPart, std::int64_t count, int chart,
  SqueezedSamples& out)
{
  std::vector<Candidate> candidates = PartCandidates(topology, points, importance, density, triangles, inPart);
  for (std::int64_t s = 0; s < count && !candidates.empty(); ++s)
  {
    const Candidate& best = *std::max_element(candidates.begin(), candidates.end(),
      [](const Candidate& a, const Candidate& b) { return a.Distance < b.Distance; });
    if (best.Distance < 0.5)
    {
      break; // the part is full (a strip along its border, its count rounded up)
    }
    out.Triangle.push_back(best.Triangle);
    out.Barycentric.insert(out.Barycentric.end(), best.W, best.W + 3);
    out.Chart.push_back(chart);
    const Vec3 x = best.X;
    Approach(candidates, x);
  }
}

/// Per surface triangle, the samples it expects at `density` (0 where it is
/// not squeezed): more than its texels hold at `resolution`, and squeezed
/// fourfold against the atlas's mean area scale (by the map, not by too
/// coarse a control map, which SampleSurface reports).
std::vector<double> SqueezedExpectations(const MeshTopology& topology, const double* points,
  const AtlasChart& packed, const double* importance, double density, int resolution)
{
  double mapArea = 0.0;
  for (std::size_t k = 0; k < packed.Triangles.size(); ++k)
  {
    mapArea += MapArea(packed, k);
  }
  const double meanScale = mapArea > 0.0 ? packed.Area3D / mapArea : 0.0;
  const double texelsPerUnit = static_cast<double>(resolution) * resolution;
  const double centre[3] = { 1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0 };
  std::vector<double> expected(static_cast<std::size_t>(topology.NumberOfTriangles()), 0.0);
  for (std::size_t k = 0; k < packed.Triangles.size(); ++k)
  {
    const Index t = packed.Triangles[k];
    const Vec3 p = Point(points, topology.CornerVertex(3 * t));
    const double area = 0.5 *
      (Point(points, topology.CornerVertex(3 * t + 1)) - p).cross(Point(points, topology.CornerVertex(3 * t + 2)) - p).norm();
    const double e = density * area * ImportanceAt(topology, importance, t, centre);
    expected[t] = e > MapArea(packed, k) * texelsPerUnit && area > 4.0 * meanScale * MapArea(packed, k) ? e : 0.0;
  }
  return expected;
}

/// The parts: the squeezed triangles (expected > 0) of one chart that share
/// a vertex, each as its triangles.
std::vector<std::vector<Index>> SqueezedPartsOf(
  const MeshTopology& topology, const AtlasResult& atlas, const std::vector<double>& expected)
{
  std::vector<Index> parent(expected.size());
  std::iota(parent.begin(), parent.end(), Index(0));
  for (Index v = 0; v < topology.NumberOfVertices(); ++v)
  {
    Index first = -1;
    for (const Index* c = topology.CornersBegin(v); c != topology.CornersEnd(v); ++c)
    {
      const Index t = *c / 3;
      if (expected[t] > 0.0 && first < 0)
      {
        first = t;
      }
      else if (expected[t] > 0.0 && atlas.ChartOfTriangle[t] == atlas.ChartOfTriangle[first])
      {
        parent[FindRoot(parent, t)] = FindRoot(parent, first);
      }
    }
  }
  std::map<Index, std::vector<Index>> parts;
  for (Index t = 0; t < static_cast<Index>(expected.size()); ++t)
  {
    if (expected[t] > 0.0)
    {
      parts[FindRoot(parent, t)].push_back(t);
    }
  }
  std::vector<std::vector<Index>> out;
  for (auto& [root, part] : parts)
  {
    out.push_back(std::move(part));
  }
  return out;
}

} // namespace

SqueezedSamples SampleSqueezedParts(const MeshTopology& topology, const double* points, const AtlasResult& atlas,
  const AtlasChart& packed, const double* importance, double density, int resolution, std::int64_t most)
{
  SqueezedSamples out;
  out.PackedSqueezed.assign(packed.Triangles.size(), 0);
  const std::vector<double> expected =
    SqueezedExpectations(topology, points, packed, importance, density, resolution);
  if (std::none_of(expected.begin(), expected.end(), [](double e) { return e > 0.0; }))
  {
    return out;
  }
  std::vector<std::uint8_t> sampled(expected.size(), 0), inPart(expected.size(), 0);
  std::int64_t left = most;
  for (const std::vector<Index>& part : SqueezedPartsOf(topology, atlas, expected))
  {
    double sum = 0.0;
    for (Index t : part)
    {
      sum += expected[t];
      inPart[t] = 1;
    }
    const std::int64_t count = std::min(left, static_cast<std::int64_t>(std::floor(sum + 0.5)));
    const std::size_t before = out.Chart.size();
    if (count > 0)
    {
      SamplePart(topology, points, importance, density, part, inPart, count, atlas.ChartOfTriangle[part.front()], out);
    }
    for (Index t : part)
    {
      sampled[t] = out.Chart.size() > before; // else its texels stay the halftone's
      inPart[t] = 0;
    }
    left -= static_cast<std::int64_t>(out.Chart.size() - before);
  }
  for (std::size_t k = 0; k < packed.Triangles.size(); ++k)
  {
    out.PackedSqueezed[k] = sampled[packed.Triangles[k]];
  }
  return out;
}

} // namespace beltrami
