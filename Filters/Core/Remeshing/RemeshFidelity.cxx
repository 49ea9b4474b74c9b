// Beltrami core: a remesh's fidelity to its input (RemeshSurface): its
// topology and two-sided deviation checked (CheckFidelity), the fidelity
// rounds that move its vertices onto the input vertices and the points of
// creases it leaves far (CheckFidelityInRounds), and the error-driven remesh
// (RemeshToDeviation).
#include "Remeshing/RemeshFidelity.h"

#include "Mesh/Laplacian.h"
#include "Mesh/MeshMeasures.h"
#include "Remeshing/RemeshMetric.h"
#include "Solvers/SparseGraph.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <set>
#include <sstream>

namespace beltrami
{

namespace
{

/// "a -> b" where the remesh's count differs from the input's.
void CompareCount(const char* what, std::int64_t input, std::int64_t remesh, std::string& differences)
{
  if (input != remesh)
  {
    differences += (differences.empty() ? "" : ", ") + std::string(what) + " " + std::to_string(input) + " -> " +
      std::to_string(remesh);
  }
}

/// The vertex count whose equilateral triangles keep within `bound` of a
/// surface of largest principal curvatures `kappa` (per vertex, areas
/// `mass`): a triangle of spacing s has its centre about kappa s^2 / 6 from
/// the surface, and s^2 = 6 bound / kappa holds 2 / (sqrt(3) s^2) vertices a
/// unit area; with a margin of 1.3 for the remesh's uneven edges.
std::int64_t CountForDeviation(const LargeVector<double>& mass, const std::vector<double>& kappa, double bound)
{
  double needed = 0.0;
  for (std::size_t v = 0; v < kappa.size(); ++v)
  {
    const double k = std::isfinite(kappa[v]) ? kappa[v] : 0.0;
    needed += mass[v] * 1.3 * 2.0 * k / (std::sqrt(3.0) * 6.0 * bound);
  }
  return static_cast<std::int64_t>(std::ceil(needed));
}

/// `values` replaced by their largest over each vertex's `rings`-ring.
void DilateOverRings(const MeshTopology& topology, int rings, std::vector<double>& values)
{
  const MeshTopology::VertexGraph& graph = topology.Graph();
  std::vector<double> next(values.size());
  for (int r = 0; r < rings; ++r)
  {
    for (std::size_t v = 0; v < values.size(); ++v)
    {
      next[v] = values[v];
      for (std::int64_t k = graph.NeighborOffsets[v]; k < graph.NeighborOffsets[v + 1]; ++k)
      {
        next[v] = std::max(next[v], values[graph.Neighbors[k]]);
      }
    }
    values.swap(next);
  }
}

/// The error-driven mode's first weights where the importance is uniform:
/// 1, and where the largest principal curvature is more than twice its
/// mean over the surface, its ratio to twice the mean (the density that
/// keeps a smooth surface's sag even grows as the curvature), except on
/// the kept sharp edges and their 1-rings (the remesh follows them: their
/// curvature is no sag).  Over the corpus and the generated shapes at 0.2%
/// and 0.5% of the diagonal (46 surfaces, with the fidelity rounds), the
/// remeshes then took 0.81 and 0.84 times the vertices of those from
/// uniform weights in geometric mean; 7 and 10 took more, at most 1.32
/// times.  With weights of the curvature's ratio to its mean itself: 0.78
/// times in the mean, but a comb of thin fingers took 2.7 times.
std::vector<double> WeightsForDeviation(const MeshTopology& topology, const AtlasResult& atlas,
  const LargeVector<double>& mass, const std::vector<double>& kappa)
{
  const std::size_t n = kappa.size();
  double area = 0.0, integral = 0.0;
  for (std::size_t v = 0; v < n; ++v)
  {
    if (std::isfinite(kappa[v]))
    {
      area += mass[v];
      integral += mass[v] * kappa[v];
    }
  }
  std::vector<double> onLine(n, 0.0);
  const MeshTopology::EdgeTable& edges = topology.Edges();
  for (std::int64_t e = 0; e < edges.NumberOfEdges() && !atlas.FeatureEdges.empty(); ++e)
  {
    if (atlas.FeatureEdges[e])
    {
      onLine[edges.Vertices[2 * e]] = onLine[edges.Vertices[2 * e + 1]] = 1.0;
    }
  }
  DilateOverRings(topology, 1, onLine);
  const double twiceMean = 2.0 * integral / std::max(area, 1e-300);
  std::vector<double> weight(n, 1.0);
  for (std::size_t v = 0; v < n && twiceMean > 0.0; ++v)
  {
    weight[v] = onLine[v] > 0.0 || !std::isfinite(kappa[v]) ? 1.0 : std::max(1.0, kappa[v] / twiceMean);
  }
  return weight;
}

/// Input vertex v is farther than `pin` from the remesh and the farthest of
/// its 1-ring (a cone point of the input between the remesh's vertices).
bool FarthestOfRing(const MeshTopology& topology, const std::vector<double>& deviation, double pin, Index v)
{
  const MeshTopology::VertexGraph& graph = topology.Graph();
  bool farthest = deviation[v] > pin;
  for (std::int64_t k = graph.NeighborOffsets[v]; farthest && k < graph.NeighborOffsets[v + 1]; ++k)
  {
    farthest = deviation[graph.Neighbors[k]] <= deviation[v];
  }
  return farthest;
}

/// RaiseWhereFar's power of the ratio of the deviation to its target where
/// the remesh's spacing is longer than the input's edges: a little beyond
/// the ratio of a smooth surface's sag (a small raised spot moves the
/// samples of error diffusion less than its share of the count).  Where
/// the spacing is shorter, the square: with 1.5 throughout, fandisk_large
/// decimated to a tenth (remeshed at 0.5% of the diagonal with 5,000-8,500
/// vertices, its input 2,600) stayed beyond the bound for 8 rounds, the
/// count growing by the least tenth each; with the square throughout, the
/// error-driven remesh of a fine cylinder at 0.05% took twice the vertices.
constexpr double LocalRaise = 1.5;

/// The input's lengths RaiseWhereFar compares the remesh with, measured
/// once for every round: its mean edge, per vertex the mean length of its
/// edges (0 at a vertex in none), and its area.
struct InputScales
{
  double MeanEdge = 0.0;
  std::vector<double> VertexEdges;
  double Area = 0.0;
};

/// InputScales::VertexEdges.
std::vector<double> MeanEdgeAtVertices(const MeshTopology& topology, const double* points)
{
  const MeshTopology::EdgeTable& e = topology.Edges();
  std::vector<double> sum(static_cast<std::size_t>(topology.NumberOfVertices()), 0.0), count(sum.size(), 0.0);
  for (std::int64_t k = 0; k < e.NumberOfEdges(); ++k)
  {
    const Index a = e.Vertices[2 * k], b = e.Vertices[2 * k + 1];
    const double length = (Point(points, a) - Point(points, b)).norm();
    sum[a] += length;
    sum[b] += length;
    count[a] += 1.0;
    count[b] += 1.0;
  }
  for (std::size_t v = 0; v < sum.size(); ++v)
  {
    sum[v] = count[v] > 0.0 ? sum[v] / count[v] : 0.0;
  }
  return sum;
}

/// The next remesh's weights and count after one that left the input
/// farther than `bound`, aiming at three quarters of it (each remesh's
/// vertices fall elsewhere: its deviation varies by 10-20%).  Where the
/// remesh's spacing is longer than the input's edges the deviation falls
/// with the square of the spacing (the sag of a smooth surface), where it
/// is shorter only with the spacing (the input is a polyhedron at that
/// scale: its edges are creases the remesh cuts): the density (`weight`,
/// whose integral over the surface is `integral`) is raised by the ratio to
/// the power 1.5 or 2 (LocalRaise) wherever the input is left farther
/// within about two spacings (the input's vertices sample the remesh's sag
/// unevenly: most lie near its vertices), and the count with the integral,
/// by a tenth at least (a small raised
/// spot moves the count less than the remeshes' deviation varies, and the
/// rounds would creep); where no input vertex is (the remesh's triangles
/// are the far ones), the count alone.  At most `most`.  The input's cone
/// points farther than the bound are pinned (LocalDeviations; pinned from
/// three quarters of it, they cost more vertices than they save).
std::int64_t RaiseWhereFar(const MeshTopology& topology, const double* points, const TriangleGrid& toInput,
  const RemeshResult& remesh,
  const LargeVector<double>& mass, const InputScales& input, double bound, double worst, std::int64_t count,
  std::int64_t most, std::vector<double>& weight, double& integral, std::vector<std::uint8_t>& pinned, int numThreads)
{
  const double target = 0.75 * bound;
  std::vector<double> factor = LocalDeviations(topology, points, toInput, remesh, bound, pinned, numThreads);
  const int rings =
    static_cast<int>(std::min(32.0, std::ceil(2.0 * remesh.Spacing / std::max(input.MeanEdge, 1e-300))));
  DilateOverRings(topology, rings, factor);
  bool raised = false;
  for (std::size_t v = 0; v < factor.size(); ++v)
  {
    double& f = factor[v];
    const double spacing = remesh.Spacing * std::sqrt(integral / std::max(input.Area * weight[v], 1e-300));
    f = f > target ? std::min(16.0, std::pow(f / target, spacing < input.VertexEdges[v] ? 2.0 : LocalRaise)) : 1.0;
    raised = raised || f > 1.0;
  }
  double growth = std::min(4.0, worst / target);
  if (raised)
  {
    double raisedIntegral = 0.0;
    for (std::size_t v = 0; v < weight.size(); ++v)
    {
      weight[v] *= factor[v];
      raisedIntegral += mass[v] * weight[v];
    }
    growth = std::min(4.0, raisedIntegral / integral);
    integral = raisedIntegral;
  }
  return std::min(static_cast<std::int64_t>(std::ceil(static_cast<double>(count) * std::max(1.1, growth))), most);
}

/// The topology of a remesh's triangles.
MeshTopology TopologyOfRemesh(const RemeshResult& r, int numThreads)
{
  return MeshTopology(
    static_cast<Index>(r.Points.size() / 3), IndexArray(r.Triangles.begin(), r.Triangles.end()), numThreads);
}

/// CheckFidelity with the remesh's distances from the input and its
/// topology (`remesh`) given.
void CheckFidelity(const MeshTopology& topology, const double* points, const RemeshOptions& options,
  const RemeshDistances& distances, const MeshTopology& remesh, RemeshResult& out)
{
  RemeshCache local;
  const RemeshCache::SurfaceFigures& input =
    (options.Cache ? *options.Cache : local).Figures(topology, points, options.NumberOfThreads);
  const TopologySummary &a = topology.Summary(), &b = remesh.Summary();
  std::string differences;
  CompareCount("Euler characteristic", a.EulerCharacteristic, b.EulerCharacteristic, differences);
  CompareCount("components", input.Components, remesh.CountComponents(), differences);
  CompareCount("boundary loops", a.NumberOfBoundaryLoops, b.NumberOfBoundaryLoops, differences);
  if (!b.IsManifold() || !b.IsOriented() || remesh.NumberOfDroppedTriangles() > 0)
  {
    differences += (differences.empty() ? "" : ", ") + std::string("not a manifold, oriented mesh");
  }
  const double diagonal = input.Diagonal;
  SurfaceDeviation deviation;
  const std::vector<double>& from = distances.FromInput;
  const auto farthest = std::max_element(from.begin(), from.end());
  if (farthest != from.end())
  {
    deviation.FirstToSecond = *farthest;
    deviation.FarthestOfFirst = Point(points, static_cast<Index>(farthest - from.begin()));
  }
  const std::vector<double>& between = distances.FromInputTriangles;
  const auto crossed = std::max_element(between.begin(), between.end());
  if (crossed != between.end() && *crossed > deviation.FirstToSecond)
  {
    const std::int64_t t = crossed - between.begin();
    const IndexArray& list = topology.TriangleList();
    const Vec3 corner[3] = { Point(points, list[3 * t]), Point(points, list[3 * t + 1]),
      Point(points, list[3 * t + 2]) };
    deviation.FirstToSecond = *crossed;
    const int k = distances.FarthestSample[t];
    deviation.FarthestOfFirst = k < 3
      ? Vec3(corner[k] + static_cast<double>(distances.FarthestAlong[t]) * (corner[(k + 1) % 3] - corner[k]))
      : TriangleSample(corner, k);
  }
  const std::vector<double>& remeshed = distances.FromTriangles;
  deviation.SecondToFirst = remeshed.empty() ? 0.0 : *std::max_element(remeshed.begin(), remeshed.end());
  const double scale = diagonal > 0.0 ? diagonal : 1.0;
  out.Diagonal = diagonal;
  out.DeviationFromInput = deviation.FirstToSecond / scale;
  out.DeviationToInput = deviation.SecondToFirst / scale;
  out.FarthestInputPoint = deviation.FarthestOfFirst;
  out.Spacing = UniformSpacing(input.Area, options.NumberOfVertices);
  if (!differences.empty())
  {
    out.Error = "the remesh does not keep the input's topology (" + differences + ")";
  }
  else if (deviation.FirstToSecond > LostPartSpacings * out.Spacing)
  {
    // Not a coarse remesh but a part cut off or bridged (a limb's end):
    // a mesh without it would pass for the input.
    std::ostringstream said;
    said << "a part of the input is lost: the input point (" << out.FarthestInputPoint[0] << ", "
         << out.FarthestInputPoint[1] << ", " << out.FarthestInputPoint[2] << ") is " << deviation.FirstToSecond
         << " from the remesh, " << deviation.FirstToSecond / out.Spacing << " times its spacing";
    out.Error = said.str();
  }
}

/// The input vertices farther from the remesh (`deviation`, per input
/// vertex, and the remesh triangle `nearest` to it) than `bound(v)`, each
/// the farthest of its 1-ring (FarthestOfRing) where `ring`, with that
/// triangle; the farthest first.
template <typename Bound>
std::vector<PinTarget> FarInputVertices(const MeshTopology& topology, const std::vector<double>& deviation,
  const std::vector<Index>& nearest, bool ring, Bound&& bound)
{
  std::vector<std::pair<double, Index>> far;
  for (Index v = 0; v < topology.NumberOfVertices(); ++v)
  {
    if (nearest[v] >= 0 && (ring ? FarthestOfRing(topology, deviation, bound(v), v) : deviation[v] > bound(v)))
    {
      far.push_back({ -deviation[v], v });
    }
  }
  std::sort(far.begin(), far.end());
  std::vector<PinTarget> targets(far.size());
  for (std::size_t i = 0; i < far.size(); ++i)
  {
    targets[i].Vertex = far[i].second;
    targets[i].Face = nearest[far[i].second];
  }
  return targets;
}

/// Points a spacing apart along the input edges a point of which the remesh
/// leaves farther than `bound` (RemeshDistances::FarthestSample: a crease
/// of the input, its edges longer than the remesh's triangles, that the
/// remesh cuts), the farthest edge's first, each with the remesh face
/// nearest to it.
std::vector<PinTarget> FarEdgePoints(const MeshTopology& topology, const double* points, const RemeshDistances& d,
  const RemeshResult& remesh, double bound, int numThreads)
{
  std::vector<std::pair<double, std::int64_t>> far; // (-distance, triangle)
  for (std::size_t t = 0; t < d.FromInputTriangles.size(); ++t)
  {
    if (d.FromInputTriangles[t] > bound && d.FarthestSample[t] < 3)
    {
      far.push_back({ -d.FromInputTriangles[t], static_cast<std::int64_t>(t) });
    }
  }
  std::sort(far.begin(), far.end());
  std::vector<PinTarget> targets;
  if (far.empty())
  {
    return targets;
  }
  const TriangleGrid toRemesh(remesh.Points.data(), remesh.Triangles.data(), remesh.Triangles.size() / 3, numThreads);
  std::set<std::pair<Index, Index>> edges; // (taken once: both triangles measure the midpoint)
  const IndexArray& list = topology.TriangleList();
  for (const auto& [distance, t] : far)
  {
    const int k = d.FarthestSample[t];
    const Index a = list[3 * t + k], b = list[3 * t + (k + 1) % 3];
    if (!edges.insert(std::minmax(a, b)).second)
    {
      continue;
    }
    const double length = (Point(points, a) - Point(points, b)).norm();
    const int n = std::max(1, static_cast<int>(std::lround(length / remesh.Spacing)) - 1);
    for (int j = 1; j <= n; ++j)
    {
      PinTarget target;
      target.Triangle = static_cast<Index>(t);
      target.W[k] = 1.0 - static_cast<double>(j) / (n + 1);
      target.W[(k + 1) % 3] = static_cast<double>(j) / (n + 1);
      double within = 0.0;
      target.Face = toRemesh.Nearest(SurfacePoint(topology, points, target.Triangle, target.W.data()), within);
      if (target.Face >= 0 && within > bound) // (those still that far)
      {
        targets.push_back(target);
      }
    }
  }
  return targets;
}

/// How far input vertex v may lie off a remesh (`nearest`: the remesh
/// triangle nearest to it) before it is a corner at the remesh's scale
/// (RemeshOptions::FarPinSpacings): CornerSagRatio times the sag of that
/// triangle's longest edge on a sphere of the input's curvature there (the
/// largest |kappa|, `curvature`), and CornerPinSpacings of the spacing.
double CornerBound(const RemeshResult& remesh, Index nearest, double curvature)
{
  const Index* c = remesh.Triangles.data() + 3 * static_cast<std::size_t>(nearest);
  double longest = 0.0;
  for (int k = 0; k < 3; ++k)
  {
    const Vec3 edge = Point(remesh.Points.data(), c[k]) - Point(remesh.Points.data(), c[(k + 1) % 3]);
    longest = std::max(longest, edge.norm());
  }
  return std::max(CornerPinSpacings * remesh.Spacing, CornerSagRatio * longest * longest * curvature / 8.0);
}

/// The stitching rounds after the far vertices' pins (PinNearestVertices).
constexpr int PinnedStitchingRounds = 5;

/// Triangles whose smallest angle and share below 30 degrees are within
/// the bar or as good as the first remesh's (`firstAngle`, `firstBelow30`).
bool AsGood(double angle, double below30, double firstAngle, double firstBelow30)
{
  const bool withinBar = angle >= 15.0 && below30 <= 0.005;
  return withinBar || (angle >= std::min(firstAngle, 15.0) && below30 <= firstBelow30 + 1e-3);
}

/// `next`'s points, triangles and places on the input with `out`'s other
/// figures; its samples and graded metric (large) moved from `out` (and
/// back with GiveBack).
RemeshResult ResultOf(const Remesh& next, RemeshResult& out)
{
  SurfaceSamples samples;
  std::vector<double> metric;
  std::swap(samples, out.Samples);
  std::swap(metric, out.GradedMetric);
  RemeshResult result = out;
  result.Samples = std::move(samples);
  result.GradedMetric = std::move(metric);
  result.Points = next.Mesh.Points();
  result.Triangles = next.Mesh.Triangles();
  result.SourceTriangle = next.Triangle;
  result.SourceBarycentric = next.Barycentric;
  return result;
}

/// What ResultOf took from `out`, given back from the round's `candidate`
/// (not kept).
void GiveBack(RemeshResult& candidate, RemeshResult& out)
{
  out.Samples = std::move(candidate.Samples);
  out.GradedMetric = std::move(candidate.GradedMetric);
}

/// A fidelity round's remesh (CheckFidelityInRounds): the pins moved, its
/// result and distances.
struct RoundCandidate
{
  Remesh Next;
  PinnedVertices Pins;
  RemeshResult Result;
  RemeshDistances Distances;
};

} // namespace

bool KeptOver(const MeshTopology& topology, const double* points, const RemeshResult& next, const RemeshResult& best,
  const std::pair<double, double>& first, int numThreads, const MeshTopology* nextTopology)
{
  // Closer in the larger deviation, or no farther in it and closer in both
  // together: a round that pins the input's far vertices (corners of a
  // spiky sphere's coarse needles at 10,000 vertices, 0.205% of the
  // diagonal from the remesh) where the remesh's own farthest triangles lie
  // elsewhere (across a needle near its tip, 0.211%) was lost; kept, the
  // input is 0.082% from the remesh.  Over the corpus and
  // the generated shapes at 2,000 and 10,000 vertices 11 of 86 remeshes
  // change, none farther: the lesser deviation 0.40-0.94 times as large in
  // those, the larger 0.74 times on head at 10,000 (whose later rounds then
  // went on) and 0.99 on the collapsed bunny at 2,000.
  const auto sum = [](const RemeshResult& r) { return r.DeviationToInput + r.DeviationFromInput; };
  const bool closer = WorstDeviation(next) < FarPinGain * WorstDeviation(best) ||
    (WorstDeviation(next) <= WorstDeviation(best) && sum(next) < FarPinGain * sum(best));
  if (!next.Error.empty() || !closer)
  {
    return false;
  }
  const auto figures = ShapeFigures(topology, points, next, numThreads, nextTopology);
  return AsGood(figures.first, figures.second, first.first, first.second);
}

void CheckFidelityInRounds(const MeshTopology& topology, const double* points, const AtlasResult& atlas,
  const RemeshOptions& options, const RemeshOptimizationOptions& optimization, Remesh& remesh, RemeshResult& out)
{
  const int threads = options.NumberOfThreads;
  RemeshCache local;
  RemeshCache& cache = optimization.Cache ? *optimization.Cache : local;
  const TriangleGrid& toInput = cache.SurfaceGrid(topology, points, threads);
  RemeshDistances distances = MeasureDistances(topology, points, toInput, out, threads);
  const MeshTopology outTopology = TopologyOfRemesh(out, threads);
  CheckFidelity(topology, points, options, distances, outTopology, out);
  if (options.FarPinSpacings <= 0.0 || options.FarPinRounds <= 0 ||
    (options.PinnedVertices && !options.RoundsWithPinnedVertices) || options.FinalSurface ||
    !out.Error.empty())
  {
    return;
  }
  out.SourceTriangle = remesh.Triangle; // (ShapeFigures' metric needs them)
  out.SourceBarycentric = remesh.Barycentric;
  const auto first = ShapeFigures(topology, points, out, threads, &outTopology);
  const std::vector<double>& curvature = cache.MaximumCurvature;
  // A round's candidate: the pins moved, the remesh measured again, and
  // whether KeptOver would keep it (its samples and metric left in `out`);
  // `distances` copied where another candidate follows, else taken.
  const auto attempt = [&](const std::vector<PinTarget>& targets, RoundCandidate& c, bool another) {
    c.Next = remesh;
    c.Pins = targets.empty()
      ? PinnedVertices()
      : PinNearestVertices(c.Next, topology, points, atlas, out.Samples, targets, optimization, PinnedStitchingRounds);
    if (c.Pins.Reached.empty() && c.Pins.ReachedPoints == 0)
    {
      return false;
    }
    c.Result = ResultOf(c.Next, out);
    c.Distances = another ? distances : std::move(distances);
    UpdateDistances(topology, points, toInput, out, c.Result, c.Distances, threads);
    const MeshTopology candidateTopology = TopologyOfRemesh(c.Result, threads);
    CheckFidelity(topology, points, options, c.Distances, candidateTopology, c.Result);
    const bool kept = KeptOver(topology, points, c.Result, out, first, threads, &candidateTopology);
    GiveBack(c.Result, out);
    return kept;
  };
  bool verticesKept = false; // a round with the far vertices alone
  for (int round = 0; round < options.FarPinRounds; ++round)
  {
    const std::vector<double>& far = distances.FromInput;
    const std::vector<Index>& nearest = distances.Nearest;
    const double bound = options.FarPinSpacings * out.Spacing;
    std::vector<PinTarget> targets = FarInputVertices(topology, far, nearest, true, [&](Index) { return bound; });
    const bool farVertices = !targets.empty();
    const std::vector<PinTarget> creases = FarEdgePoints(topology, points, distances, out, bound, threads);
    const bool corners = targets.empty() && creases.empty() && !curvature.empty(); // (none that far: the corners)
    if (corners)
    {
      targets = FarInputVertices(
        topology, far, nearest, false, [&](Index v) { return CornerBound(out, nearest[v], curvature[v]); });
    }
    // With the points along the creases the remesh cuts and with the far
    // vertices alone; the closer kept.
    RoundCandidate withCreases, alone;
    std::vector<PinTarget> all = targets;
    all.insert(all.end(), creases.begin(), creases.end());
    const bool creasesKept = !creases.empty() && attempt(all, withCreases, true);
    const bool aloneKept = (!creasesKept || farVertices) && attempt(targets, alone, false);
    const bool useAlone =
      aloneKept && (!creasesKept || WorstDeviation(alone.Result) <= WorstDeviation(withCreases.Result));
    if (!creasesKept && !aloneKept)
    {
      // Far vertices none could be moved onto, or whose moves brought the
      // remesh no closer where no round of them alone was kept (a round
      // with the creases' points may be): the remesh is made again with
      // them pinned (RemeshSurface).
      out.FarVerticesLeft = !corners && (alone.Pins.Unreached > 0 || (!verticesKept && farVertices));
      return;
    }
    verticesKept = verticesKept || useAlone;
    RoundCandidate& kept = useAlone ? alone : withCreases;
    kept.Result.Samples = std::move(out.Samples);
    kept.Result.GradedMetric = std::move(out.GradedMetric);
    remesh = std::move(kept.Next);
    out = std::move(kept.Result);
    distances = std::move(kept.Distances);
    out.ReachedFarVertices.insert(out.ReachedFarVertices.end(), kept.Pins.Reached.begin(), kept.Pins.Reached.end());
    out.FarVerticesLeft = false; // (measured in the next round)
  }
}

std::vector<double> LocalDeviations(const MeshTopology& topology, const double* points, const TriangleGrid& toInput,
  const RemeshResult& remesh, double pin, std::vector<std::uint8_t>& pinned, int numThreads)
{
  const std::size_t triangles = remesh.Triangles.size() / 3;
  RemeshDistances d = MeasureDistances(topology, points, toInput, remesh, numThreads);
  std::vector<double> deviation = std::move(d.FromInput);
  for (Index v = 0; v < topology.NumberOfVertices(); ++v)
  {
    pinned[v] = pinned[v] || FarthestOfRing(topology, deviation, pin, v);
  }
  const IndexArray& input = topology.TriangleList();
  for (std::size_t t = 0; t < d.FromInputTriangles.size(); ++t)
  {
    for (int k = 0; k < 3; ++k)
    {
      double& at = deviation[input[3 * t + k]];
      at = std::max(at, d.FromInputTriangles[t]);
    }
  }
  const std::vector<double>& remeshed = d.FromTriangles;
  for (std::size_t t = 0; t < triangles; ++t)
  {
    for (int k = 0; k < 3; ++k)
    {
      const Index source = remesh.SourceTriangle[remesh.Triangles[3 * t + k]];
      for (int j = 0; source >= 0 && j < 3; ++j)
      {
        double& at = deviation[input[3 * static_cast<std::size_t>(source) + j]];
        at = std::max(at, remeshed[t]);
      }
    }
  }
  return deviation;
}

TriangleQuality RemeshQuality(const RemeshResult& r, int numThreads)
{
  return MeasureTriangleQuality(TopologyOfRemesh(r, numThreads), r.Points.data());
}

std::pair<double, double> ShapeFigures(const MeshTopology& topology, const double* points, const RemeshResult& r,
  int numThreads, const MeshTopology* remeshTopology)
{
  if (r.GradedMetric.empty())
  {
    const TriangleQuality q =
      remeshTopology ? MeasureTriangleQuality(*remeshTopology, r.Points.data()) : RemeshQuality(r, numThreads);
    return { q.MinimumAngle, q.FractionBelow30 };
  }
  const MetricQuality q = MeasureInMetric(
    topology, points, r.GradedMetric.data(), r.Points, r.Triangles, r.SourceTriangle, r.SourceBarycentric);
  return { q.MinimumAngle, q.TrianglesBelow30 };
}

bool AsGoodTriangles(const RemeshResult& second, const RemeshResult& first, int numThreads)
{
  const TriangleQuality a = RemeshQuality(first, numThreads), b = RemeshQuality(second, numThreads);
  return AsGood(b.MinimumAngle, b.FractionBelow30, a.MinimumAngle, a.FractionBelow30);
}

void CheckFidelity(const MeshTopology& topology, const double* points, const RemeshOptions& options, RemeshResult& out)
{
  // (Not options.Cache's grid: a smoothed copy's remesh is measured against the input.)
  const TriangleGrid toInput(
    points, topology.TriangleList().data(), topology.NumberOfTriangles(), options.NumberOfThreads);
  CheckFidelity(topology, points, options, MeasureDistances(topology, points, toInput, out, options.NumberOfThreads),
    TopologyOfRemesh(out, options.NumberOfThreads), out);
}

double WorstDeviation(const RemeshResult& r)
{
  return std::max(r.DeviationToInput, r.DeviationFromInput);
}

DeviationRemeshResult RemeshToDeviation(const MeshTopology& topology, const double* points, const AtlasResult& atlas,
  const double* importance, const RemeshOptions& options, double maximumDeviation, int maximumRounds)
{
  DeviationRemeshResult out;
  const std::size_t n = static_cast<std::size_t>(topology.NumberOfVertices());
  RemeshCache local;
  RemeshCache* cache = options.Cache ? options.Cache : &local;
  KeepCurvatures(topology, points, options.NumberOfThreads, *cache);
  const LargeVector<double>& mass = cache->SurfaceLaplacian.Mass;
  const double diagonal = UsedBoundingBoxDiagonal(points, topology.TriangleList().data(), topology.NumberOfTriangles());
  const double bound = maximumDeviation * diagonal;
  std::int64_t count = options.NumberOfVertices;
  if (count <= 0)
  {
    // (With a metric in curvature's units, its density is the curvature
    // the isotropic estimate uses: sqrt(kappa_1 kappa_2) where it is
    // anisotropic.)
    count = std::max<std::int64_t>(100,
      CountForDeviation(mass,
        options.Metric ? MetricDensities(options.Metric, static_cast<Index>(n)) : cache->MaximumCurvature, bound));
  }
  // The importance, graded once for the first count (ImportanceGradation):
  // the rounds raise it where the remesh is far, spots that stay as raised.
  std::vector<double> weight = !options.Metric && importance
    ? GradedImportance(topology, points, importance, count, options.ImportanceGradation, options.NumberOfThreads, *cache)
    : std::vector<double>();
  if (weight.empty())
  {
    weight = importance ? std::vector<double>(importance, importance + n)
      : options.Metric  ? std::vector<double>(n, 1.0)
                        : WeightsForDeviation(topology, atlas, mass, cache->MaximumCurvature);
  }
  double integral = 0.0; // of the weight over the surface
  for (std::size_t v = 0; v < n; ++v)
  {
    integral += mass[v] * weight[v];
  }
  const InputScales input{ MeanEdgeLength(topology, points), MeanEdgeAtVertices(topology, points),
    std::accumulate(mass.begin(), mass.end(), 0.0) };
  // The input's grid, once for every round (its triangles stay).
  const TriangleGrid& toInput = cache->SurfaceGrid(topology, points, options.NumberOfThreads);
  std::vector<std::uint8_t> pinned(n, 0); // where a remesh left the input farthest
  RemeshOptions round = options;
  round.Cache = cache;
  round.PinnedVertices = pinned.data();
  round.RoundsWithPinnedVertices = true;
  round.ImportanceGradation = 0.0;
  int failures = 0, stalled = 0, doublings = 0;
  double closest = HUGE_VAL;
  for (int r = 0; r < maximumRounds && !out.Met; ++r)
  {
    round.NumberOfVertices = count;
    out.Counts.push_back(count);
    out.Remesh = RemeshSurface(topology, points, atlas, weight.data(), round);
    out.Rounds = r + 1;
    if (!out.Remesh.Error.empty())
    {
      // The chart boundaries (and a sample inside each chart) need more
      // samples, or a thin part was lost (tried twice more with twice the
      // count: beyond, more vertices fail as these did).
      const SurfaceSamples& samples = out.Remesh.Samples;
      const bool boundaries = samples.BoundarySamples >= count || samples.ChartsWithoutSample > 0;
      if (!boundaries && ++failures > 2)
      {
        break;
      }
      count = 2 * std::max(count, samples.BoundarySamples >= count ? samples.BoundarySamples : samples.NeededSamples);
      continue;
    }
    const double worst = std::max(out.Remesh.DeviationToInput, out.Remesh.DeviationFromInput) * diagonal;
    out.Met = worst <= bound;
    // More vertices where it is far that do not bring the remesh closer
    // (twice in a row: a thin part split along its length by a seam, whose
    // halves are narrower than the band the halftone leaves beside the
    // seams) take more everywhere, twice at most: the count times the
    // square of the deviation over the bound (the deviation falls about as
    // the count grows; its square leaves room for the 10% by which it
    // varies from remesh to remesh), a quarter more to twice.  Twice always
    // took the bunny at 0.2% of its diagonal from 10,195 vertices, 1.02
    // times the bound, to 20,390 and 0.67 times it; now 12,744 and 0.77.
    // Beyond, or beyond what the input's resolution can use, the last
    // remesh stands (Met says it missed).
    stalled = worst > 0.95 * closest ? stalled + 1 : 0;
    closest = std::min(closest, worst);
    const std::int64_t most = MostVerticesPerInputVertex * static_cast<std::int64_t>(n);
    if (out.Met || (stalled >= 2 && ++doublings > 2) || count >= most)
    {
      break;
    }
    if (stalled >= 2)
    {
      count = std::min(most, static_cast<std::int64_t>(std::ceil(
                               static_cast<double>(count) * std::clamp(worst * worst / (bound * bound), 1.25, 2.0))));
      stalled = 0;
      continue;
    }
    // With a metric, whose lengths keep the deviation even, the count
    // alone, by the ratio of the deviation to 0.85 of the bound (a tenth
    // more at least), and the input's vertices left farthest pinned (a
    // comb's fingers, a thin handle): raised spots took the density from
    // elsewhere and drew the remesh no closer on a blade's rims, where the
    // far part is long, or on fandisk (its error-driven remesh at 0.1% of
    // the diagonal took 8,343 vertices so, 4,286 now).
    if (options.Metric)
    {
      LocalDeviations(topology, points, toInput, out.Remesh, bound, pinned, options.NumberOfThreads);
      count = std::min(most, static_cast<std::int64_t>(std::ceil(
                               static_cast<double>(count) * std::clamp(worst / (0.85 * bound), 1.1, 4.0))));
    }
    else
    {
      count = RaiseWhereFar(topology, points, toInput, out.Remesh, mass, input, bound, worst, count, most, weight,
        integral, pinned, options.NumberOfThreads);
    }
  }
  return out;
}

} // namespace beltrami
