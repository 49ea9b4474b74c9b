#include "Flows/GraphFlowDiscretization.h"
#include "Flows/NoiseEstimation.h"

#include "Mesh/Tetrahedra.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <memory>
#include <numeric>

namespace beltrami
{

namespace
{

using namespace detail;

/// The edges of a Kuhn-split cell: the 19 corner pairs (lower, upper) with
/// lower's axes a subset of upper's (corner bit a = step along axis a), and
/// per tetrahedron (path) the slot of each of its six edges.
struct KuhnCell
{
  static constexpr int Edges = 19;
  int Lower[Edges], Upper[Edges];
  int Corner[6][4]; // corners of path p: 0, one axis, two axes, 7
  int Slot[6][6];   // edge slot of tetrahedron edge e of path p

  KuhnCell()
  {
    int slot[8][8];
    int e = 0;
    for (int upper = 1; upper < 8; ++upper)
    {
      for (int lower = 0; lower < 8; ++lower)
      {
        if (lower != upper && (lower & upper) == lower)
        {
          Lower[e] = lower;
          Upper[e] = upper;
          slot[lower][upper] = e++;
        }
      }
    }
    for (int p = 0; p < 6; ++p)
    {
      Corner[p][0] = 0;
      Corner[p][1] = 1 << KuhnPaths[p][0];
      Corner[p][2] = Corner[p][1] | (1 << KuhnPaths[p][1]);
      Corner[p][3] = 7;
      for (int k = 0; k < 6; ++k)
      {
        Slot[p][k] = slot[Corner[p][TetrahedronEdges[k][0]]][Corner[p][TetrahedronEdges[k][1]]];
      }
    }
  }
};

/// The six Kuhn tetrahedra of n cells of a row from their Gram matrices
/// (gram[(6 p + q) n + j]: entry q = 11, 22, 33, 12, 13, 23 of path p) into
/// the cells' 19 edge weights (edges[s n + j]) and 8 corner masses
/// (masses[c n + j], a quarter of each tetrahedron's volume).  Degenerate
/// tetrahedra add nothing.  Compiled like TriangleRow.
CLONES void TetrahedronRow(std::int64_t n, const KuhnCell& cell, const double* __restrict gram,
  double* __restrict edges, double* __restrict masses)
{
  std::fill(edges, edges + KuhnCell::Edges * n, 0.0);
  std::fill(masses, masses + 8 * n, 0.0);
  for (int p = 0; p < 6; ++p)
  {
    const double* g = gram + 6 * p * n;
    double* w[6];
    for (int k = 0; k < 6; ++k)
    {
      w[k] = edges + cell.Slot[p][k] * n;
    }
    double* m[4];
    for (int v = 0; v < 4; ++v)
    {
      m[v] = masses + cell.Corner[p][v] * n;
    }
#pragma GCC ivdep // the slots of one tetrahedron are distinct rows
    for (std::int64_t j = 0; j < n; ++j)
    {
      const TetrahedronTerms t =
        TetrahedronFromGram(g[j], g[n + j], g[2 * n + j], g[3 * n + j], g[4 * n + j], g[5 * n + j]);
      for (int k = 0; k < 6; ++k)
      {
        w[k][j] += t.Weights[k];
      }
      const double quarter = 0.25 * t.Volume;
      for (int v = 0; v < 4; ++v)
      {
        m[v][j] += quarter;
      }
    }
  }
}

// ---------------------------------------------------------------------------
// 3D images: the voxel grid split into Kuhn tetrahedra (six per cell: the
// split of GridTetrahedra, section 2.8.2) without an explicit mesh.  Each
// step evaluates every tetrahedron once, from the Gram matrix of its edge
// vectors in R^(3+n) (base part from the spacing, fixed per tetrahedron
// shape; data part from the values), and sums its edge weights into seven
// weights per voxel - every Kuhn edge goes up in each coordinate, so the
// edges of a voxel are those to its neighbours at +x, +y, +x+y, +z, +x+z,
// +y+z, +x+y+z and back - and its volume into the lumped masses (1/4 to each
// corner).  Cell planes of one parity are summed in parallel, then those of
// the other: no two threads write the same voxel and the sums do not depend
// on the thread count.

template <int NC>
class VoxelDiscretization final : public FlowDiscretization
{
public:
  /// storeOperator: keep Mass, Speed, Diagonal and KU (the semi-implicit
  /// solver's); explicit steps need the velocity only (4 doubles per voxel
  /// less).
  double EstimateNoise(const double* values) const override { return EstimateVolumeNoise(Grid, NC, values); }

  VoxelDiscretization(const VoxelGrid& grid, const std::uint8_t* fixed, double gamma, int threads, bool storeOperator)
    : Grid(grid)
  {
    Gamma = gamma;
    Threads = threads;
    StoreOperator = storeOperator;
    Size = static_cast<Index>(grid.Width * grid.Height * grid.Depth);
    Components = NC;
    LengthScale = std::cbrt(grid.SpacingX * grid.SpacingY * grid.SpacingZ);
    AutomaticContrast = VolumeAutomaticContrast;
    // 0.1 on unit grids (limit about 0.12), scaled with the spacing.
    AutomaticTimeStep = 0.1 * 3.0 /
      (1.0 / (grid.SpacingX * grid.SpacingX) + 1.0 / (grid.SpacingY * grid.SpacingY) +
        1.0 / (grid.SpacingZ * grid.SpacingZ));
    Allocate();
    for (int d = 0; d < 8; ++d)
    {
      Offset[d] = (d & 1) + grid.Width * (((d >> 1) & 1) + grid.Height * ((d >> 2) & 1));
    }
    const double spacing[3] = { grid.SpacingX, grid.SpacingY, grid.SpacingZ };
    for (int p = 0; p < 6; ++p)
    {
      // Corners of path p: 0, Cell.Corner[p][1], Cell.Corner[p][2], 7.
      double e[3][3];
      for (int s = 0; s < 3; ++s)
      {
        for (int a = 0; a < 3; ++a)
        {
          e[s][a] = (Cell.Corner[p][s + 1] >> a & 1) * spacing[a];
        }
      }
      const auto dot = [](const double* x, const double* y) { return x[0] * y[0] + x[1] * y[1] + x[2] * y[2]; };
      BaseGram[p][0] = dot(e[0], e[0]);
      BaseGram[p][1] = dot(e[1], e[1]);
      BaseGram[p][2] = dot(e[2], e[2]);
      BaseGram[p][3] = dot(e[0], e[1]);
      BaseGram[p][4] = dot(e[0], e[2]);
      BaseGram[p][5] = dot(e[1], e[2]);
    }
    Weights.assign(7 * static_cast<std::size_t>(Size), 0.0);
    GraphMass.assign(Size, 0.0);
    const LargeVector<double> flat(static_cast<std::size_t>(Size) * NC, 0.0);
    Accumulate(flat.data());
    BaseMass = GraphMass;
    Fixed.assign(Size, 0);
    for (Index i = 0; i < Size; ++i)
    {
      Fixed[i] = (fixed && fixed[i]) || !(BaseMass[i] > 0.0);
    }
  }

  void Update(const double* u) override
  {
    Accumulate(u);
    const std::int64_t rows = Grid.Height * Grid.Depth;
    // Per row: the largest rate and the row's volume, summed in row order.
    std::vector<double> rowRate(rows), rowArea(rows);
    ParallelFor(rows, Threads, [&](std::int64_t b, std::int64_t e) {
      const std::size_t width = static_cast<std::size_t>(Grid.Width);
      ScratchLease buffer(Scratch, (StoreOperator ? 1 : NC + 2) * width);
      double* positive = buffer.data();
      for (std::int64_t r = b; r < e; ++r)
      {
        const std::int64_t first = r * Grid.Width;
        // K u and the diagonal into the operator's arrays, or into scratch.
        double* ku = StoreOperator ? KU.data() + first * NC : positive + width;
        double* diagonal = StoreOperator ? Diagonal.data() + first : ku + NC * width;
        StiffnessRow(u, r, ku, diagonal, positive);
        double rate = 0.0, area = 0.0;
        for (std::int64_t i = first; i < first + Grid.Width; ++i)
        {
          const double mass = GraphMass[i];
          const double speed = mass > 0.0 ? SpeedOf(BaseMass[i] / mass) : 1.0;
          if (StoreOperator)
          {
            Mass[i] = mass;
            Speed[i] = speed;
          }
          if (!(mass > 0.0))
          {
            Fixed[i] = 1; // lost its measure (degenerate graph elements)
          }
          const double f = !Fixed[i] ? speed / mass : 0.0;
          for (int k = 0; k < NC; ++k)
          {
            Velocity[i * NC + k] = f * ku[(i - first) * NC + k];
          }
          rate = std::max(rate, f * positive[i - first]);
          area += mass;
        }
        rowRate[r] = rate;
        rowArea[r] = area;
      }
    }, {}, 0, 4);
    MaxRate = *std::max_element(rowRate.begin(), rowRate.end());
    Area = std::accumulate(rowArea.begin(), rowArea.end(), 0.0); // in row order: thread-independent
  }

  void Apply(const double* x, double* y, bool) override
  {
    ParallelFor(Grid.Height * Grid.Depth, Threads, [&](std::int64_t b, std::int64_t e) {
      ScratchLease buffer(Scratch, 2 * static_cast<std::size_t>(Grid.Width));
      for (std::int64_t r = b; r < e; ++r)
      {
        StiffnessRow(x, r, y + r * Grid.Width * NC, buffer.data(), buffer.data() + Grid.Width);
      }
    }, {}, 0, 4);
  }

private:
  /// (K x)_i, sum_j c_ij and sum_j max(c_ij, 0) for the voxels of row r
  /// (= iz * Height + iy): Width values each (kx: Width * NC).  Interior
  /// voxels in one loop without tests over the seven weight arrays (the
  /// compiler vectorizes it), the others through Stiffness; the sums in
  /// the same order either way.
  void StiffnessRow(const double* x, std::int64_t r, double* __restrict kx, double* __restrict diagonal,
    double* __restrict positive) const
  {
    const std::int64_t iy = r % Grid.Height, iz = r / Grid.Height, first = r * Grid.Width;
    const bool inner = iy > 0 && iy + 1 < Grid.Height && iz > 0 && iz + 1 < Grid.Depth;
    const std::int64_t from = inner ? 1 : Grid.Width, to = inner ? Grid.Width - 1 : Grid.Width;
    for (std::int64_t ix = 0; ix < Grid.Width; ix = ix + 1 == from ? std::max(to, ix + 1) : ix + 1)
    {
      Stiffness(x, first + ix, ix, iy, iz, kx + ix * NC, diagonal[ix], positive[ix]);
    }
    const double* w[8];
    for (int d = 1; d < 8; ++d)
    {
      w[d] = WeightsOf(d) + first;
    }
    const double* xr = x + first * NC;
    for (std::int64_t ix = from; ix < to; ++ix)
    {
      double k[NC], dg = 0.0, ps = 0.0;
      for (int m = 0; m < NC; ++m)
      {
        k[m] = 0.0;
      }
      const double* xi = xr + ix * NC;
      for (int d = 1; d < 8; ++d)
      {
        const std::int64_t o = Offset[d];
        const double up = w[d][ix], down = w[d][ix - o];
        for (int m = 0; m < NC; ++m)
        {
          k[m] += up * (xi[m] - xi[o * NC + m]);
        }
        dg += up;
        ps += std::max(up, 0.0);
        for (int m = 0; m < NC; ++m)
        {
          k[m] += down * (xi[m] - xi[-o * NC + m]);
        }
        dg += down;
        ps += std::max(down, 0.0);
      }
      for (int m = 0; m < NC; ++m)
      {
        kx[ix * NC + m] = k[m];
      }
      diagonal[ix] = dg;
      positive[ix] = ps;
    }
  }

  /// (K x)_i, sum_j c_ij and sum_j max(c_ij, 0) over the 14 neighbours of
  /// voxel i = (ix, iy, iz).
  void Stiffness(const double* x, std::int64_t i, std::int64_t ix, std::int64_t iy, std::int64_t iz,
    double* kx, double& diagonal, double& positive) const
  {
    for (int k = 0; k < NC; ++k)
    {
      kx[k] = 0.0;
    }
    diagonal = positive = 0.0;
    const auto add = [&](double c, std::int64_t j) {
      for (int k = 0; k < NC; ++k)
      {
        kx[k] += c * (x[i * NC + k] - x[j * NC + k]);
      }
      diagonal += c;
      positive += std::max(c, 0.0);
    };
    const bool up[3] = { ix + 1 < Grid.Width, iy + 1 < Grid.Height, iz + 1 < Grid.Depth };
    const bool down[3] = { ix > 0, iy > 0, iz > 0 };
    if (up[0] && up[1] && up[2] && down[0] && down[1] && down[2])
    {
      for (int d = 1; d < 8; ++d) // inside: all 14 neighbours, no tests
      {
        add(WeightsOf(d)[i], i + Offset[d]);
        add(WeightsOf(d)[i - Offset[d]], i - Offset[d]);
      }
      return;
    }
    for (int d = 1; d < 8; ++d)
    {
      const bool dx = d & 1, dy = d & 2, dz = d & 4;
      if ((!dx || up[0]) && (!dy || up[1]) && (!dz || up[2]))
      {
        add(WeightsOf(d)[i], i + Offset[d]);
      }
      if ((!dx || down[0]) && (!dy || down[1]) && (!dz || down[2]))
      {
        const std::int64_t j = i - Offset[d];
        add(WeightsOf(d)[j], j);
      }
    }
  }

  /// The edge weights and lumped masses of the graph at u.
  void Accumulate(const double* u)
  {
    std::fill(Weights.begin(), Weights.end(), 0.0);
    std::fill(GraphMass.begin(), GraphMass.end(), 0.0);
    const std::int64_t planes = Grid.Depth - 1;
    for (int parity = 0; parity < 2; ++parity)
    {
      ParallelFor((planes - parity + 1) / 2, Threads, [&](std::int64_t b, std::int64_t e) {
        for (std::int64_t m = b; m < e; ++m)
        {
          AccumulatePlane(u, 2 * m + parity);
        }
      }, {}, 0, 1);
    }
  }

  void AccumulatePlane(const double* u, std::int64_t k)
  {
    const std::int64_t n = Grid.Width - 1; // cells per row
    ScratchLease buffer(Scratch, (36 + KuhnCell::Edges + 8) * static_cast<std::size_t>(n));
    double* gram = buffer.data();
    double* edges = gram + 36 * n;
    double* masses = edges + KuhnCell::Edges * n;
    for (std::int64_t j = 0; j + 1 < Grid.Height; ++j)
    {
      const std::int64_t first = (k * Grid.Height + j) * Grid.Width;
      const double* u0 = u + first * NC;
      for (int p = 0; p < 6; ++p)
      {
        // Edge vectors a, b, c of path p: u(corner) - u(corner 0).
        const double* ua = u0 + Offset[Cell.Corner[p][1]] * NC;
        const double* ub = u0 + Offset[Cell.Corner[p][2]] * NC;
        const double* uc = u0 + Offset[7] * NC;
        double* __restrict g = gram + 6 * p * n;
        const double* base = BaseGram[p];
        for (std::int64_t i = 0; i < n; ++i)
        {
          double aa = 0, bb = 0, cc = 0, ab = 0, ac = 0, bc = 0;
          for (int m = 0; m < NC; ++m)
          {
            const double o = u0[i * NC + m];
            const double a = ua[i * NC + m] - o, b = ub[i * NC + m] - o, c = uc[i * NC + m] - o;
            aa += a * a;
            bb += b * b;
            cc += c * c;
            ab += a * b;
            ac += a * c;
            bc += b * c;
          }
          g[i] = base[0] + aa;
          g[n + i] = base[1] + bb;
          g[2 * n + i] = base[2] + cc;
          g[3 * n + i] = base[3] + ab;
          g[4 * n + i] = base[4] + ac;
          g[5 * n + i] = base[5] + bc;
        }
      }
      TetrahedronRow(n, Cell, gram, edges, masses);
      for (int c = 0; c < 8; ++c)
      {
        double* __restrict to = &GraphMass[first + Offset[c]];
        const double* from = masses + c * n;
        for (std::int64_t i = 0; i < n; ++i)
        {
          to[i] += from[i];
        }
      }
      for (int e = 0; e < KuhnCell::Edges; ++e)
      {
        const int direction = Cell.Upper[e] & ~Cell.Lower[e];
        double* __restrict to = WeightsOf(direction) + first + Offset[Cell.Lower[e]];
        const double* from = edges + e * n;
        for (std::int64_t i = 0; i < n; ++i)
        {
          to[i] += from[i];
        }
      }
    }
  }

  VoxelGrid Grid;
  std::int64_t Offset[8];
  KuhnCell Cell;
  double BaseGram[6][6];
  ScratchPool Scratch; // per-thread row buffers, kept between steps
  /// The edge weights to the neighbour at +Offset[d], one array of Size
  /// per direction d = 1..7.
  LargeVector<double> Weights, GraphMass, BaseMass;

  double* WeightsOf(int d)
  {
    return Weights.data() + static_cast<std::size_t>(d - 1) * static_cast<std::size_t>(Size);
  }
  const double* WeightsOf(int d) const
  {
    return Weights.data() + static_cast<std::size_t>(d - 1) * static_cast<std::size_t>(Size);
  }
};

} // namespace

GraphFlowResult RunVolumeGraphFlow(const VoxelGrid& grid, int components, double* values,
  const std::uint8_t* fixed, const GraphFlowOptions& options, const ProgressCallback& progress)
{
  GraphFlowResult result;
  result.Error = CheckOptions(options, components, 6, "volumes");
  const double spacing[3] = { grid.SpacingX, grid.SpacingY, grid.SpacingZ };
  for (double s : spacing)
  {
    if (result.Error.empty() && (!(s > 0.0) || !std::isfinite(s)))
    {
      result.Error = "the voxel spacing must be positive and finite";
    }
  }
  if (result.Error.empty() && static_cast<double>(grid.Width) * grid.Height * grid.Depth > 2147483647.0)
  {
    result.Error = "volumes of more than 2^31 voxels are not supported";
  }
  if (!result.Error.empty() || grid.Width < 2 || grid.Height < 2 || grid.Depth < 2)
  {
    return result;
  }
  return WithCount<6>(components, [&](auto nc) { // kernels compiled per component count
    constexpr int NC = decltype(nc)::value;
    const bool store = options.Integration == GraphFlowIntegration::SemiImplicit;
    const auto make = [&]() {
      return std::make_unique<VoxelDiscretization<NC>>(grid, fixed, options.EdgeContrast, options.NumberOfThreads, store);
    };
    // A band of planes for the risk's probe (large volumes).
    const Index plane = static_cast<Index>(grid.Width * grid.Height);
    const ProbeWindow window = GridProbeWindow(static_cast<Index>(grid.Depth), plane, options,
      [&grid, fixed, &options, store, plane](Index first, Index count) -> std::unique_ptr<FlowDiscretization> {
        VoxelGrid band = grid;
        band.Depth = count;
        return std::make_unique<VoxelDiscretization<NC>>(band, fixed ? fixed + static_cast<std::size_t>(first) * plane : nullptr,
          options.EdgeContrast, options.NumberOfThreads, store);
      });
    return Integrate(make, values, options, progress, window);
  });
}

} // namespace beltrami
