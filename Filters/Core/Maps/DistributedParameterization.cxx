// The parameterization of a surface split over MPI processes (see
// Parameterization.h): each process assembles the conformal rows of the
// points it owns and the conjugate gradients, preconditioned by a multigrid
// hierarchy that spans the processes, solve the system with the outer
// boundary fixed.  Only the boundary (its points' rows, successors and
// coordinates: O(sqrt n) values) is gathered on every process.
#include "Maps/Parameterization.h"

#include "Mesh/Geometry.h"
#include "Mesh/Laplacian.h"
#include "Solvers/Partition.h"
#include "Support/DisjointSets.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>
#include <unordered_map>

namespace beltrami
{

std::string DistributedParameterizationLimitation(const ParameterizationOptions& options)
{
  if (options.Boundary == ParameterizationBoundary::Natural)
  {
    return "the natural boundary";
  }
  if (options.AuthalicWeight != 0.0 || options.OptimizeMix)
  {
    return "the authalic energy (its system is not symmetric)";
  }
  if (!options.Constraints.empty() || !options.Lines.empty())
  {
    return "point and line constraints";
  }
  if (options.BoundaryOptimizationSteps > 0 || options.KeepBoundaryBasis)
  {
    return "the boundary basis and its optimisation";
  }
  if (options.Boundary == ParameterizationBoundary::Square && options.Corners == SquareCorners::Sharpest)
  {
    return "square corners at the sharpest turns";
  }
  return {};
}

namespace
{

/// The boundary of the whole surface, the same on every process: its points
/// (global rows, coordinates) and loops (positions in Rows), each loop
/// starting at its first point in the order of the point ids (or of the
/// coordinates), as a serial run's loops start at their lowest point id.
struct SplitBoundary
{
  std::vector<std::int64_t> Rows;
  std::vector<double> Points; // 3 per point
  std::vector<std::vector<Index>> Loops;
  bool Broken = false; // a successor missing: the boundary does not close
};

constexpr int RecordSize = 6; // row, next row, id, x, y, z

SplitBoundary GatherBoundary(
  const MeshTopology& topo, const double* points, const Partition& split, const std::int64_t* pointIds)
{
  std::vector<double> mine;
  for (Index v = 0; v < topo.NumberOfVertices(); ++v)
  {
    const Index next = topo.BoundaryNext(v);
    if (split.IsOwned(v) && next >= 0)
    {
      const double record[RecordSize] = { static_cast<double>(split.GlobalRow(v)),
        static_cast<double>(split.GlobalRow(next)), pointIds ? static_cast<double>(pointIds[v]) : 0.0,
        points[3 * v], points[3 * v + 1], points[3 * v + 2] };
      mine.insert(mine.end(), record, record + RecordSize);
    }
  }
  const std::vector<double> all = split.AllGather(mine);
  const Index n = static_cast<Index>(all.size() / RecordSize);
  SplitBoundary b;
  std::unordered_map<std::int64_t, Index> at;
  std::vector<std::int64_t> next(n);
  for (Index k = 0; k < n; ++k)
  {
    const double* r = &all[static_cast<std::size_t>(k) * RecordSize];
    b.Rows.push_back(static_cast<std::int64_t>(r[0]));
    next[k] = static_cast<std::int64_t>(r[1]);
    b.Points.insert(b.Points.end(), r + 3, r + 6);
    at[b.Rows[k]] = k;
  }
  std::vector<Index> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](Index p, Index q) {
    const double* a = &all[static_cast<std::size_t>(p) * RecordSize];
    const double* c = &all[static_cast<std::size_t>(q) * RecordSize];
    return std::lexicographical_compare(a + 2, a + 6, c + 2, c + 6) ||
      (std::equal(a + 2, a + 6, c + 2) && a[0] < c[0]);
  });
  std::vector<std::uint8_t> visited(n, 0);
  for (Index start : order)
  {
    std::vector<Index> loop;
    for (Index k = start; k >= 0 && !visited[k];)
    {
      visited[k] = 1;
      loop.push_back(k);
      const auto found = at.find(next[k]);
      b.Broken |= found == at.end();
      k = found == at.end() ? -1 : found->second;
    }
    if (!loop.empty())
    {
      b.Loops.push_back(std::move(loop));
    }
  }
  return b;
}

/// Connected components of the whole surface: those of each piece, joined
/// where a point that one process holds as a ghost lies in another's.
Index CountSplitComponents(const MeshTopology& topo, const Partition& split)
{
  const Index n = topo.NumberOfVertices();
  const std::vector<Index> root = topo.ComponentRoots();
  std::vector<Index> component(n, -1);
  Index local = 0;
  for (Index v = 0; v < n; ++v)
  {
    if (topo.Valence(v) > 0 && root[v] == v)
    {
      component[v] = local++;
    }
  }
  const std::vector<double> counts = split.AllGather({ static_cast<double>(local) });
  const double offset = std::accumulate(counts.begin(), counts.begin() + split.Rank(), 0.0);
  std::vector<double> label(n, -1.0); // the component's number over all processes
  for (Index v = 0; v < n; ++v)
  {
    label[v] = topo.Valence(v) > 0 ? offset + component[root[v]] : -1.0;
  }
  std::vector<double> owners(label);
  split.UpdateGhosts(owners.data(), 1);
  std::vector<double> pairs;
  for (Index v = 0; v < n; ++v)
  {
    if (!split.IsOwned(v) && label[v] >= 0.0 && owners[v] >= 0.0 && owners[v] != label[v])
    {
      pairs.push_back(label[v]);
      pairs.push_back(owners[v]);
    }
  }
  const std::vector<double> joined = split.AllGather(pairs);
  const Index total = static_cast<Index>(std::accumulate(counts.begin(), counts.end(), 0.0));
  std::vector<Index> global(total);
  std::iota(global.begin(), global.end(), 0);
  for (std::size_t k = 0; k < joined.size(); k += 2)
  {
    global[FindRoot(global, static_cast<Index>(joined[k]))] = FindRoot(global, static_cast<Index>(joined[k + 1]));
  }
  Index components = 0;
  for (Index c = 0; c < total; ++c)
  {
    components += FindRoot(global, c) == c;
  }
  return components;
}

/// CheckDiskTopology over the processes: each counts its owned points (whose
/// stars it holds whole) and the edges and triangles it counts.  An error
/// sentence, empty for a disk.
std::string CheckSplitDisk(const MeshTopology& topo, const double* points, const Partition& split,
  const SplitBoundary& boundary)
{
  // used points, edges, triangles, defective points, non-finite points
  double counts[5] = { 0, 0, 0, 0, 0 };
  const std::uint8_t defects = VertexNonManifold | VertexInconsistent | VertexDuplicateFace;
  for (Index v = 0; v < topo.NumberOfVertices(); ++v)
  {
    if (split.IsOwned(v) && topo.Valence(v) > 0)
    {
      counts[0] += 1.0;
      counts[3] += (topo.VertexFlags(v) & defects) != 0;
      counts[4] += !Point(points, v).allFinite();
    }
  }
  const MeshTopology::EdgeTable& edges = topo.Edges();
  for (std::int64_t e = 0; e < edges.NumberOfEdges(); ++e)
  {
    counts[1] += split.CountsEdge(edges.Vertices[2 * e], edges.Vertices[2 * e + 1]);
  }
  const IndexArray& t = topo.TriangleList();
  for (std::size_t k = 0; k < t.size(); k += 3)
  {
    counts[2] += split.CountsTriangle(t[k], t[k + 1], t[k + 2]);
  }
  split.Sum(counts, 5);
  const Index components = CountSplitComponents(topo, split);
  const double loops = static_cast<double>(boundary.Loops.size());
  const double twiceGenus = 2.0 - (counts[0] - counts[1] + counts[2]) - loops;
  if (counts[2] == 0.0)
  {
    return "Cannot parameterize: the input has no triangles.";
  }
  if (counts[3] > 0.0 || boundary.Broken || components != 1 || loops == 0.0 || twiceGenus != 0.0)
  {
    std::ostringstream os;
    os << "Cannot parameterize: a parameterization needs one connected, manifold, consistently oriented surface "
          "of genus 0 with at least one boundary loop (a disk, possibly with holes); the input split over the "
          "ranks is: "
       << counts[2] << " triangles, " << components << " components, " << loops << " boundary loops, Euler "
       << "characteristic " << counts[0] - counts[1] + counts[2];
    if (counts[3] > 0.0 || boundary.Broken)
    {
      os << ", " << counts[3] << " non-manifold, inconsistently oriented or duplicated points";
    }
    os << ".";
    return os.str();
  }
  if (counts[4] > 0.0)
  {
    return "Cannot parameterize: " + std::to_string(static_cast<long long>(counts[4])) +
      " points have non-finite coordinates.";
  }
  return {};
}

/// The fixed rows and their positions (2 per row of the topology): the outer
/// loop on the circle or the square, or every loop at the given positions;
/// points in no triangle at (0, 0).  An error sentence, empty if none.
std::string FixSplitBoundary(const MeshTopology& topo, const Partition& split, const SplitBoundary& boundary,
  const ParameterizationOptions& options, std::vector<std::uint8_t>& fixed, std::vector<double>& uv,
  std::vector<std::int64_t>& outer)
{
  const Index n = topo.NumberOfVertices();
  fixed.assign(n, 0);
  uv.assign(2 * static_cast<std::size_t>(n), 0.0);
  std::unordered_map<std::int64_t, Index> onLoop; // global row -> boundary point
  const bool given = options.Boundary == ParameterizationBoundary::Given;
  const std::vector<Index>& longest = boundary.Loops[LongestLoop(boundary.Loops, boundary.Points.data())];
  for (std::size_t l = 0; given && l < boundary.Loops.size(); ++l)
  {
    for (Index k : boundary.Loops[l])
    {
      onLoop[boundary.Rows[k]] = k;
    }
  }
  std::vector<double> placed(2 * boundary.Rows.size(), 0.0);
  if (!given)
  {
    if (options.Boundary == ParameterizationBoundary::Square && longest.size() < 4)
    {
      return "A square boundary needs at least 4 boundary points.";
    }
    PlaceBoundaryLoop(longest, boundary.Points.data(), options.Boundary, options.Spacing, placed.data());
    for (Index k : longest)
    {
      onLoop[boundary.Rows[k]] = k;
    }
  }
  std::vector<double> givenUV(given ? 2 * static_cast<std::size_t>(n) : 0, 0.0);
  if (given && split.Sum(n > 0 && !options.GivenUV ? 1.0 : 0.0) > 0.0) // (agreed: no process waits)
  {
    return "Given boundary positions were requested but none were supplied.";
  }
  if (given)
  {
    std::copy_n(options.GivenUV ? options.GivenUV : givenUV.data(), givenUV.size(), givenUV.begin());
    split.UpdateGhosts(givenUV.data(), 2);
  }
  double nonFinite = 0.0;
  for (Index v = 0; v < n; ++v)
  {
    const auto found = onLoop.find(split.GlobalRow(v));
    fixed[v] = found != onLoop.end() || topo.Valence(v) == 0;
    if (found != onLoop.end())
    {
      const double* at = given ? &givenUV[2 * static_cast<std::size_t>(v)] : &placed[2 * found->second];
      uv[2 * v] = at[0];
      uv[2 * v + 1] = at[1];
      nonFinite += split.IsOwned(v) && !(std::isfinite(at[0]) && std::isfinite(at[1]));
    }
  }
  split.UpdateGhosts(fixed); // (a ghost row is fixed where its owner's is: here its star may be partial)
  outer.clear();
  for (Index k : longest)
  {
    outer.push_back(boundary.Rows[k]);
  }
  return split.Sum(nonFinite) > 0.0 ? "The given boundary positions of some points are not finite." : "";
}

} // namespace

ParameterizationResult Parameterize(const MeshTopology& topo, const double* points,
  const ParameterizationOptions& options, const Partition& split, const std::int64_t* pointIds)
{
  ParameterizationResult result;
  const std::string limitation = DistributedParameterizationLimitation(options);
  if (!limitation.empty())
  {
    result.Error = "A parameterization over split processes does not cover " + limitation + ".";
    return result;
  }
  const SplitBoundary boundary = GatherBoundary(topo, points, split, pointIds);
  result.Error = CheckSplitDisk(topo, points, split, boundary);
  std::vector<std::uint8_t> fixed;
  std::vector<double> uv;
  if (result.Error.empty())
  {
    result.Error = FixSplitBoundary(topo, split, boundary, options, fixed, uv, result.OuterRows);
  }
  if (!result.Error.empty())
  {
    return result;
  }
  // The conformal energy (eq. 5.4): the cotangent stiffness, the fixed rows eliminated.
  const int threads = ResolveThreadCount(options.NumberOfThreads);
  GraphLaplacian laplacian;
  AssembleSurfaceLaplacian(topo, points, LaplacianWeights::Cotangent, laplacian, threads);
  ShiftedLaplacianProblem problem = laplacian.Problem(2);
  problem.Fixed = fixed.data();
  problem.Scale.assign(2, 1.0);
  problem.Tolerance = options.SplitTolerance;
  problem.MaximumIterations = 100000; // converged long before, or an error
  problem.NumberOfThreads = threads;
  problem.Preconditioner = Preconditioning::Multigrid;
  problem.Split = &split;
  const std::vector<double> zero(uv.size(), 0.0);
  const ConjugateGradientResult solved = SolveShiftedLaplacian(problem, zero.data(), uv.data());
  result.Iterations = solved.Iterations;
  double degenerate = 0.0;
  for (Index t = 0; t < topo.NumberOfTriangles(); ++t)
  {
    degenerate += split.CountsTriangle(topo.CornerVertex(3 * t), topo.CornerVertex(3 * t + 1),
                    topo.CornerVertex(3 * t + 2)) && Degenerate3D(topo, points, t);
  }
  result.DegenerateTriangles = static_cast<Index>(split.Sum(degenerate));
  double finite = 1.0;
  for (double value : uv)
  {
    finite = std::isfinite(value) ? finite : 0.0;
  }
  if (!solved.Converged || split.Sum(1.0 - finite) > 0.0)
  {
    std::ostringstream os;
    os << "Cannot parameterize: the conjugate gradients did not converge (relative residual "
       << solved.RelativeResidual << " after " << solved.Iterations << " iterations; degenerate triangles?).";
    result.Error = os.str();
    return result;
  }
  if (result.DegenerateTriangles)
  {
    result.Warning = std::to_string(result.DegenerateTriangles) + " zero-area triangles were left out of the energy";
  }
  result.UV = std::move(uv);
  return result;
}

} // namespace beltrami
