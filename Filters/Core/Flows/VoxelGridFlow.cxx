#include "Flows/NoiseEstimation.h"
#include "Flows/VoxelKernels.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <memory>
#include <numeric>

namespace beltrami
{

namespace
{

/// The rows of the plane buffers a cell row's 27 sums (19 edges, then 8
/// corner masses) go to: per target its array (edge direction - 1, or 7:
/// the masses), the lower corner of its edges (the plane, row and x offset
/// of the voxels) and the sums it gets at x offset 0 (First) and 1
/// (Second, or -1): the edges and masses of corners a cell apart along x
/// land in the same row, and are added in one pass (AddRowPair).
struct KuhnRowTargets
{
  static constexpr int Count = 18;
  int Array[Count]{}, Lower[Count]{}, First[Count]{}, Second[Count]{};

  constexpr KuhnRowTargets()
  {
    int t = 0;
    for (int e = 0; e < KuhnCell::Edges; ++e)
    {
      const int lower = Kuhn.Lower[e], direction = Kuhn.Upper[e] & ~lower;
      if (lower & 1)
      {
        continue; // (the Second of the edge at lower - 1)
      }
      Array[t] = direction - 1;
      Lower[t] = lower;
      First[t] = e;
      Second[t] = -1;
      for (int f = e + 1; f < KuhnCell::Edges; ++f)
      {
        if (Kuhn.Lower[f] == (lower | 1) && (Kuhn.Upper[f] & ~Kuhn.Lower[f]) == direction)
        {
          Second[t] = f;
        }
      }
      ++t;
    }
    for (int c = 0; c < 8; c += 2, ++t)
    {
      Array[t] = 7;
      Lower[t] = c;
      First[t] = KuhnCell::Edges + c;
      Second[t] = KuhnCell::Edges + c + 1;
    }
  }
};

constexpr KuhnRowTargets RowTargets{};

/// to[i] = (to[i] + a[i]) + b[i - 1], i <= n (a[n], b[-1]: none): two
/// rows of sums a cell apart, in the order of two AddRow calls.
template <typename Real>
CLONES void AddRowPair(std::int64_t n, const Real* __restrict a, const Real* __restrict b, Real* __restrict to)
{
  to[0] += a[0];
  for (std::int64_t i = 1; i < n; ++i)
  {
    to[i] = (to[i] + a[i]) + b[i - 1];
  }
  to[n] += b[n - 1];
}

/// AddRowPair into a row of zeros, without reading it.
template <typename Real>
CLONES void StoreRowPair(std::int64_t n, const Real* __restrict a, const Real* __restrict b, Real* __restrict to)
{
  to[0] = a[0];
  for (std::int64_t i = 1; i < n; ++i)
  {
    to[i] = a[i] + b[i - 1];
  }
  to[n] = b[n - 1];
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
// corner).
//
// One pass per step, streaming through the planes: the tetrahedra of cell
// plane k add to the weights and masses of voxel planes k and k + 1, held
// in three rolling plane buffers (k - 1, k, k + 1); after cell row (j, k) the
// voxel row (j, k) is complete and its velocity is evaluated at once, so no
// weight array of the volume's size is written or read (only the
// semi-implicit steps keep one, for their solver).  The threads take
// chunks of planes; each first evaluates the cell plane below its chunk.
// Every weight is summed in the same order (cell planes k - 1 then k, rows
// j - 1 then j) whatever the chunks: results do not depend on the thread
// count.  Explicit steps write the next state in the same pass
// (FusedStep), not a velocity.  Real: the precision of the tetrahedra and
// weights, single (twice the lanes per instruction; 1e-4 of a step's change
// in the worst case tested); the data, K u and the state stay in double.

template <int NC, typename Real>
class VoxelDiscretization final : public SweepDiscretization
{
public:
  /// storeOperator: keep Mass, Speed, Diagonal and KU and the weights (the
  /// semi-implicit solver's); explicit steps need the velocity only.
  /// piece (optional): the grid is a piece of a split grid (GridPiece).
  VoxelDiscretization(const VoxelGrid& grid, const std::uint8_t* fixed, double gamma, int threads, bool storeOperator,
    const GridPiece* piece = nullptr)
    : Grid(grid)
    , W(grid.Width)
    , H(grid.Height)
    , D(grid.Depth)
  {
    if (piece && piece->Split)
    {
      Piece = *piece;
      Split = piece->Split;
      Owned = OwnedRuns(*Split, H * D, W);
    }
    Allocate(static_cast<Index>(W * H * D), NC, gamma, threads, storeOperator);
    LengthScale = std::cbrt(grid.SpacingX * grid.SpacingY * grid.SpacingZ);
    AutomaticContrast = VolumeAutomaticContrast;
    // 0.1 on unit grids (limit about 0.12), scaled with the spacing.
    AutomaticTimeStep = 0.1 * 3.0 /
      (1.0 / (grid.SpacingX * grid.SpacingX) + 1.0 / (grid.SpacingY * grid.SpacingY) +
        1.0 / (grid.SpacingZ * grid.SpacingZ));
    for (int d = 0; d < 8; ++d)
    {
      Offset[d] = (d & 1) + W * (((d >> 1) & 1) + H * ((d >> 2) & 1));
    }
    const double spacing[3] = { grid.SpacingX, grid.SpacingY, grid.SpacingZ };
    MakeKuhnShapes(spacing, Shapes, CornerMass);
    // Weights of the volume (semi-implicit steps), each direction's array
    // after a zero margin of a plane and a row (the "down" neighbours of the
    // first plane and row are read there).
    PlaneSize = W * H;
    Margin = PlaneSize + W + 1;
    if (StoreOperator)
    {
      Weights.assign(7 * static_cast<std::size_t>(Margin + Size), Real(0));
    }
    Zeros.assign((W + 2) * NC, 0.0);
    Fixed.assign(Size, 0);
    for (Index i = 0; fixed && i < Size; ++i)
    {
      Fixed[i] = fixed[i] != 0;
    }
  }

  double EstimateNoise(const double* values) const override
  {
    return EstimateVolumeNoise(Grid, NC, values, Threads, Split ? &Piece : nullptr);
  }

  void ProbeSigns(std::size_t begin, std::size_t end, UninitializedVector<double>& b) const override
  {
    Split ? GridPieceProbeSigns(*this, Piece, W, H, D, b) : FlowDiscretization::ProbeSigns(begin, end, b);
  }

  bool SumsRows() const override { return true; }

  void Apply(const double* x, double* y, bool) override
  {
    ParallelFor(H * D, Threads, [&](std::int64_t b, std::int64_t e) {
      ScratchLease buffer(Scratch, static_cast<std::size_t>(W)); // (the sums of positive weights)
      for (std::int64_t r = b; r < e; ++r)
      {
        const Real* up[8];
        const Real* down[8];
        const std::int64_t first = r * W;
        for (int d = 1; d < 8; ++d)
        {
          up[d] = WeightsOf(d) + first;
          down[d] = WeightsOf(d) + first - Offset[d];
        }
        RowStiffness(x, r % H, r / H, up, down, y + first * NC, nullptr, buffer.data());
      }
    }, {}, 0, 4);
  }

private:
  static constexpr std::int64_t PlanesPerChunk = 16;
  std::vector<double> RowFigures[3]; // Sweep's per row: rates, volumes, sums

  /// One pass over the volume (what Output says).
  void Sweep(const double* u) override
  {
    // Per row, in row order (thread-independent sums): the largest rate,
    // the volume and (steps with RowSum) the row's sum (kept between
    // sweeps: fresh memory each step cost page faults).
    std::vector<double>& rowRate = RowFigures[0];
    std::vector<double>& rowArea = RowFigures[1];
    std::vector<double>& rowSum = RowFigures[2];
    rowRate.resize(H * D);
    rowArea.resize(H * D);
    rowSum.resize(Output == RowOutput::Step && RowSum ? H * D : 0);
    const std::int64_t chunks = (D + PlanesPerChunk - 1) / PlanesPerChunk;
    ParallelFor(chunks, Threads, [&](std::int64_t b, std::int64_t e) {
      for (std::int64_t c = b; c < e; ++c)
      {
        SweepPlanes(u, c * PlanesPerChunk, std::min(D, (c + 1) * PlanesPerChunk), rowRate.data(), rowArea.data(),
          rowSum.empty() ? nullptr : rowSum.data());
      }
    }, {}, 0, 1);
    MaxRate = rowRate.empty() ? 0.0 : *std::max_element(rowRate.begin(), rowRate.end());
    Area = std::accumulate(rowArea.begin(), rowArea.end(), 0.0);
    StepSum = std::accumulate(rowSum.begin(), rowSum.end(), 0.0);
    if (Split)
    {
      MaxRate = Split->Max(MaxRate);
      Area = Split->Sum(Area);
    }
  }

  /// The plane buffers of one thread: for three planes (rolling, plane k in
  /// slot k mod 3) the 7 weight arrays and the masses, each after a zero
  /// margin of a row; then the rows' scratch.
  struct Buffers
  {
    Real* Plane[3];  // per slot: 8 arrays of Stride values (7 weight directions, masses)
    Real *Edges, *Masses;
    double *KU, *Positive, *Speed, *Rates;
    /// Per slot, array and voxel row: the plane whose sums the row holds
    /// (-1: none yet).  A row's first sum is stored, the others added, so
    /// rows are never cleared; one that gets no sum reads as zeros.
    std::vector<std::int64_t> Holds;
    std::int64_t& HoldsAt(std::int64_t k, int d, std::int64_t j, std::int64_t h) { return Holds[((k % 3) * 8 + d) * h + j]; }
  };
  std::int64_t Stride() const { return W + 1 + PlaneSize; }
  /// The cells of a row rounded up to whole vectors (16 lanes).
  std::int64_t PaddedCells() const { return (W - 1 + 15) / 16 * 16; }
  std::size_t BufferDoubles() const
  {
    const std::size_t reals = 3 * 8 * Stride() + (KuhnCell::Edges + 8) * PaddedCells();
    return (reals * sizeof(Real) + sizeof(double) - 1) / sizeof(double) + (NC + 3) * W;
  }
  Real* PlaneWeights(Buffers& b, std::int64_t k, int d) const { return b.Plane[k % 3] + d * Stride() + W + 1; }

  /// Voxel planes [k0, k1): velocities (and the stored operator), per row the
  /// largest rate, the volume and (non-null rowSum) RowSum of its step.
  void SweepPlanes(const double* u, std::int64_t k0, std::int64_t k1, double* rowRate, double* rowArea, double* rowSum)
  {
    ScratchLease lease(Scratch, BufferDoubles());
    Buffers b;
    Real* r = reinterpret_cast<Real*>(lease.data());
    for (int s = 0; s < 3; ++s, r += 8 * Stride())
    {
      b.Plane[s] = r;
    }
    b.Edges = r;
    b.Masses = b.Edges + KuhnCell::Edges * PaddedCells();
    b.KU = lease.data() + (BufferDoubles() - (NC + 3) * W);
    b.Positive = b.KU + NC * W;
    b.Speed = b.Positive + W;
    b.Rates = b.Speed + W;
    std::fill(b.Speed, b.Speed + W, 1.0);
    // The slots zeroed once, margins included (never written; nor is the
    // last value of a row of the arrays of directions along x, which the
    // rows after it read as their x neighbour's); the rows' first sums are
    // stored (Holds).
    std::fill(b.Plane[0], b.Plane[0] + 3 * 8 * Stride(), Real(0));
    b.Holds.assign(3 * 8 * H, -1);
    if (k0 > 0)
    {
      for (std::int64_t j = 0; j + 1 < H; ++j)
      {
        CellRow(u, j, k0 - 1, b);
      }
    }
    for (std::int64_t k = k0; k < k1; ++k)
    {
      for (std::int64_t j = 0; j < H; ++j)
      {
        if (j + 1 < H && k + 1 < D)
        {
          CellRow(u, j, k, b);
        }
        EmitRow(u, j, k, b, rowRate, rowArea, rowSum);
      }
    }
  }

  /// The tetrahedra of cell row (j, k) into the plane buffers of k and k + 1.
  /// The row's cells are evaluated in whole vectors where the reads past
  /// its end stay within the data (all rows but the volume's last): the
  /// lanes past the row are computed and dropped, instead of a scalar tail.
  void CellRow(const double* u, std::int64_t j, std::int64_t k, Buffers& b) const
  {
    const std::int64_t n = W - 1, first = (k * H + j) * W;
    const std::int64_t m = first + Offset[7] + PaddedCells() <= Size ? PaddedCells() : n; // (cells evaluated)
    const double* u0 = u + first * NC;
    KuhnCellRow<NC, Real>(m, u0, u0 + Offset[1] * NC, u0 + Offset[2] * NC, u0 + Offset[3] * NC, u0 + Offset[4] * NC,
      u0 + Offset[5] * NC, u0 + Offset[6] * NC, u0 + Offset[7] * NC, Shapes, b.Edges, b.Masses);
    const auto sums = [&](int s) {
      return s < KuhnCell::Edges ? b.Edges + s * m : b.Masses + (s - KuhnCell::Edges) * m;
    };
    for (int t = 0; t < KuhnRowTargets::Count; ++t)
    {
      const int lower = RowTargets.Lower[t], d = RowTargets.Array[t];
      const std::int64_t plane = k + (lower >> 2), row = j + (lower >> 1 & 1);
      Real* to = PlaneWeights(b, plane, d) + row * W;
      std::int64_t& holds = b.HoldsAt(plane, d, row, H);
      const bool first = holds != plane;
      holds = plane;
      const Real* a = sums(RowTargets.First[t]);
      if (RowTargets.Second[t] < 0)
      {
        first ? static_cast<void>(std::copy_n(a, n, to)) : AddRow(n, a, to);
      }
      else
      {
        (first ? StoreRowPair<Real> : AddRowPair<Real>)(n, a, sums(RowTargets.Second[t]), to);
      }
    }
  }

  /// Voxel row (j, k), complete in the plane buffers: its velocity, rate
  /// and volume (and the stored operator).
  void EmitRow(const double* u, std::int64_t j, std::int64_t k, Buffers& b, double* rowRate, double* rowArea,
    double* rowSum)
  {
    const Real* up[8];
    const Real* down[8];
    // Rows that got no sum (at the volume's faces) read as zeros.
    const auto complete = [&](std::int64_t plane, int d, std::int64_t row) {
      if (plane >= 0 && row >= 0 && b.HoldsAt(plane, d, row, H) != plane)
      {
        std::fill_n(PlaneWeights(b, plane, d) + row * W, W, Real(0));
        b.HoldsAt(plane, d, row, H) = plane;
      }
    };
    for (int d = 0; d < 8; ++d)
    {
      complete(k, d, j);
    }
    for (int d = 1; d < 8; ++d)
    {
      complete(k - (d >> 2), d - 1, j - (d >> 1 & 1));
      up[d] = PlaneWeights(b, k, d - 1) + j * W;
      down[d] = PlaneWeights(b, k - (d >> 2) + 3, d - 1) + (j - (d >> 1 & 1)) * W - (d & 1);
    }
    const std::int64_t first = (k * H + j) * W;
    // The row's fixed flags asked for now, read after K u (VelocityRow
    // stalled on this array of the volume's size).
    for (std::int64_t ix = 0; ix < W; ix += 64)
    {
      __builtin_prefetch(Fixed.data() + first + ix, 1);
    }
    double* ku = StoreOperator ? KU.data() + first * NC : b.KU;
    double* diagonal = StoreOperator ? Diagonal.data() + first : nullptr;
    RowStiffness(u, j, k, up, down, ku, diagonal, b.Positive);
    const Real* mass = PlaneWeights(b, k, 7) + j * W;
    double* speed = StoreOperator ? Speed.data() + first : b.Speed; // (b.Speed: ones)
    for (std::int64_t ix = 0; (StoreOperator || Gamma != 1.0) && ix < W; ++ix)
    {
      const double m = mass[ix];
      speed[ix] = m > 0.0 && Gamma != 1.0 ? SpeedOf(BaseMassAt(ix, j, k) / m) : 1.0;
    }
    for (std::int64_t ix = 0; StoreOperator && ix < W; ++ix)
    {
      Mass[first + ix] = mass[ix];
    }
    double rate = 0.0, area = 0.0;
    std::uint8_t* fixed = Fixed.data() + first;
    const double* x = u + first * NC;
    switch (Output)
    {
      case RowOutput::Velocity:
        VelocityRow<NC, Real, RowOutput::Velocity>(W, mass, speed, fixed, ku, b.Positive, x, 0.0,
          Velocity.data() + first * NC, b.Rates, rate, area);
        break;
      case RowOutput::Step:
        VelocityRow<NC, Real, RowOutput::Step>(W, mass, speed, fixed, ku, b.Positive, x, StepSize,
          Next + first * NC, b.Rates, rate, area);
        break;
      case RowOutput::None:
        VelocityRow<NC, Real, RowOutput::None>(W, mass, speed, fixed, ku, b.Positive, x, 0.0, nullptr, b.Rates, rate,
          area);
        break;
    }
    if (Split) // a piece of a split grid: the figures of the voxels it owns
    {
      OwnedFigures(k * H + j, mass, b.Rates, rate, area);
    }
    rowRate[k * H + j] = rate;
    rowArea[k * H + j] = area;
    if (rowSum && !Split)
    {
      rowSum[k * H + j] = RowSum(first * NC, W * NC, Next + first * NC);
    }
    else if (rowSum)
    {
      double sum = 0.0;
      Owned.ForEach(k * H + j, [&](std::int64_t begin, std::int64_t end) {
        sum += RowSum((first + begin) * NC, (end - begin) * NC, Next + (first + begin) * NC);
      });
      rowSum[k * H + j] = sum;
    }
    if (StoreOperator)
    {
      for (int d = 1; d < 8; ++d)
      {
        std::copy(up[d], up[d] + W, WeightsOf(d) + first);
      }
    }
  }

  /// (K x), sum_j c_ij (diagonal not null) and sum_j max(c_ij, 0) of voxel row (j, k) from its
  /// weights: in one loop (StiffnessRow), neighbour rows outside the grid
  /// read as zeros; the rows next to the volume's first and last row (whose
  /// x neighbours at the ends are outside the memory) voxel by voxel.
  void RowStiffness(const double* x, std::int64_t j, std::int64_t k, const Real* const* up,
    const Real* const* down, double* kx, double* diagonal, double* positive) const
  {
    const std::int64_t first = (k * H + j) * W;
    const double* xu[8];
    const double* xd[8];
    bool inside = true; // all neighbours read within the memory
    for (int d = 1; d < 8; ++d)
    {
      const int dy = d >> 1 & 1, dz = d >> 2;
      const std::int64_t u = first + Offset[d], l = first - Offset[d];
      const bool hasUp = j + dy < H && k + dz < D, hasDown = j >= dy && k >= dz;
      xu[d] = hasUp ? x + u * NC : Zeros.data() + NC;
      xd[d] = hasDown ? x + l * NC : Zeros.data() + NC;
      inside = inside && (!hasUp || u + W <= Size) && (!hasDown || l >= 0);
    }
    if (inside)
    {
      StiffnessRow<NC, Real>(W, x + first * NC, xu, xd, up, down, kx, diagonal, positive);
      return;
    }
    for (std::int64_t ix = 0; ix < W; ++ix)
    {
      const std::int64_t i = first + ix;
      double* ki = kx + ix * NC;
      std::fill(ki, ki + NC, 0.0);
      double dg = 0.0, ps = 0.0;
      const auto add = [&](double c, std::int64_t n) {
        for (int m = 0; m < NC; ++m)
        {
          ki[m] += c * (x[i * NC + m] - x[n * NC + m]);
        }
        dg += c;
        ps += std::max(c, 0.0);
      };
      for (int d = 1; d < 8; ++d)
      {
        const int dx = d & 1, dy = d >> 1 & 1, dz = d >> 2;
        if (ix + dx < W && j + dy < H && k + dz < D)
        {
          add(up[d][ix], i + Offset[d]);
        }
        if (ix >= dx && j >= dy && k >= dz)
        {
          add(down[d][ix], i - Offset[d]);
        }
      }
      if (diagonal)
      {
        diagonal[ix] = dg;
      }
      positive[ix] = ps;
    }
  }

  /// The largest rate and the volume of the owned voxels of voxel row r
  /// (rates: VelocityRow's per voxel).
  void OwnedFigures(std::int64_t r, const Real* mass, const double* rates, double& rate, double& area) const
  {
    rate = area = 0.0;
    Owned.ForEach(r, [&](std::int64_t begin, std::int64_t end) {
      for (std::int64_t ix = begin; ix < end; ++ix)
      {
        rate = std::max(rate, rates[ix]);
        area += mass[ix];
      }
    });
  }

  /// The lumped mass of voxel (ix, j, k) of the flat graph: the corner
  /// masses of the cells it is a corner of.
  double BaseMassAt(std::int64_t ix, std::int64_t j, std::int64_t k) const
  {
    double m = 0.0;
    for (int c = 0; c < 8; ++c)
    {
      const std::int64_t cx = ix - (c & 1), cy = j - (c >> 1 & 1), cz = k - (c >> 2);
      if (cx >= 0 && cx + 1 < W && cy >= 0 && cy + 1 < H && cz >= 0 && cz + 1 < D)
      {
        m += CornerMass[c];
      }
    }
    return m;
  }

  VoxelGrid Grid;
  GridPiece Piece; // with Split: the piece of a split grid
  OwnedRuns Owned; // and its voxels, row by row
  std::int64_t W, H, D, PlaneSize = 0, Margin = 0;
  std::int64_t Offset[8];
  KuhnShapes<Real> Shapes; // of the flat cell
  double CornerMass[8];
  ScratchPool Scratch; // per-thread buffers, kept between steps
  /// Semi-implicit steps: the edge weights to the neighbour at +Offset[d],
  /// one array per direction d = 1..7, each after Margin zeros.
  LargeVector<Real> Weights;
  std::vector<double> Zeros; // a row of values outside the grid (their weights are 0)

  const Real* WeightsOf(int d) const
  {
    return Weights.data() + static_cast<std::size_t>(d - 1) * static_cast<std::size_t>(Margin + Size) + Margin;
  }
  Real* WeightsOf(int d)
  {
    return Weights.data() + static_cast<std::size_t>(d - 1) * static_cast<std::size_t>(Margin + Size) + Margin;
  }
};

} // namespace

GraphFlowResult RunVolumeGraphFlow(const VoxelGrid& grid, int components, double* values,
  const std::uint8_t* fixed, const GraphFlowOptions& options, const ProgressCallback& progress,
  const GridPiece* piece)
{
  const bool split = piece && piece->Split; // (every process runs, an empty piece too)
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
  if (!result.Error.empty() || (!split && (grid.Width < 2 || grid.Height < 2 || grid.Depth < 2)))
  {
    return result;
  }
  return WithCount<6>(components, [&](auto nc) { // kernels compiled per component count
    constexpr int NC = decltype(nc)::value;
    const bool store = options.Integration == GraphFlowIntegration::SemiImplicit;
    const auto make = [&]() {
      return std::make_unique<VoxelDiscretization<NC, VoxelReal>>(
        grid, fixed, options.EdgeContrast, options.NumberOfThreads, store, piece);
    };
    if (split)
    {
      return Integrate(make, values, options, progress); // (no probe band: the probe runs on every piece)
    }
    // A band of planes for the risk's probe (large volumes).
    const Index plane = static_cast<Index>(grid.Width * grid.Height);
    const ProbeWindow window = GridProbeWindow(static_cast<Index>(grid.Depth), plane, NC, 16, options,
      [&grid, fixed, &options, store, plane](Index first, Index count) -> std::unique_ptr<FlowDiscretization> {
        VoxelGrid band = grid;
        band.Depth = count;
        return std::make_unique<VoxelDiscretization<NC, VoxelReal>>(band, fixed ? fixed + static_cast<std::size_t>(first) * plane : nullptr,
          options.EdgeContrast, options.NumberOfThreads, store);
      });
    return Integrate(make, values, options, progress, window);
  });
}

} // namespace beltrami
