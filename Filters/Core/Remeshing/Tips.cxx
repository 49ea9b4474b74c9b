#include "Remeshing/Tips.h"

#include "Mesh/Geometry.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

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

/// The vertices to pin: interior vertices with an angle defect above
/// `threshold` (0: none), or `pinned` (per vertex; may be null).
std::vector<Index> TipVertices(
  const MeshTopology& topology, const double* points, double threshold, const std::uint8_t* pinned)
{
  std::vector<Index> tips;
  for (Index v = 0; (threshold > 0.0 || pinned) && v < topology.NumberOfVertices(); ++v)
  {
    if (topology.IsInterior(v) && topology.Valence(v) > 0 &&
      ((pinned && pinned[v]) || (threshold > 0.0 && AngleDefect(topology, points, v) > threshold)))
    {
      tips.push_back(v);
    }
  }
  return tips;
}

/// Tip vertex v on a chart boundary: the sample of its path nearest to it
/// (not a corner; a corner at v is there already) moves onto it, as a Tip
/// that the optimisation leaves (a seam that runs up a needle and down
/// again would otherwise leave its tip between two samples).
void PinOnPath(const MeshTopology& topology, const double* points, Index v, SurfaceSamples& out)
{
  for (SamplePath& path : out.Paths)
  {
    for (std::size_t i = 0; i < path.Vertices.size(); ++i)
    {
      if (path.Vertices[i] != v)
      {
        continue;
      }
      std::size_t nearest = 0;
      double best = HUGE_VAL;
      for (std::size_t k = 0; k < path.Samples.size(); ++k)
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
      }
    }
  }
}

} // namespace

/// Every tip vertex (TipVertices) takes the nearest sample, exactly at the
/// vertex, as a Tip (SamplingOptions::TipAngleDefect, PinnedVertices): an
/// interior sample of its chart where all its triangles are in one, else,
/// at a cone point, a sample of its chart boundary's path (PinOnPath).
void PinTips(const MeshTopology& topology, const double* points, const AtlasResult& atlas, double threshold,
  const std::uint8_t* pinned, SurfaceSamples& out)
{
  const std::vector<Index> tips = TipVertices(topology, points, threshold, pinned);
  std::vector<std::vector<std::size_t>> interior(tips.empty() ? 0 : atlas.Charts.size()); // per chart
  for (std::size_t s = 0; s < out.Kind.size() && !interior.empty(); ++s)
  {
    if (out.Kind[s] == SampleKind::Interior)
    {
      interior[out.Chart[s]].push_back(s);
    }
  }
  for (const Index v : tips)
  {
    const Index corner = *topology.CornersBegin(v);
    const int chart = atlas.ChartOfTriangle[corner / 3];
    if (!std::all_of(topology.CornersBegin(v), topology.CornersEnd(v),
          [&](Index c) { return atlas.ChartOfTriangle[c / 3] == chart; }))
    {
      if (threshold > 0.0 && AngleDefect(topology, points, v) > threshold)
      {
        PinOnPath(topology, points, v, out); // (a far vertex the error-driven mode pins: a path sample is near)
      }
      continue;
    }
    const Vec3 x = Point(points, v);
    std::size_t nearest = out.Kind.size();
    double best = HUGE_VAL;
    for (std::size_t s : interior[chart])
    {
      const double d = (Point(out.Positions.data(), static_cast<Index>(s)) - x).squaredNorm();
      if (out.Kind[s] == SampleKind::Interior && d < best)
      {
        best = d;
        nearest = s;
      }
    }
    if (nearest == out.Kind.size())
    {
      continue; // no interior sample left in the chart
    }
    const double w[3] = { corner % 3 == 0 ? 1.0 : 0.0, corner % 3 == 1 ? 1.0 : 0.0, corner % 3 == 2 ? 1.0 : 0.0 };
    out.Triangle[nearest] = corner / 3;
    std::copy(w, w + 3, &out.Barycentric[3 * nearest]);
    std::copy(x.data(), x.data() + 3, &out.Positions[3 * nearest]);
    out.Kind[nearest] = SampleKind::Tip;
  }
}

} // namespace beltrami
