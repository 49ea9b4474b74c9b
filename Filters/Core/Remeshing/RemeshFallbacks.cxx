// The remesher's fallbacks and advice (Remeshing/SurfaceRemeshing.h): the
// smoothed copy a noisy scan is laid out on, when its remesh is kept, and the
// counts a failed or far remesh names.
#include "Remeshing/SurfaceRemeshing.h"

#include "Flows/Fairing.h"

#include <algorithm>
#include <cmath>

namespace beltrami
{

double FoldedEdgeShare(const MeshTopology& topology, const double* points)
{
  const MeshTopology::EdgeTable& edges = topology.Edges();
  const auto normal = [&](Index corner) {
    const Index t = corner / 3;
    const Vec3 a = Point(points, topology.CornerVertex(3 * t));
    return Vec3((Point(points, topology.CornerVertex(3 * t + 1)) - a).cross(Point(points, topology.CornerVertex(3 * t + 2)) - a));
  };
  std::int64_t interior = 0, folded = 0;
  for (std::int64_t e = 0; e < edges.NumberOfEdges(); ++e)
  {
    const Index c0 = edges.OppositeCorners[2 * e], c1 = edges.OppositeCorners[2 * e + 1];
    if (c0 >= 0 && c1 >= 0 && edges.FaceCount[e] == 2)
    {
      // (Beyond round-off: the faces of a box meet at 90 degrees exactly.)
      ++interior;
      const Vec3 n0 = normal(c0), n1 = normal(c1);
      folded += n0.dot(n1) < -1e-9 * n0.norm() * n1.norm() ? 1 : 0;
    }
  }
  return interior > 0 ? static_cast<double>(folded) / static_cast<double>(interior) : 0.0;
}

bool PoorRemesh(const RemeshResult& remesh, int numThreads)
{
  if (!remesh.Error.empty() || remesh.DeviationFromInput * remesh.Diagonal > remesh.Spacing)
  {
    return true;
  }
  const TriangleQuality q = RemeshQuality(remesh, numThreads);
  return q.MinimumAngle < 15.0 || q.FractionBelow30 > 0.005;
}

bool KeepCopysRemesh(const RemeshResult& copy, const RemeshResult& own, int numThreads)
{
  return copy.Error.empty() && AsGoodTriangles(copy, own, numThreads) &&
    WorstDeviation(copy) <= CopyDeviationAllowance * WorstDeviation(own);
}

std::vector<double> DenoisedLayout(const MeshTopology& topology, const double* points, double step, int numThreads)
{
  std::vector<double> layout(points, points + 3 * static_cast<std::size_t>(topology.NumberOfVertices()));
  FairingOptions umbrella;
  umbrella.Operator = FairingOperator::Umbrella;
  umbrella.TimeStep = step;
  umbrella.Invariant = FairingInvariant::None;
  umbrella.Boundary = FairingBoundary::SmoothCurve;
  umbrella.NumberOfThreads = numThreads;
  const FairingReport report = FairSurface(topology, layout.data(), umbrella);
  if (!report.Error.empty() || !report.Completed || std::equal(layout.begin(), layout.end(), points) ||
    !std::all_of(layout.begin(), layout.end(), [](double x) { return std::isfinite(x); }))
  {
    layout.clear();
  }
  return layout;
}

namespace
{

/// Whether a remesh succeeded with every input point within its spacing of
/// it and it within its spacing of the input: a run at its count, which
/// keeps a remesh with far vertices pinned (RemeshOptions::FarPinSpacings)
/// only where that is closer, keeps the input too.
bool KeepsTheInput(const RemeshResult& r)
{
  return r.Error.empty() && WorstDeviation(r) * r.Diagonal <= r.Spacing;
}

/// Two significant digits, rounded up.
std::int64_t RoundedUp(double count)
{
  const double unit = std::pow(10.0, std::floor(std::log10(count)) - 1.0);
  return static_cast<std::int64_t>(std::ceil(count / unit) * unit);
}

} // namespace

CountAdvice AdviseCounts(const MeshTopology& topology, const double* points, const AtlasResult& atlas,
  const double* importance, const RemeshOptions& options, const RemeshResult& result)
{
  CountAdvice out;
  RemeshOptions larger = options;
  larger.FarPinSpacings = 0.0; // (one remesh a try: KeepsTheInput)
  const std::int64_t most = MostVerticesPerInputVertex * static_cast<std::int64_t>(topology.NumberOfVertices());
  const auto tryCount = [&](std::int64_t count) {
    larger.NumberOfVertices = count;
    return RemeshSurface(topology, points, atlas, importance, larger);
  };
  std::int64_t count = options.NumberOfVertices;
  if (!result.Error.empty())
  {
    std::int64_t needed = result.Samples.NeededSamples;
    for (int k = 0; k < 4 && out.Remeshes == 0; ++k)
    {
      // A tenth above what the boundaries and charts need, a quarter more
      // than the count tried at least.
      count = RoundedUp(std::max(1.1 * static_cast<double>(needed), 1.25 * static_cast<double>(count)));
      if (count > most)
      {
        return out;
      }
      const RemeshResult r = tryCount(count);
      out.Remeshes = r.Error.empty() ? count : 0;
      out.Keeps = KeepsTheInput(r) ? count : 0;
      needed = r.Samples.NeededSamples;
    }
    if (out.Remeshes == 0 || out.Keeps > 0)
    {
      return out;
    }
  }
  // 2, 4 and 8 times the count, above the one found to remesh.
  for (std::int64_t factor = 2; factor <= 8 && factor * options.NumberOfVertices <= most; factor *= 2)
  {
    if (factor * options.NumberOfVertices > out.Remeshes && KeepsTheInput(tryCount(factor * options.NumberOfVertices)))
    {
      out.Keeps = factor * options.NumberOfVertices;
      break;
    }
  }
  return out;
}

} // namespace beltrami
