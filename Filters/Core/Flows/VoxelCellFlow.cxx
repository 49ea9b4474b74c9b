#include "Flows/NoiseEstimation.h"
#include "Flows/VoxelKernels.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <numeric>
#include <vector>

namespace beltrami
{

namespace
{

// ---------------------------------------------------------------------------
// Voxel cells of a lattice (sparse active voxels): the same tetrahedra and
// weights as the dense grid, on the cells present.  Set-up: the points of
// the cells renumbered in lattice order (z, y, x) inside the kernel, the
// cells in that order cut into runs along x (whose corners are then runs of
// consecutive points), and per point its neighbour up and down each of the
// 7 edge directions.  Each step: the state gathered into that order; each
// run's tetrahedra through KuhnCellRow and its weights and masses added
// row by row, as the grid's cell rows (the threads take chunks of cell
// planes, the even chunks then the odd ones: no two threads add into one
// point, and every sum has one order, so results do not depend on the
// thread count); then per point K u from its 14 neighbours and the
// velocity as the grid's rows, scattered back to the caller's numbering.

/// (K x)_i, sum_j c_ij (where diagonal is not null) and sum_j max(c_ij, 0)
/// (in the weights' precision, as StiffnessRow) for points i in [first,
/// first + n) of voxel cells: per direction d and point (7 arrays of
/// size each) the neighbour up and down (the point itself where there is
/// no edge) and the index of the down edge's weight in `weights` (7 arrays of size + 1:
/// per direction each point's edge up, 0 where none, then a 0 that the
/// missing down edges read).  Without branches, so that it vectorizes
/// (with the indices direction by direction: GCC 12 does not vectorize
/// groups of 7).
template <int NC, typename Real, bool WithDiagonal>
BELTRAMI_ALWAYS_INLINE inline void StencilLoop(std::int64_t first, std::int64_t n, std::int64_t size,
  const double* __restrict x, const Index* __restrict upper, const Index* __restrict lower,
  const Index* __restrict lowerWeight, const Real* __restrict weights, double* __restrict kx,
  double* __restrict diagonal, double* __restrict positive)
{
  for (std::int64_t i = first; i < first + n; ++i)
  {
    double dg = 0.0, sum[NC] = {};
    Real ps = 0;
#pragma GCC unroll 7
    for (int d = 0; d < 7; ++d)
    {
      const std::int64_t u = upper[d * size + i], l = lower[d * size + i];
      const Real wu = weights[d * (size + 1) + i], wl = weights[lowerWeight[d * size + i]];
      const double cu = wu, cl = wl;
#pragma GCC unroll 8
      for (int m = 0; m < NC; ++m)
      {
        const double xi = x[i * NC + m];
        sum[m] += cu * (xi - x[u * NC + m]) + cl * (xi - x[l * NC + m]);
      }
      if constexpr (WithDiagonal)
      {
        dg += cu + cl;
      }
      ps += std::max(wu, Real(0)) + std::max(wl, Real(0));
    }
#pragma GCC unroll 8
    for (int m = 0; m < NC; ++m)
    {
      kx[(i - first) * NC + m] = sum[m];
    }
    if constexpr (WithDiagonal)
    {
      diagonal[i - first] = dg;
    }
    positive[i - first] = ps;
  }
}

/// StencilLoop, without the diagonal where it is null.
template <int NC, typename Real>
CLONES void StencilRows(std::int64_t first, std::int64_t n, std::int64_t size, const double* __restrict x,
  const Index* __restrict upper, const Index* __restrict lower, const Index* __restrict lowerWeight,
  const Real* __restrict weights, double* __restrict kx, double* __restrict diagonal, double* __restrict positive)
{
  if (diagonal)
  {
    StencilLoop<NC, Real, true>(first, n, size, x, upper, lower, lowerWeight, weights, kx, diagonal, positive);
  }
  else
  {
    StencilLoop<NC, Real, false>(first, n, size, x, upper, lower, lowerWeight, weights, kx, nullptr, positive);
  }
}

template <int NC, typename Real>
class VoxelCellDiscretization final : public SweepDiscretization
{
public:
  /// storeOperator: keep Mass, Speed, Diagonal and KU (the semi-implicit
  /// solver's); explicit steps are fused (FusedStep).
  VoxelCellDiscretization(Index size, const double* points, const std::uint8_t* fixed, const std::int64_t* baseOffsets,
    const Index* baseNeighbors, double gamma, int threads, bool storeOperator)
    : Points(points)
    , BaseOffsets(baseOffsets)
    , BaseNeighbors(baseNeighbors)
  {
    Allocate(size, NC, gamma, threads, storeOperator);
    Fixed.assign(Size, 0);
    for (Index i = 0; fixed && i < Size; ++i)
    {
      Fixed[i] = fixed[i] != 0;
    }
  }

  /// The lattice of `corners`; false where the cells are not one.
  bool SetUp(const std::vector<Index>& corners)
  {
    const std::int64_t cells = static_cast<std::int64_t>(corners.size() / 8);
    double spacing[3];
    std::vector<std::int64_t> cellKey;
    if (cells == 0 || !Lattice(corners, spacing, cellKey))
    {
      return false;
    }
    MakeKuhnShapes(spacing, Shapes, CornerMass);
    const std::vector<Index> rank = Renumber(corners, cellKey);
    if (7 * (static_cast<double>(Active) + 1) >= 2147483647.0)
    {
      return false;
    }
    std::vector<Index> v;
    std::vector<std::int64_t> sortedKey;
    SortCells(corners, cellKey, rank, v, sortedKey);
    if (!Neighbours(v))
    {
      return false;
    }
    MakeRuns(v, sortedKey);
    // Base masses (the indicator's reference) and fixed flags, in lattice order.
    BaseMass.assign(Active, 0.0);
    for (std::int64_t c = 0; c < cells; ++c)
    {
      for (int k = 0; k < 8; ++k)
      {
        BaseMass[v[8 * c + k]] += CornerMass[k];
      }
    }
    ActiveFixed.resize(Active);
    for (Index a = 0; a < Active; ++a)
    {
      ActiveFixed[a] = Fixed[Perm[a]];
    }
    for (Index i = 0; i < Size; ++i)
    {
      Fixed[i] = Fixed[i] || rank[i] < 0; // in no cell: kept
    }
    Weights.assign(7 * (static_cast<std::size_t>(Active) + 1), Real(0)); // (a zero after each direction's)
    Masses.assign(Active, Real(0));
    State.resize(static_cast<std::size_t>(Active) * NC);
    return true;
  }

  double EstimateNoise(const double* values) const override
  {
    return EstimateGraphNoise(Size, BaseOffsets, BaseNeighbors, Points, Components, values, Fixed.data(), nullptr);
  }

  void ProbeSigns(std::size_t begin, std::size_t end, UninitializedVector<double>& b) const override
  {
    PositionProbeSigns(Components, Points, LengthScale, begin, end, b);
  }

  void Apply(const double* x, double* y, bool) override
  {
    ApplyStencil(x, y);
  }

private:
  /// One pass: what Output says, and the figures.
  void Sweep(const double* u) override
  {
    Gather(u, State.data());
    AddCells();
    std::vector<double> blockRate((Active + PointsPerBlock - 1) / PointsPerBlock), blockArea(blockRate.size());
    ParallelFor(static_cast<std::int64_t>(blockRate.size()), Threads, [&](std::int64_t b, std::int64_t e) {
      ScratchLease lease(Scratch, static_cast<std::size_t>(2 * NC + 4) * PointsPerBlock);
      for (std::int64_t block = b; block < e; ++block)
      {
        EmitPoints(block, lease.data(), blockRate[block], blockArea[block]);
      }
    }, {}, 0, 1);
    MaxRate = blockRate.empty() ? 0.0 : *std::max_element(blockRate.begin(), blockRate.end());
    Area = std::accumulate(blockArea.begin(), blockArea.end(), 0.0);
  }

  /// y = K x (the caller's numbering).
  void ApplyStencil(const double* x, double* y)
  {
    Input.resize(static_cast<std::size_t>(Active) * NC); // (kept: the solver applies K every iteration)
    Gather(x, Input.data());
    std::fill(y, y + static_cast<std::size_t>(Size) * NC, 0.0); // (points in no cell: no edges)
    const std::int64_t blocks = (Active + PointsPerBlock - 1) / PointsPerBlock;
    ParallelFor(blocks, Threads, [&](std::int64_t b, std::int64_t e) {
      ScratchLease lease(Scratch, static_cast<std::size_t>(NC + 1) * PointsPerBlock);
      for (std::int64_t block = b; block < e; ++block)
      {
        const std::int64_t first = block * PointsPerBlock, n = std::min<std::int64_t>(PointsPerBlock, Active - first);
        double* kx = lease.data();
        PointStiffness(Input.data(), first, n, kx, nullptr, kx + NC * PointsPerBlock);
        for (std::int64_t k = 0; k < n; ++k)
        {
          std::copy(kx + k * NC, kx + (k + 1) * NC, y + static_cast<std::size_t>(Perm[first + k]) * NC);
        }
      }
    }, {}, 0, 1);
  }

  struct Run
  {
    Index Corner[8]; // the corners of its first cell (lattice order); of cell t: + t
    std::int64_t Length = 1;
  };

  static constexpr std::int64_t PlanesPerChunk = 4;
  static constexpr std::int64_t PointsPerBlock = 1024;

  /// Checks that the cells are axis-aligned boxes of one spacing (every
  /// corner where the spacing puts it, to 1e-6 of a step); their spacing,
  /// the lattice's extent (Extent) and each cell's key (its corner 0's
  /// lattice index, x fastest).
  bool Lattice(const std::vector<Index>& corners, double* spacing, std::vector<std::int64_t>& cellKey)
  {
    const std::int64_t cells = static_cast<std::int64_t>(corners.size() / 8);
    double origin[3] = { HUGE_VAL, HUGE_VAL, HUGE_VAL };
    for (const Index id : corners)
    {
      if (id < 0 || id >= Size)
      {
        return false;
      }
    }
    for (int a = 0; a < 3; ++a)
    {
      spacing[a] = Points[3 * static_cast<std::size_t>(corners[1 << a]) + a] - Points[3 * static_cast<std::size_t>(corners[0]) + a];
      if (!(spacing[a] > 0.0) || !std::isfinite(spacing[a]))
      {
        return false;
      }
    }
    for (std::int64_t c = 0; c < cells; ++c)
    {
      const double* p0 = Points + 3 * static_cast<std::size_t>(corners[8 * c]);
      for (int k = 0; k < 8; ++k)
      {
        for (int a = 0; a < 3; ++a)
        {
          const double expected = p0[a] + ((k >> a) & 1) * spacing[a];
          if (!(std::abs(Points[3 * static_cast<std::size_t>(corners[8 * c + k]) + a] - expected) <= 1e-6 * spacing[a]))
          {
            return false;
          }
        }
      }
      for (int a = 0; a < 3; ++a)
      {
        origin[a] = std::min(origin[a], p0[a]);
      }
    }
    std::vector<std::int64_t> lattice(3 * cells);
    for (std::int64_t c = 0; c < cells; ++c)
    {
      for (int a = 0; a < 3; ++a)
      {
        lattice[3 * c + a] =
          std::llround((Points[3 * static_cast<std::size_t>(corners[8 * c]) + a] - origin[a]) / spacing[a]);
        Extent[a] = std::max(Extent[a], lattice[3 * c + a] + 2); // (the cell's far corner)
      }
    }
    if (static_cast<double>(Extent[0]) * Extent[1] * Extent[2] > 9e18)
    {
      return false;
    }
    cellKey.resize(cells);
    for (std::int64_t c = 0; c < cells; ++c)
    {
      cellKey[c] = (lattice[3 * c + 2] * Extent[1] + lattice[3 * c + 1]) * Extent[0] + lattice[3 * c];
    }
    return true;
  }

  /// The points of the cells in lattice order (Perm, Active; a cell's
  /// corner keys follow from its corner 0's); returns each point's place
  /// in that order (-1: in no cell).
  std::vector<Index> Renumber(const std::vector<Index>& corners, const std::vector<std::int64_t>& cellKey)
  {
    std::vector<std::int64_t> pointKey(Size, -1);
    for (std::size_t c = 0; c < cellKey.size(); ++c)
    {
      for (int k = 0; k < 8; ++k)
      {
        pointKey[corners[8 * c + k]] = cellKey[c] + (k & 1) + Extent[0] * ((k >> 1 & 1) + Extent[1] * (k >> 2));
      }
    }
    for (Index i = 0; i < Size; ++i)
    {
      if (pointKey[i] >= 0)
      {
        Perm.push_back(i);
      }
    }
    std::sort(Perm.begin(), Perm.end(), [&](Index a, Index b) { return pointKey[a] < pointKey[b]; });
    Active = static_cast<Index>(Perm.size());
    std::vector<Index> rank(Size, -1);
    for (Index a = 0; a < Active; ++a)
    {
      rank[Perm[a]] = a;
    }
    return rank;
  }

  /// The cells sorted by key, with their corners renumbered (v, 8 each)
  /// and their keys.
  static void SortCells(const std::vector<Index>& corners, const std::vector<std::int64_t>& cellKey,
    const std::vector<Index>& rank, std::vector<Index>& v, std::vector<std::int64_t>& sortedKey)
  {
    const std::int64_t cells = static_cast<std::int64_t>(cellKey.size());
    std::vector<std::int64_t> order(cells);
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](std::int64_t a, std::int64_t b) { return cellKey[a] < cellKey[b]; });
    v.resize(8 * static_cast<std::size_t>(cells));
    sortedKey.resize(cells);
    for (std::int64_t c = 0; c < cells; ++c)
    {
      for (int k = 0; k < 8; ++k)
      {
        v[8 * c + k] = rank[corners[8 * order[c] + k]];
      }
      sortedKey[c] = cellKey[order[c]];
    }
  }

  /// The stencil (see StencilRows) of the renumbered cells v; false where
  /// two cells disagree on a neighbour (they do not share their corners).
  bool Neighbours(const std::vector<Index>& v)
  {
    Upper.assign(7 * static_cast<std::size_t>(Active), -1);
    Lower.assign(7 * static_cast<std::size_t>(Active), -1);
    for (std::size_t c = 0; c < v.size(); c += 8)
    {
      for (int e = 0; e < KuhnCell::Edges; ++e)
      {
        const int d = (Kuhn.Upper[e] & ~Kuhn.Lower[e]) - 1;
        const Index a = v[c + Kuhn.Lower[e]], b = v[c + Kuhn.Upper[e]];
        Index& up = Upper[static_cast<std::size_t>(d) * Active + a];
        Index& down = Lower[static_cast<std::size_t>(d) * Active + b];
        if ((up >= 0 && up != b) || (down >= 0 && down != a))
        {
          return false;
        }
        up = b;
        down = a;
      }
    }
    LowerWeight.resize(Lower.size());
    for (int d = 0; d < 7; ++d)
    {
      for (Index a = 0; a < Active; ++a)
      {
        const std::size_t k = static_cast<std::size_t>(d) * Active + a;
        LowerWeight[k] = static_cast<Index>(WeightIndex(d, Lower[k] < 0 ? Active : Lower[k]));
        Upper[k] = Upper[k] < 0 ? a : Upper[k];
        Lower[k] = Lower[k] < 0 ? a : Lower[k];
      }
    }
    // Runs of points whose every neighbour index and weight index goes on
    // by one (a missing down edge's weight: the same 0), from the point
    // before: their stencil is the grid's rows (StiffnessRow, no gathers).
    Continues.assign(Active, 0);
    for (Index a = 1; a < Active; ++a)
    {
      bool runs = true;
      for (int d = 0; d < 7 && runs; ++d)
      {
        const std::size_t k = static_cast<std::size_t>(d) * Active + a;
        const Index zero = static_cast<Index>(WeightIndex(d, Active));
        runs = Upper[k] == Upper[k - 1] + 1 && Lower[k] == Lower[k - 1] + 1 &&
          (LowerWeight[k] == LowerWeight[k - 1] + 1 || (LowerWeight[k] == zero && LowerWeight[k - 1] == zero));
      }
      Continues[a] = runs;
    }
    ZeroWeights.assign(PointsPerBlock, Real(0));
    return true;
  }

  /// The sorted cells v (keys sortedKey) cut into runs along x whose corners
  /// are runs of consecutive points, and the runs into chunks of planes.
  void MakeRuns(const std::vector<Index>& v, const std::vector<std::int64_t>& sortedKey)
  {
    const std::int64_t cells = static_cast<std::int64_t>(sortedKey.size());
    std::int64_t chunk = -1;
    for (std::int64_t c = 0; c < cells; ++c)
    {
      bool continues = c > 0 && sortedKey[c] == sortedKey[c - 1] + 1 &&
        sortedKey[c] / Extent[0] == sortedKey[c - 1] / Extent[0];
      for (int k = 0; continues && k < 8; ++k)
      {
        continues = v[8 * c + k] == v[8 * (c - 1) + k] + 1;
      }
      if (continues)
      {
        ++Runs.back().Length;
        continue;
      }
      const std::int64_t plane = sortedKey[c] / (Extent[0] * Extent[1]) / PlanesPerChunk;
      for (; chunk < plane; ++chunk)
      {
        ChunkStart.push_back(static_cast<std::int64_t>(Runs.size()));
      }
      Run run;
      std::copy(v.begin() + 8 * c, v.begin() + 8 * c + 8, run.Corner);
      Runs.push_back(run);
    }
    for (const Run& run : Runs)
    {
      LongestRun = std::max(LongestRun, run.Length);
    }
    ChunkStart.push_back(static_cast<std::int64_t>(Runs.size()));
  }

  /// The caller's values x in lattice order.
  void Gather(const double* x, double* out) const
  {
    ParallelFor(Active, Threads, [&](std::int64_t b, std::int64_t e) {
      for (std::int64_t a = b; a < e; ++a)
      {
        std::copy(x + static_cast<std::size_t>(Perm[a]) * NC, x + static_cast<std::size_t>(Perm[a]) * NC + NC, out + a * NC);
      }
    });
  }

  /// The cells' weights and masses into Weights and Masses, run by run.
  void AddCells()
  {
    ParallelFor(Active, Threads, [&](std::int64_t b, std::int64_t e) {
      std::fill(Masses.begin() + b, Masses.begin() + e, Real(0));
      for (int d = 0; d < 7; ++d)
      {
        std::fill(Weights.begin() + d * (Active + 1) + b, Weights.begin() + d * (Active + 1) + e, Real(0));
      }
    });
    const std::int64_t chunks = static_cast<std::int64_t>(ChunkStart.size()) - 1;
    for (int phase = 0; phase < 2; ++phase)
    {
      ParallelFor((chunks + 1 - phase) / 2, Threads, [&](std::int64_t b, std::int64_t e) {
        std::vector<Real> edges(KuhnCell::Edges * LongestRun), masses(8 * LongestRun);
        for (std::int64_t k = b; k < e; ++k)
        {
          const std::int64_t chunk = 2 * k + phase;
          for (std::int64_t r = ChunkStart[chunk]; r < ChunkStart[chunk + 1]; ++r)
          {
            AddRun(Runs[r], edges.data(), masses.data());
          }
        }
      }, {}, 0, 1);
    }
  }

  /// A run's tetrahedra (its corners' values are rows of State) through
  /// KuhnCellRow, its sums into the points' rows.
  void AddRun(const Run& run, Real* edges, Real* masses)
  {
    const std::int64_t n = run.Length;
    const double* u = State.data();
    const Index* v = run.Corner;
    KuhnCellRow<NC, Real>(n, u + v[0] * NC, u + v[1] * NC, u + v[2] * NC, u + v[3] * NC, u + v[4] * NC,
      u + v[5] * NC, u + v[6] * NC, u + v[7] * NC, Shapes, edges, masses);
    // Rows of a few cells (thin active regions) inline: a call per row
    // would cost more than its additions.
    const auto add = [n](const Real* from, Real* to) {
      if (n >= 8)
      {
        AddRow(n, from, to);
        return;
      }
      for (std::int64_t t = 0; t < n; ++t)
      {
        to[t] += from[t];
      }
    };
    for (int c = 0; c < 8; ++c)
    {
      add(masses + c * n, Masses.data() + v[c]);
    }
    for (int e = 0; e < KuhnCell::Edges; ++e)
    {
      const int d = (Kuhn.Upper[e] & ~Kuhn.Lower[e]) - 1;
      add(edges + e * n, Weights.data() + WeightIndex(d, v[Kuhn.Lower[e]]));
    }
  }

  /// (K x), sum_j c_ij (diagonal not null) and sum_j max(c_ij, 0) of points
  /// [first, first + n) (lattice order; x too; n <= PointsPerBlock): runs of points whose
  /// neighbours are runs (Continues) as the grid's rows, the others
  /// through the stencil's indices.
  void PointStiffness(const double* x, std::int64_t first, std::int64_t n, double* kx, double* diagonal,
    double* positive) const
  {
    constexpr std::int64_t ShortestRun = 16; // (the points between runs: in one gathering loop)
    const std::int64_t end = first + n;
    const auto gather = [&](std::int64_t s, std::int64_t e) {
      const std::int64_t o = s - first;
      StencilRows<NC, Real>(s, e - s, Active, x, Upper.data(), Lower.data(), LowerWeight.data(), Weights.data(),
        kx + o * NC, diagonal ? diagonal + o : nullptr, positive + o);
    };
    std::int64_t done = first;
    for (std::int64_t s = first, e = first + 1; s < end; s = e, e = s + 1)
    {
      while (e < end && Continues[e])
      {
        ++e;
      }
      if (e - s < ShortestRun)
      {
        continue;
      }
      if (done < s)
      {
        gather(done, s);
      }
      done = e;
      const std::int64_t o = s - first;
      const double* xu[8];
      const double* xd[8];
      const Real* up[8];
      const Real* down[8];
      for (int d = 0; d < 7; ++d)
      {
        const std::size_t k = static_cast<std::size_t>(d) * Active + s;
        const std::int64_t zero = WeightIndex(d, Active);
        xu[d + 1] = x + static_cast<std::int64_t>(Upper[k]) * NC;
        xd[d + 1] = x + static_cast<std::int64_t>(Lower[k]) * NC;
        up[d + 1] = Weights.data() + WeightIndex(d, s);
        down[d + 1] = LowerWeight[k] == zero ? ZeroWeights.data() : Weights.data() + LowerWeight[k];
      }
      StiffnessRow<NC, Real>(
        e - s, x + s * NC, xu, xd, up, down, kx + o * NC, diagonal ? diagonal + o : nullptr, positive + o);
    }
    if (done < end)
    {
      gather(done, end);
    }
  }

  /// Block `block` of the points (lattice order): K u, the velocity, the
  /// largest rate and the volume, written to the caller's numbering.
  void EmitPoints(std::int64_t block, double* scratch, double& rate, double& area)
  {
    const std::int64_t first = block * PointsPerBlock, n = std::min<std::int64_t>(PointsPerBlock, Active - first);
    double* ku = scratch;
    double* velocity = ku + NC * PointsPerBlock;
    double* diagonal = velocity + NC * PointsPerBlock;
    double* positive = diagonal + PointsPerBlock;
    double* speed = positive + PointsPerBlock;
    double* rates = speed + PointsPerBlock;
    PointStiffness(State.data(), first, n, ku, StoreOperator ? diagonal : nullptr, positive);
    const Real* mass = Masses.data() + first;
    for (std::int64_t k = 0; k < n; ++k)
    {
      const double m = mass[k];
      speed[k] = m > 0.0 && Gamma != 1.0 ? SpeedOf(BaseMass[first + k] / m) : 1.0;
    }
    const double* x = State.data() + first * NC;
    std::uint8_t* fixed = ActiveFixed.data() + first;
    switch (Output)
    {
      case RowOutput::Velocity:
        VelocityRow<NC, Real, RowOutput::Velocity>(n, mass, speed, fixed, ku, positive, x, 0.0, velocity, rates, rate,
          area);
        break;
      case RowOutput::Step:
        VelocityRow<NC, Real, RowOutput::Step>(n, mass, speed, fixed, ku, positive, x, StepSize, velocity, rates, rate,
          area);
        break;
      case RowOutput::None:
        VelocityRow<NC, Real, RowOutput::None>(n, mass, speed, fixed, ku, positive, x, 0.0, nullptr, rates, rate, area);
        break;
    }
    double* out = Output == RowOutput::Velocity ? Velocity.data() : Next; // (the step, or nothing)
    for (std::int64_t k = 0; k < n; ++k)
    {
      const std::size_t i = static_cast<std::size_t>(Perm[first + k]);
      if (out)
      {
        std::copy(velocity + k * NC, velocity + (k + 1) * NC, out + i * NC);
      }
      if (Fixed[i] != ActiveFixed[first + k]) // (a write only where it changes: the flags of
      {                                       // 64 points share a cache line between the threads)
        Fixed[i] = ActiveFixed[first + k];
      }
      if (StoreOperator)
      {
        std::copy(ku + k * NC, ku + (k + 1) * NC, KU.data() + i * NC);
        Mass[i] = mass[k];
        Speed[i] = speed[k];
        Diagonal[i] = diagonal[k];
      }
    }
  }

  const double* Points;
  const std::int64_t* BaseOffsets;
  const Index* BaseNeighbors;
  std::int64_t Extent[3] = { 0, 0, 0 }; // of the lattice, in points
  Index Active = 0;                     // points in a cell
  std::vector<Index> Perm;              // lattice order -> the caller's point
  std::vector<Run> Runs;                // in lattice order
  std::int64_t LongestRun = 1;
  std::vector<std::int64_t> ChunkStart; // first run of each chunk of PlanesPerChunk cell planes
  std::vector<Index> Upper, Lower, LowerWeight; // 7 x Active (direction-major): see StencilRows
  /// The slot in Weights of point a's edge up direction d (a = Active: the
  /// 0 that missing down edges read).
  std::int64_t WeightIndex(int d, std::int64_t a) const { return d * (static_cast<std::int64_t>(Active) + 1) + a; }
  std::vector<std::uint8_t> Continues;          // per point: its stencil goes on from the point before's
  std::vector<Real> ZeroWeights;                // the missing down edges' weights of a run
  std::vector<double> BaseMass;
  std::vector<std::uint8_t> ActiveFixed;
  LargeVector<double> State;            // the state in lattice order
  std::vector<double> Input;            // Apply's x in lattice order
  LargeVector<Real> Weights, Masses;    // 7 x (Active + 1): per direction, each point's and a zero; Active
  KuhnShapes<Real> Shapes;
  double CornerMass[8];
  ScratchPool Scratch;
};

} // namespace

std::unique_ptr<detail::FlowDiscretization> detail::MakeVoxelCellDiscretization(Index size, const double* points,
  int components, const std::vector<Index>& corners, const std::uint8_t* fixed, const std::int64_t* baseOffsets,
  const Index* baseNeighbors, double gamma, int threads, bool storeOperator)
{
  return WithCount<6>(components, [&](auto nc) -> std::unique_ptr<FlowDiscretization> {
    constexpr int NC = decltype(nc)::value;
    auto disc = std::make_unique<VoxelCellDiscretization<NC, VoxelReal>>(
      size, points, fixed, baseOffsets, baseNeighbors, gamma, threads, storeOperator);
    if (!disc->SetUp(corners))
    {
      return nullptr;
    }
    return disc;
  });
}

} // namespace beltrami
