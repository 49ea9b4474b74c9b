// The decomposition of a vector field on a surface split over MPI processes
// (see VectorFields.h): each process holds its part of the surface with the
// whole star of every point it owns (Solvers/Partition.h) and assembles the
// rows of the points and edges it owns; conjugate gradients on BoomerAMG
// spanning the processes solve the Poisson systems, or, where there are no
// harmonic fields, each process integrates the stream function across its
// part.  The edges are split as the points are: each owned by the owner of
// its end with the lower global row, which holds both of its triangles.  No
// process holds more than its part: only a record per component (its pin,
// its mean, its Euler characteristic) and per pair of adjacent parts (the
// constant joining their integrations) is gathered on every process.
#include "Mesh/VectorFields.h"

#include "Mesh/Geometry.h"
#include "Mesh/Laplacian.h"
#include "Mesh/MeshMeasures.h"
#include "Mesh/VectorFieldsDetail.h"
#include "Solvers/GraphSolvers.h"
#include "Solvers/Partition.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <unordered_map>
#include <unordered_set>

namespace beltrami
{

using namespace detail;

namespace
{

/// Per row of `split` (the points of `topo`), its component over all
/// processes, named by its lowest global row: each process's components
/// take the lowest label they hold, and the ghosts their owners', until no
/// label changes (one round per process a component crosses).
std::vector<double> ComponentLabels(const MeshTopology& topo, const Partition& split)
{
  const Index n = topo.NumberOfVertices();
  const std::vector<Index> root = topo.ComponentRoots();
  std::vector<double> label(n), least(n);
  for (Index i = 0; i < n; ++i)
  {
    label[i] = static_cast<double>(split.GlobalRow(i));
  }
  for (;;)
  {
    std::fill(least.begin(), least.end(), std::numeric_limits<double>::infinity());
    for (Index i = 0; i < n; ++i)
    {
      least[root[i]] = std::min(least[root[i]], label[i]);
    }
    double changed = 0.0;
    for (Index i = 0; i < n; ++i)
    {
      changed += split.IsOwned(i) && least[root[i]] != label[i];
      label[i] = least[root[i]];
    }
    split.UpdateGhosts(label.data(), 1);
    if (split.Max(changed) == 0.0)
    {
      return label;
    }
  }
}

/// Values per component label: each process's records (label -> `width`
/// values) combined over all processes by `fold(into, from)`, in the order
/// of the ranks (the same on every process).
using Records = std::unordered_map<std::int64_t, std::vector<double>>;
Records CombineOverProcesses(const Partition& split, const Records& mine, int width,
  const std::function<void(double*, const double*)>& fold)
{
  std::vector<double> flat;
  flat.reserve(mine.size() * (width + 1));
  for (const auto& [label, values] : mine)
  {
    flat.push_back(static_cast<double>(label));
    flat.insert(flat.end(), values.begin(), values.end());
  }
  const std::vector<double> all = split.AllGather(flat);
  Records combined;
  for (std::size_t k = 0; k < all.size(); k += width + 1)
  {
    const auto label = static_cast<std::int64_t>(all[k]);
    const auto found = combined.find(label);
    if (found == combined.end())
    {
      combined.emplace(label, std::vector<double>(all.begin() + k + 1, all.begin() + k + 1 + width));
    }
    else
    {
      fold(found->second.data(), &all[k + 1]);
    }
  }
  return combined;
}

/// One Poisson system of the decomposition, split over the processes: as
/// the serial PoissonSystem (K x = b, the fixed rows at 0, one row pinned in
/// each component that none anchors, zero mean there), solved by conjugate
/// gradients on BoomerAMG spanning the processes.  (The points' system on
/// the processes' own geometric multigrids joined by a coarse level took
/// 1.3-1.6 times as long: 54 iterations against 11 on the bunny
/// Loop-subdivided twice, 603k points, on 2 processes.)
class SplitPoissonSystem
{
public:
  SplitPoissonSystem(GraphLaplacian laplacian, std::vector<std::uint8_t> fixed, std::vector<double> label,
    const Partition& split, const VectorFieldOptions& options)
    : L(std::move(laplacian))
    , Fixed(std::move(fixed))
    , Label(std::move(label))
    , Split(split)
    , Options(options)
  {
    PinFloatingComponents();
  }

  std::vector<double> Solve(const std::vector<double>& b, double scale, VectorFieldDecomposition& r) const
  {
    std::vector<double> x(L.NumberOfVertices, 0.0);
    ShiftedLaplacianProblem pb = L.Problem(1);
    pb.Factor = 2.0; // (the true stiffness: twice the assembler's)
    pb.Fixed = Fixed.data();
    pb.Scale.assign(1, scale);
    pb.Tolerance = Options.Tolerance;
    pb.NumberOfThreads = Options.NumberOfThreads;
    pb.Split = &Split;
    pb.Preconditioner = Preconditioning::Multigrid;
    pb.MaximumIterations = 20000;
    const ConjugateGradientResult result = SolveShiftedLaplacian(pb, b.data(), x.data());
    r.Iterations += result.Iterations;
    r.Iterations = static_cast<int>(Split.Max(r.Iterations));
    r.Converged = r.Converged && Split.Max(result.Converged ? 0.0 : 1.0) == 0.0;
    r.Residual = std::max(r.Residual, Split.Max(result.RelativeResidual));
    RemoveMeans(x);
    return x;
  }

private:
  /// Pins, in each component that no fixed row anchors on any process, its
  /// free row with the lowest global number.
  void PinFloatingComponents()
  {
    Records mine; // label -> anchored, lowest free row
    for (Index i = 0; i < L.NumberOfVertices; ++i)
    {
      if (!Split.IsOwned(i) || !(L.Diagonal[i] > 0.0))
      {
        continue;
      }
      std::vector<double>& record = mine.try_emplace(static_cast<std::int64_t>(Label[i]),
        std::vector<double>{ 0.0, std::numeric_limits<double>::infinity() }).first->second;
      record[0] = std::max(record[0], Fixed[i] ? 1.0 : 0.0);
      record[1] = Fixed[i] ? record[1] : std::min(record[1], static_cast<double>(Split.GlobalRow(i)));
    }
    const Records all = CombineOverProcesses(Split, mine, 2, [](double* into, const double* from) {
      into[0] = std::max(into[0], from[0]);
      into[1] = std::min(into[1], from[1]);
    });
    std::vector<double> fixed(L.NumberOfVertices);
    for (Index i = 0; i < L.NumberOfVertices; ++i)
    {
      const auto found = all.find(static_cast<std::int64_t>(Label[i]));
      const bool floating = found != all.end() && found->second[0] == 0.0;
      if (floating)
      {
        Floating.insert(found->first);
      }
      fixed[i] = Fixed[i] || (floating && Split.IsOwned(i) && static_cast<double>(Split.GlobalRow(i)) == found->second[1]);
    }
    Split.UpdateGhosts(fixed.data(), 1);
    for (Index i = 0; i < L.NumberOfVertices; ++i)
    {
      Fixed[i] = fixed[i] != 0.0;
    }
  }

  /// Zero mean (mass-weighted) on the floating components.
  void RemoveMeans(std::vector<double>& x) const
  {
    Records mine; // label -> sum of mass times x, mass
    for (Index i = 0; i < L.NumberOfVertices; ++i)
    {
      const auto label = static_cast<std::int64_t>(Label[i]);
      if (Split.IsOwned(i) && Floating.count(label))
      {
        std::vector<double>& record = mine.try_emplace(label, std::vector<double>{ 0.0, 0.0 }).first->second;
        record[0] += L.Mass[i] * x[i];
        record[1] += L.Mass[i];
      }
    }
    const Records all = CombineOverProcesses(Split, mine, 2, [](double* into, const double* from) {
      into[0] += from[0];
      into[1] += from[1];
    });
    for (Index i = 0; i < L.NumberOfVertices; ++i) // (the ghosts too: the same mean as at their owners)
    {
      const auto found = all.find(static_cast<std::int64_t>(Label[i]));
      if (found != all.end() && found->second[1] > 0.0)
      {
        x[i] -= found->second[0] / found->second[1];
      }
    }
  }

  GraphLaplacian L;
  std::vector<std::uint8_t> Fixed;
  std::vector<double> Label; ///< per row: its component (ComponentLabels)
  std::unordered_set<std::int64_t> Floating; ///< the labels of the pinned components
  const Partition& Split;
  VectorFieldOptions Options;
};

/// As detail::NoHarmonicFields over the processes: no zero-area triangle,
/// manifold and oriented at every point (each checked by its owner, which
/// holds its star), and every component of Euler characteristic 2 or 1.
bool NoHarmonicFieldsSplit(
  const MeshTopology& topo, const Partition& split, const std::vector<double>& label, Index degenerate)
{
  const std::uint8_t defects = VertexNonManifold | VertexInconsistent | VertexDuplicateFace;
  const IndexArray& tri = topo.TriangleList();
  const MeshTopology::EdgeTable& edges = topo.Edges();
  double bad = degenerate > 0 ? 1.0 : 0.0;
  Records euler; // label -> V - E + F, each counted once over the processes
  const auto add = [&euler, &label](Index v, double x) {
    euler.try_emplace(static_cast<std::int64_t>(label[v]), std::vector<double>{ 0.0 }).first->second[0] += x;
  };
  for (Index v = 0; v < topo.NumberOfVertices(); ++v)
  {
    if (split.IsOwned(v) && topo.Valence(v) > 0)
    {
      bad += (topo.VertexFlags(v) & defects) != 0;
      add(v, 1.0);
    }
  }
  for (std::int64_t e = 0; e < edges.NumberOfEdges(); ++e)
  {
    const Index a = edges.Vertices[2 * e], b = edges.Vertices[2 * e + 1];
    if (split.CountsEdge(a, b))
    {
      add(a, -1.0);
    }
  }
  for (std::int64_t k = 0; k < 3 * static_cast<std::int64_t>(topo.NumberOfTriangles()); k += 3)
  {
    if (split.CountsTriangle(tri[k], tri[k + 1], tri[k + 2]))
    {
      add(tri[k], 1.0);
    }
  }
  const Records all = CombineOverProcesses(split, euler, 1, [](double* into, const double* from) { into[0] += from[0]; });
  return split.Max(bad) == 0.0 &&
    std::all_of(all.begin(), all.end(), [](const auto& c) { return c.second[0] == 1.0 || c.second[0] == 2.0; });
}

/// As detail::IntegrateStreamFunction over the processes: each integrates
/// its part, component by component (its triangles joined by edges) from
/// one of their edges; the constants that join those values across the
/// processes come from the edges that two of them hold (one per pair of
/// components, gathered on every process); then, per component of the
/// surface, the boundary at 0 (TangentDivergenceFree, where it has one) or
/// zero mean.  `edgeSplit`: the edges over the processes.
std::vector<double> IntegratedStreamFunctionSplit(const MeshTopology& topo, const double* points,
  const TriangleFrames& f, const EdgeGraph& graph, VectorFieldBoundary boundary, const std::vector<double>& rest,
  const Partition& edgeSplit, const std::vector<double>& label)
{
  const MeshTopology::EdgeTable& edges = topo.Edges();
  const std::int64_t ne = edges.NumberOfEdges();
  std::vector<double> v(ne, 0.0), part(ne, 0.0);
  std::vector<std::uint8_t> known(ne, 0), visited(topo.NumberOfTriangles(), 0);
  double parts = 0.0;
  for (Index t = 0; t < topo.NumberOfTriangles(); ++t)
  {
    if (!visited[t])
    {
      const Index first = graph.TriangleEdges[3 * static_cast<std::int64_t>(t)];
      for (const Index e : IntegrateAcross(topo, points, f, graph, rest, t, first, v, known, visited))
      {
        part[e] = parts;
      }
      ++parts;
    }
  }
  // Each part named over the processes; at every edge, its owner's value and part.
  const double stride = edgeSplit.Max(parts) + 1.0;
  std::vector<double> owners(2 * ne);
  for (std::int64_t e = 0; e < ne; ++e)
  {
    part[e] += stride * edgeSplit.Rank();
    owners[2 * e] = v[e];
    owners[2 * e + 1] = part[e];
  }
  edgeSplit.UpdateGhosts(owners.data(), 2);
  std::map<std::pair<double, double>, double> relations; // (mine, theirs) -> c_mine - c_theirs
  for (std::int64_t e = 0; e < ne; ++e)
  {
    if (!edgeSplit.IsOwned(static_cast<Index>(e)) && owners[2 * e + 1] != part[e])
    {
      relations.emplace(std::make_pair(part[e], owners[2 * e + 1]), owners[2 * e] - v[e]);
    }
  }
  std::vector<double> flat;
  for (const auto& [pair, difference] : relations)
  {
    flat.insert(flat.end(), { pair.first, pair.second, difference });
  }
  const std::vector<double> all = edgeSplit.AllGather(flat);
  std::map<double, std::vector<std::pair<double, double>>> joined; // part -> (other, c_other - c_part)
  for (std::size_t k = 0; k < all.size(); k += 3)
  {
    joined[all[k]].emplace_back(all[k + 1], -all[k + 2]);
    joined[all[k + 1]].emplace_back(all[k], all[k + 2]);
  }
  std::map<double, double> constant; // from the lowest part of each group, breadth first (the same on every process)
  for (const auto& [root, unused] : joined)
  {
    if (constant.emplace(root, 0.0).second)
    {
      std::vector<double> queue(1, root);
      for (std::size_t q = 0; q < queue.size(); ++q)
      {
        for (const auto& [other, step] : joined[queue[q]])
        {
          if (constant.emplace(other, constant[queue[q]] + step).second)
          {
            queue.push_back(other);
          }
        }
      }
    }
  }
  // Per component: the boundary's mean, the mass-weighted mean (the lumped
  // mass: a third of each triangle per edge), over the owned edges.
  Records mine;
  for (std::int64_t e = 0; e < ne; ++e)
  {
    const auto found = constant.find(part[e]);
    v[e] += found == constant.end() ? 0.0 : found->second;
    if (!edgeSplit.IsOwned(static_cast<Index>(e)))
    {
      continue;
    }
    double mass = 0.0;
    for (int s = 0; s < 2; ++s)
    {
      const Index corner = edges.OppositeCorners[2 * e + s];
      mass += corner >= 0 ? f.Areas[corner / 3] / 3.0 : 0.0;
    }
    const bool onBoundary = edges.FaceCount[e] == 1;
    std::vector<double>& r = mine.try_emplace(static_cast<std::int64_t>(label[edges.Vertices[2 * e]]),
      std::vector<double>(4, 0.0)).first->second;
    r[0] += onBoundary;
    r[1] += onBoundary ? v[e] : 0.0;
    r[2] += mass;
    r[3] += mass * v[e];
  }
  const Records sums = CombineOverProcesses(edgeSplit, mine, 4, [](double* into, const double* from) {
    for (int k = 0; k < 4; ++k)
    {
      into[k] += from[k];
    }
  });
  for (std::int64_t e = 0; e < ne; ++e)
  {
    const auto found = sums.find(static_cast<std::int64_t>(label[edges.Vertices[2 * e]]));
    if (found == sums.end())
    {
      continue; // (a ghost edge of a component no process owns an edge of: cannot be)
    }
    const std::vector<double>& r = found->second;
    const bool fixed = boundary == VectorFieldBoundary::TangentDivergenceFree && r[0] > 0.0;
    v[e] = fixed ? (edges.FaceCount[e] == 1 && edgeSplit.IsOwned(static_cast<Index>(e)) ? 0.0 : v[e] - r[1] / r[0])
                 : v[e] - (r[2] > 0.0 ? r[3] / r[2] : 0.0);
  }
  edgeSplit.UpdateGhosts(v.data(), 1);
  return v;
}

/// The bounding box of the points of every process's triangles.
Eigen::AlignedBox3d WholeBox(const MeshTopology& topo, const double* points, const Partition& split)
{
  const Eigen::AlignedBox3d box = UsedPointsBox(topo, points);
  const double inf = std::numeric_limits<double>::infinity();
  double corners[6];
  for (int d = 0; d < 3; ++d)
  {
    corners[d] = box.isEmpty() ? -inf : -box.min()[d];
    corners[3 + d] = box.isEmpty() ? -inf : box.max()[d];
  }
  split.Max(corners, 6);
  Eigen::AlignedBox3d whole; // (empty where no process has a triangle)
  if (corners[3] >= -corners[0])
  {
    whole = Eigen::AlignedBox3d(Eigen::Vector3d(-corners[0], -corners[1], -corners[2]),
      Eigen::Vector3d(corners[3], corners[4], corners[5]));
  }
  return whole;
}

} // namespace

void DecomposeVectorField(const MeshTopology& topo, const double* points, const double* vectors,
  const VectorFieldOptions& o, const Partition& split, VectorFieldDecomposition& r)
{
  const int threads = o.NumberOfThreads;
  const Index nt = topo.NumberOfTriangles();
  const IndexArray& tri = topo.TriangleList();
  // Coordinates far from unit size: as the serial decomposer, the points of
  // the whole surface times one power of two.
  const Eigen::AlignedBox3d box = WholeBox(topo, points, split);
  const int e = FarScaleExponent(box);
  const std::vector<double> scaled =
    e ? PointsTimesPowerOfTwo(points, topo.NumberOfVertices(), -e) : std::vector<double>();
  const double* p = e ? scaled.data() : points;
  // (The scaled points' box: the box's corners times 2^-e, exactly.)
  const auto scaledBy = [e](double x) { return std::ldexp(x, -e); };
  const Eigen::Vector3d diagonal = box.max().unaryExpr(scaledBy) - box.min().unaryExpr(scaledBy);
  const double extent = box.isEmpty() ? 1.0 : std::max(diagonal.norm(), 1e-300);
  const TriangleFrames frames = MakeFrames(topo, p, threads);
  std::vector<std::uint8_t> counted(nt); // each triangle summed on one process
  double degenerate = 0.0;
  for (Index t = 0; t < nt; ++t)
  {
    const std::int64_t k = 3 * static_cast<std::int64_t>(t);
    counted[t] = split.CountsTriangle(tri[k], tri[k + 1], tri[k + 2]);
    degenerate += counted[t] && frames.Areas[t] == 0.0;
  }
  r = VectorFieldDecomposition();
  r.DegenerateTriangles = static_cast<Index>(split.Sum(degenerate));
  ProjectToTangent(frames, vectors, r, threads);
  double largest = 0.0;
  for (const double x : r.Tangent)
  {
    largest = std::max(largest, std::abs(x));
  }
  largest = split.Max(largest);
  int f = 0; // the field times 2^-f where far from unit size
  if (largest > 0.0 && std::isfinite(largest))
  {
    std::frexp(largest, &f);
    f = std::abs(f) > 60 ? f : 0;
  }
  TimesPowerOfTwo(r.Tangent.data(), r.Tangent.size(), -f);
  const double scale = std::ldexp(largest, -f) * extent;
  const std::vector<double> label = ComponentLabels(topo, split);

  GraphLaplacian cotangent;
  AssembleSurfaceLaplacian(topo, p, LaplacianWeights::Cotangent, cotangent, threads);
  std::vector<std::uint8_t> fixed = FixedVertices(topo, frames, cotangent, o.Boundary);
  const SplitPoissonSystem potential(std::move(cotangent), std::move(fixed), label, split, o);
  r.Potential = potential.Solve(PotentialRightHandSide(topo, p, frames, threads, r), scale, r);
  GradientPart(topo, p, frames, threads, r);

  // The stream function: where there are no harmonic fields integrated
  // across the triangles, else solved.
  const MeshTopology::EdgeTable& edges = topo.Edges();
  const Index ne = static_cast<Index>(edges.NumberOfEdges());
  const std::unique_ptr<Partition> edgeSplit = Partition::OfItems(split, ne, 2, edges.Vertices.data());
  r.Integrated = o.Integrate && NoHarmonicFieldsSplit(topo, split, label, r.DegenerateTriangles);
  EdgeGraph graph;
  graph.Build(topo, !r.Integrated);
  if (r.Integrated)
  {
    std::vector<double> rest(r.Tangent.size());
    for (std::size_t k = 0; k < rest.size(); ++k)
    {
      rest[k] = r.Tangent[k] - r.CurlFree[k];
    }
    r.StreamFunction = IntegratedStreamFunctionSplit(topo, p, frames, graph, o.Boundary, rest, *edgeSplit, label);
  }
  else
  {
    GraphLaplacian nonconforming;
    AssembleNonconformingLaplacian(topo, graph, p, nonconforming, threads);
    std::vector<std::uint8_t> fixedEdges = FixedEdges(topo, frames, nonconforming, o.Boundary);
    std::vector<double> edgeLabel(ne);
    for (Index k = 0; k < ne; ++k)
    {
      edgeLabel[k] = label[edges.Vertices[2 * static_cast<std::int64_t>(k)]];
    }
    const SplitPoissonSystem stream(
      std::move(nonconforming), std::move(fixedEdges), std::move(edgeLabel), *edgeSplit, o);
    r.StreamFunction = stream.Solve(StreamRightHandSide(topo, p, threads, r), scale, r);
  }
  RotatedGradientPart(topo, p, frames, graph, threads, r);
  HarmonicPart(frames, threads, r, counted.data());
  split.Sum(r.Energy, 4);
  split.Sum(r.InnerProducts, 3);
  r.Areas = frames.Areas;
  ScaleBack(e, f, r);
}

} // namespace beltrami
