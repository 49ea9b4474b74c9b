// The surface hierarchy of the geometric multigrid (see SurfaceMultigrid.h):
// samples, regions, coarse graphs and prolongations.
#include "Solvers/SurfaceMultigrid.h"

#include "Solvers/GraphSolversDetail.h"
#include "Solvers/SparseGraph.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <numeric>
#include <utility>

namespace beltrami
{

namespace
{

/// Levels stop at this many rows (solved by a sparse Cholesky), or where a
/// level keeps more than MostKept of the finer one's rows (many tiny
/// components, each of which keeps a sample).
constexpr Index CoarsestRows = 1000;
constexpr double MostKept = 0.6;

/// A graph with a point per row (one level of the hierarchy).
struct PointGraph
{
  LargeVector<std::int64_t> Offsets{ 0 };
  LargeVector<Index> Neighbors;
  std::vector<double> Points;

  Index Rows() const { return static_cast<Index>(Offsets.size() - 1); }
};

/// The samples: a maximal set of rows at least three edges apart, taken in
/// row order (coarse[i] = the sample's coarse row, or -1).
std::vector<Index> Samples(const PointGraph& g, Index& count)
{
  const Index n = g.Rows();
  std::vector<Index> coarse(n, -1);
  std::vector<std::uint8_t> covered(n, 0);
  count = 0;
  for (Index i = 0; i < n; ++i)
  {
    if (covered[i])
    {
      continue;
    }
    coarse[i] = count++;
    covered[i] = 1;
    for (std::int64_t k = g.Offsets[i]; k < g.Offsets[i + 1]; ++k)
    {
      const Index j = g.Neighbors[k];
      covered[j] = 1;
      for (std::int64_t l = g.Offsets[j]; l < g.Offsets[j + 1]; ++l)
      {
        covered[g.Neighbors[l]] = 1;
      }
    }
  }
  return coarse;
}

double Distance(const double* a, const double* b)
{
  return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
}

/// The region of each row: its sample, or the sample nearest along paths
/// of one or two edges (every row is within two edges of a sample: the
/// samples are a maximal set).  A multi-source Dijkstra along the edges
/// took 0.17 s single-threaded at 600k rows.
std::vector<Index> NearestSamples(const PointGraph& g, const std::vector<Index>& coarse, int threads)
{
  const Index n = g.Rows();
  std::vector<Index> region(n, -1);
  ParallelFor(n, threads, [&](std::int64_t s, std::int64_t e) {
    for (std::int64_t i = s; i < e; ++i)
    {
      if (coarse[i] >= 0)
      {
        region[i] = coarse[i];
        continue;
      }
      const double* p = &g.Points[3 * i];
      double nearest = std::numeric_limits<double>::infinity();
      const auto consider = [&](Index j, double d) {
        d = std::isnan(d) ? std::numeric_limits<double>::max() : d; // (NaN points: still some sample)
        if (coarse[j] >= 0 && (region[i] < 0 || d < nearest || (d == nearest && coarse[j] < region[i])))
        {
          nearest = d;
          region[i] = coarse[j];
        }
      };
      for (std::int64_t k = g.Offsets[i]; k < g.Offsets[i + 1]; ++k)
      {
        const Index j = g.Neighbors[k];
        const double d = Distance(p, &g.Points[3 * j]);
        consider(j, d);
        for (std::int64_t l = g.Offsets[j]; l < g.Offsets[j + 1]; ++l)
        {
          consider(g.Neighbors[l], d + Distance(&g.Points[3 * j], &g.Points[3 * g.Neighbors[l]]));
        }
      }
    }
  });
  return region;
}

/// The coarse graph: samples joined where their regions touch.
PointGraph CoarseGraph(const PointGraph& g, const std::vector<Index>& coarse, const std::vector<Index>& region,
  Index count, int threads)
{
  // The rows of each region: the transpose of the rows' regions.
  LevelMatrix inRegion;
  inRegion.Offsets.resize(static_cast<std::size_t>(g.Rows()) + 1);
  std::iota(inRegion.Offsets.begin(), inRegion.Offsets.end(), 0);
  inRegion.Columns.assign(region.begin(), region.end());
  inRegion.Values.assign(region.size(), 1.0);
  const LevelMatrix members = Transposed(inRegion, count);
  PointGraph c;
  c.Points.resize(3 * static_cast<std::size_t>(count));
  c.Offsets.resize(static_cast<std::size_t>(count) + 1, 0);
  // Blocks of coarse rows in parallel, each with its own neighbour list,
  // joined in order.
  constexpr Index block = 4096;
  std::vector<std::vector<Index>> parts(static_cast<std::size_t>((count + block - 1) / block));
  ParallelFor(static_cast<std::int64_t>(parts.size()), threads, [&](std::int64_t first, std::int64_t last) {
    std::vector<Index> touching;
    for (std::int64_t part = first; part < last; ++part)
    {
      for (Index a = static_cast<Index>(part * block); a < std::min<Index>(count, static_cast<Index>((part + 1) * block)); ++a)
      {
        touching.clear();
        for (std::int64_t m = members.Offsets[a]; m < members.Offsets[a + 1]; ++m)
        {
          const Index i = members.Columns[m];
          if (coarse[i] == a)
          {
            std::copy(&g.Points[3 * i], &g.Points[3 * i] + 3, &c.Points[3 * a]);
          }
          for (std::int64_t k = g.Offsets[i]; k < g.Offsets[i + 1]; ++k)
          {
            const Index b = region[g.Neighbors[k]];
            if (b != a)
            {
              touching.push_back(b);
            }
          }
        }
        std::sort(touching.begin(), touching.end());
        touching.erase(std::unique(touching.begin(), touching.end()), touching.end());
        parts[part].insert(parts[part].end(), touching.begin(), touching.end());
        c.Offsets[a + 1] = static_cast<std::int64_t>(touching.size());
      }
    }
  }, {}, 0, 1);
  std::partial_sum(c.Offsets.begin(), c.Offsets.end(), c.Offsets.begin());
  c.Neighbors.reserve(static_cast<std::size_t>(c.Offsets.back()));
  for (const std::vector<Index>& part : parts)
  {
    c.Neighbors.insert(c.Neighbors.end(), part.begin(), part.end());
  }
  return c;
}

bool Adjacent(const PointGraph& g, Index a, Index b)
{
  return std::binary_search(g.Neighbors.begin() + g.Offsets[a], g.Neighbors.begin() + g.Offsets[a + 1], b);
}

/// Row i's prolongation weights (coarse row, weight): the clamped
/// barycentric coordinates of p in the coarse triangle around sample s that
/// holds it best, else on the nearest coarse edge from s, else s alone.
void ProlongationRow(const PointGraph& c, Index s, const double* p, std::vector<std::pair<Index, double>>& row)
{
  row.clear();
  const double* o = &c.Points[3 * s];
  const double d[3] = { p[0] - o[0], p[1] - o[1], p[2] - o[2] };
  double best = -std::numeric_limits<double>::infinity();
  double weights[3] = { 1.0, 0.0, 0.0 };
  Index corners[3] = { s, -1, -1 };
  for (std::int64_t k = c.Offsets[s]; k < c.Offsets[s + 1]; ++k)
  {
    const Index a = c.Neighbors[k];
    const double* pa = &c.Points[3 * a];
    const double e1[3] = { pa[0] - o[0], pa[1] - o[1], pa[2] - o[2] };
    for (std::int64_t l = k + 1; l < c.Offsets[s + 1]; ++l)
    {
      const Index b = c.Neighbors[l];
      if (!Adjacent(c, a, b))
      {
        continue;
      }
      const double* pb = &c.Points[3 * b];
      const double e2[3] = { pb[0] - o[0], pb[1] - o[1], pb[2] - o[2] };
      const double g11 = e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2];
      const double g12 = e1[0] * e2[0] + e1[1] * e2[1] + e1[2] * e2[2];
      const double g22 = e2[0] * e2[0] + e2[1] * e2[1] + e2[2] * e2[2];
      const double det = g11 * g22 - g12 * g12;
      if (!(det > 1e-12 * g11 * g22))
      {
        continue; // degenerate
      }
      const double r1 = e1[0] * d[0] + e1[1] * d[1] + e1[2] * d[2];
      const double r2 = e2[0] * d[0] + e2[1] * d[1] + e2[2] * d[2];
      const double u = (g22 * r1 - g12 * r2) / det, v = (g11 * r2 - g12 * r1) / det;
      const double score = std::min({ 1.0 - u - v, u, v });
      if (score > best)
      {
        best = score;
        weights[0] = 1.0 - u - v;
        weights[1] = u;
        weights[2] = v;
        corners[1] = a;
        corners[2] = b;
      }
    }
  }
  if (corners[1] < 0)
  {
    // No triangle: the nearest point on the edges from s.
    double nearest = std::numeric_limits<double>::infinity();
    for (std::int64_t k = c.Offsets[s]; k < c.Offsets[s + 1]; ++k)
    {
      const Index a = c.Neighbors[k];
      const double* pa = &c.Points[3 * a];
      const double e[3] = { pa[0] - o[0], pa[1] - o[1], pa[2] - o[2] };
      const double ee = e[0] * e[0] + e[1] * e[1] + e[2] * e[2];
      if (!(ee > 0.0))
      {
        continue;
      }
      const double t = std::clamp((e[0] * d[0] + e[1] * d[1] + e[2] * d[2]) / ee, 0.0, 1.0);
      const double q[3] = { d[0] - t * e[0], d[1] - t * e[1], d[2] - t * e[2] };
      const double dd = q[0] * q[0] + q[1] * q[1] + q[2] * q[2];
      if (dd < nearest)
      {
        nearest = dd;
        weights[0] = 1.0 - t;
        weights[1] = t;
        weights[2] = 0.0;
        corners[1] = a;
      }
    }
  }
  double sum = 0.0;
  for (double& w : weights)
  {
    w = std::isfinite(w) ? std::max(0.0, w) : 0.0;
    sum += w;
  }
  if (!(sum > 0.0))
  {
    row.emplace_back(s, 1.0);
    return;
  }
  for (int k = 0; k < 3; ++k)
  {
    if (corners[k] >= 0 && weights[k] > 0.0)
    {
      row.emplace_back(corners[k], weights[k] / sum);
    }
  }
}

/// The prolongation from the coarse graph to g's rows.
LevelMatrix ProlongationOf(const PointGraph& g, const PointGraph& c, const std::vector<Index>& coarse,
  const std::vector<Index>& region, int threads)
{
  const Index n = g.Rows();
  std::vector<std::array<std::pair<Index, double>, 3>> rows(n);
  std::vector<std::uint8_t> sizes(n);
  ParallelFor(n, threads, [&](std::int64_t b, std::int64_t e) {
    std::vector<std::pair<Index, double>> row;
    for (std::int64_t i = b; i < e; ++i)
    {
      if (coarse[i] >= 0)
      {
        row.assign(1, { coarse[i], 1.0 });
      }
      else
      {
        ProlongationRow(c, region[i], &g.Points[3 * i], row);
      }
      sizes[i] = static_cast<std::uint8_t>(row.size());
      std::copy(row.begin(), row.end(), rows[i].begin());
    }
  });
  LevelMatrix p;
  p.Offsets.resize(static_cast<std::size_t>(n) + 1);
  p.Offsets[0] = 0;
  for (Index i = 0; i < n; ++i)
  {
    p.Offsets[i + 1] = p.Offsets[i] + sizes[i];
  }
  p.Columns.resize(p.Offsets[n]);
  p.Values.resize(p.Offsets[n]);
  for (Index i = 0; i < n; ++i)
  {
    for (int k = 0; k < sizes[i]; ++k)
    {
      p.Columns[p.Offsets[i] + k] = rows[i][k].first;
      p.Values[p.Offsets[i] + k] = rows[i][k].second;
    }
  }
  return p;
}

} // namespace

/// The transpose of a (rows x columns) matrix stored without diagonal.
LevelMatrix Transposed(const LevelMatrix& a, Index columns)
{
  const Index n = static_cast<Index>(a.Offsets.size() - 1);
  LevelMatrix t;
  t.Offsets.assign(static_cast<std::size_t>(columns) + 1, 0);
  for (const Index c : a.Columns)
  {
    ++t.Offsets[c + 1];
  }
  for (Index c = 0; c < columns; ++c)
  {
    t.Offsets[c + 1] += t.Offsets[c];
  }
  std::vector<std::int64_t> next(t.Offsets.begin(), t.Offsets.end() - 1);
  t.Columns.resize(a.Columns.size());
  t.Values.resize(a.Values.size());
  for (Index i = 0; i < n; ++i)
  {
    for (std::int64_t k = a.Offsets[i]; k < a.Offsets[i + 1]; ++k)
    {
      const std::int64_t at = next[a.Columns[k]]++;
      t.Columns[at] = i;
      t.Values[at] = a.Values[k];
    }
  }
  return t;
}

SurfaceHierarchy::SurfaceHierarchy(
  Index rows, const std::int64_t* offsets, const Index* neighbors, const double* points, int numThreads)
{
  const int threads = ResolveThreadCount(numThreads);
  FineOrder = LocalityOrder(rows, offsets, neighbors);
  PointGraph g;
  ShiftedLaplacianProblem graph;
  graph.Rows = rows;
  graph.Offsets = offsets;
  graph.Neighbors = neighbors;
  graph.NumberOfThreads = threads;
  LargeVector<std::uint8_t> none;
  FinePosition = detail::RenumberEntries(graph, FineOrder.data(), [](Index) { return true; },
    [](std::int64_t) { return std::uint8_t(0); }, g.Offsets, g.Neighbors, none);
  g.Points.resize(3 * static_cast<std::size_t>(rows));
  for (Index i = 0; i < rows; ++i)
  {
    std::copy_n(points + 3 * static_cast<std::int64_t>(FineOrder[i]), 3, &g.Points[3 * i]);
  }
  Sizes.push_back(rows);
  while (g.Rows() > CoarsestRows)
  {
    Index count = 0;
    const std::vector<Index> coarse = Samples(g, count);
    if (count > MostKept * g.Rows())
    {
      break;
    }
    const std::vector<Index> region = NearestSamples(g, coarse, threads);
    PointGraph c = CoarseGraph(g, coarse, region, count, threads);
    Prolongations.push_back(ProlongationOf(g, c, coarse, region, threads));
    Restrictions.push_back(Transposed(Prolongations.back(), count));
    Sizes.push_back(count);
    g = std::move(c);
  }
}

} // namespace beltrami
