// Beltrami core, private to Flows/Fairing: the step (and the operator) of a
// large surface chosen on a sample of it (FairWithSampledSearch), the same
// sample whether the surface is whole or split over processes.
#include "Flows/FairingStepChoice.h"

#include "Flows/NoiseEstimation.h"
#include "Mesh/MeshMeasures.h"
#include "Solvers/SparseGraph.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>

namespace beltrami::detail
{

namespace
{

/// A sampled point as doubles: its hash (two exact halves), its id (index
/// or global row), its point and its constraints (fixed, weight, axis, plane).
constexpr std::size_t Width = 14;

/// A point's hash as two doubles (exact).
std::array<double, 2> Halves(std::uint64_t h)
{
  return { static_cast<double>(h >> 32), static_cast<double>(h & 0xffffffffull) };
}

/// The SampledPatches points of least PointHash (of all processes' owned
/// points with `split`): the centres of the sample's balls.
std::vector<Vec3> Seeds(Index n, const double* x, const Partition* split)
{
  // The least (hash, id) pairs, kept sorted as the points pass (a copy of
  // all of them took a second on 10M points).
  std::vector<std::pair<std::uint64_t, Index>> hashes;
  for (Index v = 0; v < n; ++v)
  {
    if ((!split || split->IsOwned(v)) && Point(x, v).allFinite())
    {
      const std::pair<std::uint64_t, Index> h(PointHash(x + 3 * static_cast<std::int64_t>(v)), v);
      if (hashes.size() < SampledPatches || h < hashes.back())
      {
        hashes.insert(std::upper_bound(hashes.begin(), hashes.end(), h), h);
        hashes.resize(std::min(hashes.size(), SampledPatches));
      }
    }
  }
  const std::size_t mine = hashes.size();
  std::vector<double> candidates;
  for (std::size_t s = 0; s < mine; ++s)
  {
    const std::array<double, 2> h = Halves(hashes[s].first);
    const Vec3 p = Point(x, hashes[s].second);
    candidates.insert(candidates.end(), { h[0], h[1], p[0], p[1], p[2] });
  }
  if (split)
  {
    candidates = split->AllGather(candidates);
  }
  std::vector<std::array<double, 5>> all(candidates.size() / 5);
  for (std::size_t c = 0; c < all.size(); ++c)
  {
    std::copy_n(candidates.begin() + static_cast<std::ptrdiff_t>(5 * c), 5, all[c].begin());
  }
  std::sort(all.begin(), all.end());
  std::vector<Vec3> seeds;
  for (std::size_t s = 0; s < std::min(SampledPatches, all.size()); ++s)
  {
    seeds.emplace_back(all[s][2], all[s][3], all[s][4]);
  }
  return seeds;
}

/// Per point (ghosts too), whether it is in the sample: the `count` points
/// (of all) nearest to the seeds, balls of one radius.
std::vector<std::uint8_t> Inside(Index n, const double* x, std::int64_t count, const Partition* split, int threads)
{
  const std::vector<Vec3> seeds = Seeds(n, x, split);
  std::vector<double> nearest(static_cast<std::size_t>(n), std::numeric_limits<double>::infinity()), owned;
  ParallelFor(n, threads, [&](std::int64_t begin, std::int64_t end) {
    for (std::int64_t v = begin; v < end; ++v)
    {
      for (const Vec3& c : seeds)
      {
        nearest[v] = std::min(nearest[v], (Point(x, v) - c).squaredNorm()); // (a NaN point stays out)
      }
    }
  });
  if (split)
  {
    for (Index v = 0; v < n; ++v)
    {
      if (split->IsOwned(v))
      {
        owned.push_back(nearest[v]);
      }
    }
  }
  else
  {
    owned = nearest;
  }
  const std::int64_t total = split ? split->TotalRows() : n;
  const std::int64_t k = std::min<std::int64_t>(count, total - 1);
  double radius = 0.0;
  if (split)
  {
    radius = split->NthSmallest(owned, k);
  }
  else
  {
    std::nth_element(owned.begin(), owned.begin() + k, owned.end());
    radius = owned[static_cast<std::size_t>(k)];
  }
  std::vector<std::uint8_t> inside(static_cast<std::size_t>(n), 0);
  for (Index v = 0; v < n; ++v)
  {
    inside[v] = nearest[v] <= radius;
  }
  return inside;
}

/// The sample cut out of the surface, its points and triangles in an order
/// from their coordinates alone (Assemble), so that a split surface gives
/// the whole one's sample exactly.
struct Sample
{
  std::unique_ptr<MeshTopology> Topology;
  std::vector<double> Points, Weights, Axes, Normals;
  std::vector<std::uint8_t> Fixed;
  FairingConstraints Constraints;
};

/// The records (Width doubles each) of the points of `triangles` (three ids
/// each), along a Morton curve of their box (near in the sample where they
/// are near on the surface, for the solves), then by hash.
std::vector<std::size_t> AlongCurve(const std::vector<double>& records, const std::vector<double>& triangles)
{
  std::vector<double> used(triangles); // (points of no sampled triangle are left out)
  std::sort(used.begin(), used.end());
  std::vector<std::size_t> order;
  Vec3 low = Vec3::Constant(std::numeric_limits<double>::infinity()), high = -low;
  for (std::size_t r = 0; r < records.size() / Width; ++r)
  {
    if (std::binary_search(used.begin(), used.end(), records[Width * r + 2]))
    {
      order.push_back(r);
      low = low.cwiseMin(Vec3(&records[Width * r + 3]));
      high = high.cwiseMax(Vec3(&records[Width * r + 3]));
    }
  }
  const Vec3 scale = (high - low).cwiseMax(Vec3::Constant(1e-300)).cwiseInverse() * 2097151.0; // 21 bits
  std::vector<std::array<std::uint64_t, 3>> keys(records.size() / Width);
  for (const std::size_t r : order)
  {
    std::uint64_t morton = 0;
    for (int a = 0; a < 3; ++a)
    {
      const double t = (records[Width * r + 3 + a] - low[a]) * scale[a]; // (NaN where the box overflows)
      const auto q = static_cast<std::uint64_t>(t >= 0.0 ? std::min(t, 2097151.0) : 0.0);
      for (int b = 0; b < 21; ++b)
      {
        morton |= ((q >> b) & 1) << (3 * b + a);
      }
    }
    keys[r] = { morton, static_cast<std::uint64_t>(records[Width * r]),
      static_cast<std::uint64_t>(records[Width * r + 1]) };
  }
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return keys[a] < keys[b]; });
  return order;
}

/// The triangles (three ids each) in sample points (`order`: the records of
/// the sample's points), each from its least point (the same orientation),
/// in order.
IndexArray SampleTriangles(
  const std::vector<double>& records, const std::vector<double>& triangles, const std::vector<std::size_t>& order)
{
  std::vector<std::pair<double, Index>> index(order.size()); // (id, sample point) by id
  for (std::size_t r = 0; r < order.size(); ++r)
  {
    index[r] = { records[Width * order[r] + 2], static_cast<Index>(r) };
  }
  std::sort(index.begin(), index.end());
  const auto at = [&](double id) {
    return std::lower_bound(index.begin(), index.end(), std::pair<double, Index>(id, -1))->second;
  };
  std::vector<std::array<Index, 3>> sorted;
  for (std::size_t t = 0; t + 2 < triangles.size(); t += 3)
  {
    std::array<Index, 3> c = { at(triangles[t]), at(triangles[t + 1]), at(triangles[t + 2]) };
    std::rotate(c.begin(), std::min_element(c.begin(), c.end()), c.end());
    sorted.push_back(c);
  }
  std::sort(sorted.begin(), sorted.end());
  IndexArray list;
  for (const auto& c : sorted)
  {
    list.insert(list.end(), c.begin(), c.end());
  }
  return list;
}

/// The sample from its points' records (Width doubles each, any order) and
/// its triangles (three ids each); `given`: which constraints the surface
/// has.  Its points along the curve (AlongCurve), then breadth-first from
/// there (the solves run a third faster than along the curve: 5.8 s against
/// 8.1 s for the search on bunny00 Loop-subdivided twice with noise of
/// 0.075% of the diagonal).
Sample Assemble(const std::vector<double>& records, const std::vector<double>& triangles, const FairingConstraints& given,
  int threads)
{
  std::vector<std::size_t> order = AlongCurve(records, triangles);
  const Index count = static_cast<Index>(order.size());
  {
    const MeshTopology curve(count, SampleTriangles(records, triangles, order), threads);
    const MeshTopology::VertexGraph& graph = curve.Graph();
    const std::vector<Index> breadth = LocalityOrder(count, graph.NeighborOffsets.data(), graph.Neighbors.data());
    std::vector<std::size_t> reordered(order.size());
    for (std::size_t r = 0; r < order.size(); ++r)
    {
      reordered[r] = order[breadth[r]];
    }
    order.swap(reordered);
  }
  Sample s;
  s.Topology = std::make_unique<MeshTopology>(count, SampleTriangles(records, triangles, order), threads);
  for (const std::size_t r : order)
  {
    const double* p = &records[Width * r];
    s.Points.insert(s.Points.end(), p + 3, p + 6);
    s.Fixed.push_back(p[6] != 0.0);
    s.Weights.push_back(p[7]);
    s.Axes.insert(s.Axes.end(), p + 8, p + 11);
    s.Normals.insert(s.Normals.end(), p + 11, p + 14);
  }
  s.Constraints.Fixed = given.Fixed ? s.Fixed.data() : nullptr;
  s.Constraints.Weights = given.Weights ? s.Weights.data() : nullptr;
  s.Constraints.AxisDirections = given.AxisDirections ? s.Axes.data() : nullptr;
  s.Constraints.PlaneNormals = given.PlaneNormals ? s.Normals.data() : nullptr;
  return s;
}

/// The records of the sampled points this process owns and the sampled
/// triangles it counts (ids: indices, global rows with `split`).
void Records(const MeshTopology& topo, const double* x, const FairingConstraints& cons,
  const std::vector<std::uint8_t>& inside, const Partition* split, std::vector<double>& records,
  std::vector<double>& triangles)
{
  const auto id = [&](Index v) { return static_cast<double>(split ? split->GlobalRow(v) : v); };
  for (Index v = 0; v < topo.NumberOfVertices(); ++v)
  {
    if (inside[v] && (!split || split->IsOwned(v)))
    {
      const std::array<double, 2> h = Halves(PointHash(x + 3 * static_cast<std::int64_t>(v)));
      const auto three = [&](const double* a, int k) { return a ? a[3 * static_cast<std::int64_t>(v) + k] : 0.0; };
      records.insert(records.end(), { h[0], h[1], id(v), x[3 * v], x[3 * v + 1], x[3 * v + 2],
                                      cons.Fixed ? static_cast<double>(cons.Fixed[v] != 0) : 0.0,
                                      cons.Weights ? cons.Weights[v] : 1.0, three(cons.AxisDirections, 0),
                                      three(cons.AxisDirections, 1), three(cons.AxisDirections, 2),
                                      three(cons.PlaneNormals, 0), three(cons.PlaneNormals, 1),
                                      three(cons.PlaneNormals, 2) });
    }
  }
  const IndexArray& all = topo.TriangleList();
  for (std::size_t t = 0; t + 2 < all.size(); t += 3)
  {
    const Index a = all[t], b = all[t + 1], c = all[t + 2];
    if (inside[a] && inside[b] && inside[c] && (!split || split->CountsTriangle(a, b, c)))
    {
      triangles.insert(triangles.end(), { id(a), id(b), id(c) });
    }
  }
}

/// The unit of the time step (FairSurface's): h^(2k) for order k in the
/// mean edge length h, 1 for the umbrella.
double StepUnit(
  const MeshTopology& topo, const double* x, const FairingOptions& opt, FairingOperator op, const Partition* split)
{
  if (opt.Units != LengthUnit::MeanEdgeLength || op == FairingOperator::Umbrella)
  {
    return 1.0;
  }
  return StepUnitOf(MeanEdgeLength(topo, x, split), Powers::Of(opt).Degree, op);
}

/// The choice on the sample, as doubles: whether it ran, the operator, the
/// step (in length units), the noise figures, the estimated errors (of the
/// step and of the input), the sample's points and the warning's characters.
std::vector<double> ChooseOnSample(const Sample& s, const FairingOptions& options)
{
  FairingOptions o = options;
  o.Boundary = FairingBoundary::Fixed; // (the cut around each ball too)
  o.Invariant = FairingInvariant::None; // (a ball encloses nothing)
  o.Hierarchy = nullptr;
  o.KeptHierarchy = nullptr;
  o.StepSearchPoints = 0; // (the sample searched whole)
  std::vector<double> sample(s.Points);
  const FairingReport r = FairSurface(*s.Topology, sample.data(), o, s.Constraints, nullptr, nullptr);
  std::vector<double> pack = { r.Error.empty() ? 1.0 : 0.0, static_cast<double>(r.OperatorUsed),
    r.ChosenTimeStep * StepUnit(*s.Topology, s.Points.data(), options, r.OperatorUsed, nullptr), r.Noise,
    r.MedianDihedral, r.WiderNoise, r.LocalNoise, r.TangentialNoise, r.EstimatedError, r.InputError,
    static_cast<double>(s.Topology->NumberOfVertices()) };
  pack.insert(pack.end(), r.StepWarning.begin(), r.StepWarning.end());
  return pack;
}

} // namespace

std::optional<FairingReport> FairWithSampledSearch(const MeshTopology& topo, double* points,
  const FairingOptions& options, const FairingConstraints& cons, const ProgressCallback& progress,
  const Partition* split)
{
  const std::int64_t total = split ? split->TotalRows() : topo.NumberOfVertices();
  if (options.TimeStep != 0.0 || options.NumberOfIterations <= 0 || options.StepSearchPoints <= 0 ||
    options.Integration == FairingIntegration::TaubinLambdaMu || total <= SampledSearchRatio * options.StepSearchPoints ||
    (split && !DistributedFairingLimitation(options).empty()))
  {
    return std::nullopt;
  }
  const std::vector<std::uint8_t> inside =
    Inside(topo.NumberOfVertices(), points, options.StepSearchPoints, split, options.NumberOfThreads);
  std::vector<double> records, triangles;
  Records(topo, points, cons, inside, split, records, triangles);
  // (Balls of infinite radius - coordinates whose squares overflow - or of
  // many points at one distance would take more: the whole surface instead.)
  const double count = static_cast<double>(records.size() / Width);
  if ((split ? split->Sum(count) : count) > 2.0 * static_cast<double>(options.StepSearchPoints))
  {
    return std::nullopt;
  }
  if (split)
  {
    records = split->GatherOnFirst(records);
    triangles = split->GatherOnFirst(triangles);
  }
  std::vector<double> pack;
  if (!split || split->Rank() == 0)
  {
    pack = ChooseOnSample(Assemble(records, triangles, cons, options.NumberOfThreads), options);
  }
  if (split)
  {
    pack = split->AllGather(pack); // (process 0's alone)
  }
  if (pack.empty() || pack[0] == 0.0)
  {
    return std::nullopt; // (the whole surface searched instead)
  }
  // The whole surface with the sample's operator and step (the same step
  // in length units).
  FairingOptions o = options;
  o.Operator = static_cast<FairingOperator>(static_cast<int>(pack[1]));
  o.TimeStep = pack[2] / StepUnit(topo, points, options, o.Operator, split);
  if (!std::isfinite(o.TimeStep))
  {
    return std::nullopt; // (a length unit that overflows: the whole surface's path says so)
  }
  o.NumberOfIterations = o.TimeStep > 0.0 ? options.NumberOfIterations : 0;
  FairingReport report = FairSurface(topo, points, o, cons, progress, split);
  report.Noise = pack[3];
  report.MedianDihedral = pack[4];
  report.WiderNoise = pack[5];
  report.LocalNoise = pack[6];
  report.TangentialNoise = pack[7];
  report.ChosenTimeStep = o.TimeStep;
  report.EstimatedError = pack[8];
  report.InputError = pack[9];
  report.SampledPoints = static_cast<Index>(pack[10]);
  for (auto c = pack.begin() + 11; c != pack.end(); ++c)
  {
    report.StepWarning.push_back(static_cast<char>(*c));
  }
  report.Warning = report.StepWarning + report.Warning;
  return report;
}

} // namespace beltrami::detail
