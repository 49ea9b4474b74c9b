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

using VoxelReal = float;

/// The edges of a Kuhn-split cell: the 19 corner pairs (lower, upper) with
/// lower's axes a subset of upper's (corner bit a = step along axis a), and
/// per tetrahedron (path) the slot of each of its six edges.
struct KuhnCell
{
  static constexpr int Edges = 19;
  int Lower[Edges]{}, Upper[Edges]{};
  int Corner[6][4]{}; // corners of path p: 0, one axis, two axes, 7
  int Slot[6][6]{};   // edge slot of tetrahedron edge e of path p

  constexpr KuhnCell()
  {
    int slot[8][8]{};
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

constexpr KuhnCell Kuhn{};

/// The flat cell's tetrahedra: per path the Gram matrix of its edge vectors
/// (entries 11, 22, 33, 12, 13, 23) and the inverse squared lengths of its
/// three steps (the path's axes in order); their common volume.
template <typename Real>
struct KuhnShapes
{
  Real Gram[6][6];
  Real InverseSquares[6][3];
  Real Volume;
};

/// The flat cell's tetrahedra for a spacing (3 values), and the lumped mass
/// each corner of the cell gets from them.
template <typename Real>
void MakeKuhnShapes(const double* spacing, KuhnShapes<Real>& shapes, double (&cornerMass)[8])
{
  shapes.Volume = static_cast<Real>(spacing[0] * spacing[1] * spacing[2] / 6.0);
  std::fill(cornerMass, cornerMass + 8, 0.0);
  for (int p = 0; p < 6; ++p)
  {
    // Corners of path p: 0, Kuhn.Corner[p][1], Kuhn.Corner[p][2], 7.
    double e[3][3];
    for (int s = 0; s < 3; ++s)
    {
      for (int a = 0; a < 3; ++a)
      {
        e[s][a] = (Kuhn.Corner[p][s + 1] >> a & 1) * spacing[a];
      }
    }
    const auto dot = [](const double* x, const double* y) { return x[0] * y[0] + x[1] * y[1] + x[2] * y[2]; };
    const double g[6] = { dot(e[0], e[0]), dot(e[1], e[1]), dot(e[2], e[2]), dot(e[0], e[1]), dot(e[0], e[2]),
      dot(e[1], e[2]) };
    std::copy(g, g + 6, shapes.Gram[p]);
    for (int s = 0; s < 3; ++s)
    {
      shapes.InverseSquares[p][s] = static_cast<Real>(1.0 / (spacing[KuhnPaths[p][s]] * spacing[KuhnPaths[p][s]]));
    }
    const double quarter = 0.25 * TetrahedronFromGram(g[0], g[1], g[2], g[3], g[4], g[5]).Volume;
    for (int v = 0; v < 4; ++v)
    {
      cornerMass[Kuhn.Corner[p][v]] += quarter;
    }
  }
}

/// Tetrahedron P's six edge weights into its cell's edges and a quarter of
/// its volume into its corners' masses.
template <int P, typename Real>
BELTRAMI_ALWAYS_INLINE inline void AddToCell(const Real (&weights)[6], Real volume, Real (&edges)[KuhnCell::Edges], Real (&masses)[8])
{
  #pragma GCC unroll 32
  for (int k = 0; k < 6; ++k)
  {
    edges[Kuhn.Slot[P][k]] += weights[k];
  }
  const Real quarter = Real(0.25) * volume;
  #pragma GCC unroll 32
  for (int v = 0; v < 4; ++v)
  {
    masses[Kuhn.Corner[P][v]] += quarter;
  }
}

/// Tetrahedron (path) P of a cell for scalar data, in closed form.  On the
/// tetrahedron 0, A, B, 7 (steps of lengths ha, hb, hc along the path's
/// axes ea, eb, ec) the
/// barycentric gradients are -ea/ha, ea/ha - eb/hb, eb/hb - ec/hc, ec/hc:
/// flat, only the pairs 01, 12, 23 meet (at -1/ha^2, -1/hb^2, -1/hc^2).  The
/// graph's metric I + grad f grad f^T has the determinant R^2 = 1 +
/// |grad f|^2 and the inverse I - grad f grad f^T / R^2, so the stiffness
/// is V0 R (grad phi_i . grad phi_j - t_i t_j / R^2), t_i = grad phi_i .
/// grad f, and the volume V0 R: what TetrahedronFromGram gives, in a third
/// of the operations.  (Never degenerate: R >= 1; non-finite data are
/// refused before the flow.)
template <int P, typename Real>
BELTRAMI_ALWAYS_INLINE inline void AddScalarKuhnTetrahedron(const Real (&d)[8][1], const KuhnShapes<Real>& shapes, Real (&edges)[KuhnCell::Edges], Real (&masses)[8])
{
  constexpr int A = Kuhn.Corner[P][1], B = Kuhn.Corner[P][2];
  const Real* h = shapes.InverseSquares[P];
  const Real da = d[A][0], db = d[B][0] - d[A][0], dc = d[7][0] - d[B][0]; // along the three steps
  const Real ga = da * h[0], gb = db * h[1], gc = dc * h[2];
  const Real r2 = Real(1) + da * ga + db * gb + dc * gc;
  const Real vr = shapes.Volume / std::sqrt(r2); // V0 / R
  const Real t0 = -ga, t1 = ga - gb, t2 = gb - gc, t3 = gc;
  const Real weights[6] = { vr * (t0 * t1 + r2 * h[0]), vr * (t0 * t2), vr * (t0 * t3), vr * (t1 * t2 + r2 * h[1]),
    vr * (t1 * t3), vr * (t2 * t3 + r2 * h[2]) };
  AddToCell<P>(weights, vr * r2, edges, masses);
}

/// Tetrahedron (path) P of a cell: its Gram matrix from the differences d
/// of the corners' values to corner 0's (NC each) and the base part, its
/// edge weights added to the cell's edges and a quarter of its volume to
/// its corners' masses (all indices constant: registers); scalars in the
/// closed form above.
template <int NC, int P, typename Real>
BELTRAMI_ALWAYS_INLINE inline void AddKuhnTetrahedron(const Real (&d)[8][NC], const KuhnShapes<Real>& shapes, Real (&edges)[KuhnCell::Edges], Real (&masses)[8])
{
  if constexpr (NC == 1)
  {
    AddScalarKuhnTetrahedron<P>(d, shapes, edges, masses);
    return;
  }
  constexpr int A = Kuhn.Corner[P][1], B = Kuhn.Corner[P][2];
  const Real* base = shapes.Gram[P];
  Real aa = 0, bb = 0, cc = 0, ab = 0, ac = 0, bc = 0;
  #pragma GCC unroll 32
  for (int m = 0; m < NC; ++m)
  {
    aa += d[A][m] * d[A][m];
    bb += d[B][m] * d[B][m];
    cc += d[7][m] * d[7][m];
    ab += d[A][m] * d[B][m];
    ac += d[A][m] * d[7][m];
    bc += d[B][m] * d[7][m];
  }
  const BasicTetrahedronTerms<Real> t =
    TetrahedronFromGram(base[0] + aa, base[1] + bb, base[2] + cc, base[3] + ab, base[4] + ac, base[5] + bc);
  AddToCell<P>(t.Weights, t.Volume, edges, masses);
}

/// The six Kuhn tetrahedra of the n cells of a row (u[c]: the values at
/// the cells' corner c, NC per voxel; shapes: of the flat cell) into the
/// cells' 19 edge weights (edges[s n + i]) and 8 corner masses (masses[c n
/// + i]).  Degenerate tetrahedra add nothing.  Compiled like TriangleRow.
template <int NC, typename Real>
CLONES void KuhnCellRow(std::int64_t n, const double* __restrict u0, const double* __restrict u1,
  const double* __restrict u2, const double* __restrict u3, const double* __restrict u4,
  const double* __restrict u5, const double* __restrict u6, const double* __restrict u7,
  const KuhnShapes<Real>& shapes, Real* __restrict edges, Real* __restrict masses)
{
#pragma GCC ivdep // the 27 output rows do not overlap
  for (std::int64_t i = 0; i < n; ++i)
  {
    Real d[8][NC];
#pragma GCC unroll 8
    for (int m = 0; m < NC; ++m)
    {
      const std::int64_t k = i * NC + m;
      const double o = u0[k];
      d[1][m] = Real(u1[k] - o);
      d[2][m] = Real(u2[k] - o);
      d[3][m] = Real(u3[k] - o);
      d[4][m] = Real(u4[k] - o);
      d[5][m] = Real(u5[k] - o);
      d[6][m] = Real(u6[k] - o);
      d[7][m] = Real(u7[k] - o);
    }
    Real e[KuhnCell::Edges] = {}, w[8] = {};
    AddKuhnTetrahedron<NC, 0>(d, shapes, e, w);
    AddKuhnTetrahedron<NC, 1>(d, shapes, e, w);
    AddKuhnTetrahedron<NC, 2>(d, shapes, e, w);
    AddKuhnTetrahedron<NC, 3>(d, shapes, e, w);
    AddKuhnTetrahedron<NC, 4>(d, shapes, e, w);
    AddKuhnTetrahedron<NC, 5>(d, shapes, e, w);
    #pragma GCC unroll 32
    for (int s = 0; s < KuhnCell::Edges; ++s)
    {
      edges[s * n + i] = e[s];
    }
    #pragma GCC unroll 32
    for (int c = 0; c < 8; ++c)
    {
      masses[c * n + i] = w[c];
    }
  }
}

/// to[i] += from[i], i < n (a cell row's sums into its plane buffers).
template <typename Real>
CLONES void AddRow(std::int64_t n, const Real* __restrict from, Real* __restrict to)
{
  for (std::int64_t i = 0; i < n; ++i)
  {
    to[i] += from[i];
  }
}

/// What a row's evaluation writes: the velocities, the explicit step from
/// state x, or nothing (the figures only).
enum class RowOutput
{
  Velocity,
  Step,
  None
};

/// For the n voxels of a row, from their masses, speeds, fixed flags (set
/// where the mass is lost: degenerate graph elements), K u and sums of
/// positive weights: the velocity f (K u) with f = speed / mass (0 where
/// fixed) into out, or the step out = x - dt f (K u), or nothing; and the
/// row's largest rate f sum(positive) and its volume.  (The loop has no
/// branches and no reductions, so that it vectorizes: the rates go to
/// positive, and are reduced after it in lanes.)
template <int NC, typename Real, RowOutput Output>
CLONES void VelocityRow(std::int64_t n, const Real* __restrict mass, const double* __restrict speed,
  std::uint8_t* __restrict fixed, const double* __restrict ku, double* __restrict positive,
  const double* __restrict x, double dt, double* __restrict out, double& rate, double& area)
{
  for (std::int64_t i = 0; i < n; ++i)
  {
    const double m = mass[i];
    const bool keep = (fixed[i] != 0) | !(m > 0.0);
    fixed[i] = keep;
    const double q = speed[i] / (keep ? 1.0 : m);
    const double f = keep ? 0.0 : q;
    for (int c = 0; c < NC && Output != RowOutput::None; ++c)
    {
      const std::int64_t k = i * NC + c;
      out[k] = Output == RowOutput::Velocity ? f * ku[k] : x[k] - dt * (f * ku[k]);
    }
    positive[i] *= f;
  }
  constexpr int Lanes = 8;
  double r[Lanes] = {}, a[Lanes] = {};
  std::int64_t i = 0;
  for (; i + Lanes <= n; i += Lanes)
  {
    for (int l = 0; l < Lanes; ++l)
    {
      r[l] = std::max(r[l], positive[i + l]);
      a[l] += mass[i + l];
    }
  }
  for (; i < n; ++i)
  {
    r[0] = std::max(r[0], positive[i]);
    a[0] += mass[i];
  }
  rate = *std::max_element(r, r + Lanes);
  area = std::accumulate(a, a + Lanes, 0.0);
}

/// (K x)_i, sum_j c_ij and sum_j max(c_ij, 0) for the n voxels of a row
/// (x: the row's values; xu[d], xd[d]: the values of the neighbours at
/// +Offset[d] and -Offset[d] of the row's first voxel, NC each; up[d],
/// down[d]: the weights of those edges).  Edges that leave the grid have
/// weight 0, so the wrapped neighbours of a row's ends, and rows of
/// neighbours outside the grid (read from a row of zeros), add nothing.
template <int NC, typename Real>
CLONES void StiffnessRow(std::int64_t n, const double* __restrict x, const double* const* xu,
  const double* const* xd, const Real* const* up, const Real* const* down, double* __restrict kx,
  double* __restrict diagonal, double* __restrict positive)
{
  const double *u1 = xu[1], *u2 = xu[2], *u3 = xu[3], *u4 = xu[4], *u5 = xu[5], *u6 = xu[6], *u7 = xu[7];
  const double *d1 = xd[1], *d2 = xd[2], *d3 = xd[3], *d4 = xd[4], *d5 = xd[5], *d6 = xd[6], *d7 = xd[7];
  const Real *w1 = up[1], *w2 = up[2], *w3 = up[3], *w4 = up[4], *w5 = up[5], *w6 = up[6], *w7 = up[7];
  const Real *v1 = down[1], *v2 = down[2], *v3 = down[3], *v4 = down[4], *v5 = down[5], *v6 = down[6],
             *v7 = down[7];
  for (std::int64_t i = 0; i < n; ++i)
  {
    const double c[14] = { w1[i], w2[i], w3[i], w4[i], w5[i], w6[i], w7[i], v1[i], v2[i], v3[i], v4[i], v5[i], v6[i],
      v7[i] };
    double dg = 0.0, ps = 0.0;
#pragma GCC unroll 14
    for (int e = 0; e < 14; ++e)
    {
      dg += c[e];
      ps += std::max(c[e], 0.0);
    }
#pragma GCC unroll 8
    for (int m = 0; m < NC; ++m)
    {
      const std::int64_t k = i * NC + m;
      const double xi = x[k];
      kx[k] = c[0] * (xi - u1[k]) + c[1] * (xi - u2[k]) + c[2] * (xi - u3[k]) + c[3] * (xi - u4[k]) +
        c[4] * (xi - u5[k]) + c[5] * (xi - u6[k]) + c[6] * (xi - u7[k]) + c[7] * (xi - d1[k]) +
        c[8] * (xi - d2[k]) + c[9] * (xi - d3[k]) + c[10] * (xi - d4[k]) + c[11] * (xi - d5[k]) +
        c[12] * (xi - d6[k]) + c[13] * (xi - d7[k]);
    }
    diagonal[i] = dg;
    positive[i] = ps;
  }
}

/// A discretization evaluated in one pass over the data (Sweep) that
/// writes what Output says: the velocities, the explicit step (fused, where
/// the operator is not kept), or only the figures.
class SweepDiscretization : public FlowDiscretization
{
public:
  void Update(const double* u) final
  {
    Output = RowOutput::Velocity;
    Sweep(u);
  }

  bool FusesSteps() const final { return !StoreOperator; }

  void FusedStep(const double* u, double dt, double* next) final
  {
    Output = next ? RowOutput::Step : RowOutput::None;
    StepSize = dt;
    Next = next;
    Sweep(u);
  }

protected:
  virtual void Sweep(const double* u) = 0;

  RowOutput Output = RowOutput::Velocity; // of the pass under way
  double StepSize = 0.0;
  double* Next = nullptr; // the step's output
};

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
  VoxelDiscretization(const VoxelGrid& grid, const std::uint8_t* fixed, double gamma, int threads, bool storeOperator)
    : Grid(grid)
    , W(grid.Width)
    , H(grid.Height)
    , D(grid.Depth)
  {
    Gamma = gamma;
    Threads = threads;
    StoreOperator = storeOperator;
    Size = static_cast<Index>(W * H * D);
    Components = NC;
    LengthScale = std::cbrt(grid.SpacingX * grid.SpacingY * grid.SpacingZ);
    AutomaticContrast = VolumeAutomaticContrast;
    // 0.1 on unit grids (limit about 0.12), scaled with the spacing.
    AutomaticTimeStep = 0.1 * 3.0 /
      (1.0 / (grid.SpacingX * grid.SpacingX) + 1.0 / (grid.SpacingY * grid.SpacingY) +
        1.0 / (grid.SpacingZ * grid.SpacingZ));
    Allocate();
    if (!StoreOperator)
    {
      LargeVector<double>().swap(Velocity); // explicit steps are fused (Velocity on demand)
    }
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

  double EstimateNoise(const double* values) const override { return EstimateVolumeNoise(Grid, NC, values); }

  void Apply(const double* x, double* y, bool) override
  {
    ParallelFor(H * D, Threads, [&](std::int64_t b, std::int64_t e) {
      ScratchLease buffer(Scratch, 2 * static_cast<std::size_t>(W));
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
        RowStiffness(x, r % H, r / H, up, down, y + first * NC, buffer.data(), buffer.data() + W);
      }
    }, {}, 0, 4);
  }

private:
  static constexpr std::int64_t PlanesPerChunk = 16;

  /// One pass over the volume (what Output says).
  void Sweep(const double* u) override
  {
    if (Output == RowOutput::Velocity && Velocity.size() != static_cast<std::size_t>(Size) * NC)
    {
      Velocity.assign(static_cast<std::size_t>(Size) * NC, 0.0);
    }
    std::vector<double> rowRate(H * D), rowArea(H * D); // per row: in row order, thread-independent
    const std::int64_t chunks = (D + PlanesPerChunk - 1) / PlanesPerChunk;
    ParallelFor(chunks, Threads, [&](std::int64_t b, std::int64_t e) {
      for (std::int64_t c = b; c < e; ++c)
      {
        SweepPlanes(u, c * PlanesPerChunk, std::min(D, (c + 1) * PlanesPerChunk), rowRate.data(), rowArea.data());
      }
    }, {}, 0, 1);
    MaxRate = *std::max_element(rowRate.begin(), rowRate.end());
    Area = std::accumulate(rowArea.begin(), rowArea.end(), 0.0);
  }

  /// The plane buffers of one thread: for three planes (rolling, plane k in
  /// slot k mod 3) the 7 weight arrays and the masses, each after a zero
  /// margin of a row; then the rows' scratch.
  struct Buffers
  {
    Real* Plane[3];  // per slot: 8 arrays of Stride values (7 weight directions, masses)
    Real *Edges, *Masses;
    double *KU, *Diagonal, *Positive, *Speed;
  };
  std::int64_t Stride() const { return W + 1 + PlaneSize; }
  std::size_t BufferDoubles() const
  {
    const std::size_t reals = 3 * 8 * Stride() + (KuhnCell::Edges + 8) * W;
    return (reals * sizeof(Real) + sizeof(double) - 1) / sizeof(double) + (NC + 3) * W;
  }
  Real* PlaneWeights(Buffers& b, std::int64_t k, int d) const { return b.Plane[k % 3] + d * Stride() + W + 1; }

  /// Voxel planes [k0, k1): velocities (and the stored operator), per row the
  /// largest rate and the volume.
  void SweepPlanes(const double* u, std::int64_t k0, std::int64_t k1, double* rowRate, double* rowArea)
  {
    ScratchLease lease(Scratch, BufferDoubles());
    Buffers b;
    Real* r = reinterpret_cast<Real*>(lease.data());
    for (int s = 0; s < 3; ++s, r += 8 * Stride())
    {
      b.Plane[s] = r;
    }
    b.Edges = r;
    b.Masses = b.Edges + KuhnCell::Edges * W;
    b.KU = lease.data() + (BufferDoubles() - (NC + 3) * W);
    b.Diagonal = b.KU + NC * W;
    b.Positive = b.Diagonal + W;
    b.Speed = b.Positive + W;
    std::fill(b.Speed, b.Speed + W, 1.0);
    const auto clear = [&](std::int64_t k) { std::fill(b.Plane[(k + 3) % 3], b.Plane[(k + 3) % 3] + 8 * Stride(), Real(0)); };
    clear(k0 - 1);
    clear(k0);
    if (k0 > 0)
    {
      for (std::int64_t j = 0; j + 1 < H; ++j)
      {
        CellRow(u, j, k0 - 1, b);
      }
    }
    for (std::int64_t k = k0; k < k1; ++k)
    {
      if (k + 1 < D)
      {
        clear(k + 1);
      }
      for (std::int64_t j = 0; j < H; ++j)
      {
        if (j + 1 < H && k + 1 < D)
        {
          CellRow(u, j, k, b);
        }
        EmitRow(u, j, k, b, rowRate, rowArea);
      }
    }
  }

  /// The tetrahedra of cell row (j, k) into the plane buffers of k and k + 1.
  void CellRow(const double* u, std::int64_t j, std::int64_t k, Buffers& b) const
  {
    const std::int64_t n = W - 1;
    const double* u0 = u + (k * H + j) * W * NC;
    KuhnCellRow<NC, Real>(n, u0, u0 + Offset[1] * NC, u0 + Offset[2] * NC, u0 + Offset[3] * NC, u0 + Offset[4] * NC,
      u0 + Offset[5] * NC, u0 + Offset[6] * NC, u0 + Offset[7] * NC, Shapes, b.Edges, b.Masses);
    for (int c = 0; c < 8; ++c)
    {
      AddRow(n, b.Masses + c * n, PlaneWeights(b, k + (c >> 2), 7) + (j + (c >> 1 & 1)) * W + (c & 1));
    }
    for (int e = 0; e < KuhnCell::Edges; ++e)
    {
      const int lower = Kuhn.Lower[e], direction = Kuhn.Upper[e] & ~lower;
      AddRow(n, b.Edges + e * n, PlaneWeights(b, k + (lower >> 2), direction - 1) + (j + (lower >> 1 & 1)) * W + (lower & 1));
    }
  }

  /// Voxel row (j, k), complete in the plane buffers: its velocity, rate
  /// and volume (and the stored operator).
  void EmitRow(const double* u, std::int64_t j, std::int64_t k, Buffers& b, double* rowRate, double* rowArea)
  {
    const Real* up[8];
    const Real* down[8];
    for (int d = 1; d < 8; ++d)
    {
      up[d] = PlaneWeights(b, k, d - 1) + j * W;
      down[d] = PlaneWeights(b, k - (d >> 2) + 3, d - 1) + (j - (d >> 1 & 1)) * W - (d & 1);
    }
    const std::int64_t first = (k * H + j) * W;
    double* ku = StoreOperator ? KU.data() + first * NC : b.KU;
    double* diagonal = StoreOperator ? Diagonal.data() + first : b.Diagonal;
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
          Velocity.data() + first * NC, rate, area);
        break;
      case RowOutput::Step:
        VelocityRow<NC, Real, RowOutput::Step>(W, mass, speed, fixed, ku, b.Positive, x, StepSize,
          Next + first * NC, rate, area);
        break;
      case RowOutput::None:
        VelocityRow<NC, Real, RowOutput::None>(W, mass, speed, fixed, ku, b.Positive, x, 0.0, nullptr, rate, area);
        break;
    }
    rowRate[k * H + j] = rate;
    rowArea[k * H + j] = area;
    if (StoreOperator)
    {
      for (int d = 1; d < 8; ++d)
      {
        std::copy(up[d], up[d] + W, WeightsOf(d) + first);
      }
    }
  }

  /// (K x), sum_j c_ij and sum_j max(c_ij, 0) of voxel row (j, k) from its
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
      diagonal[ix] = positive[ix] = 0.0;
      const auto add = [&](double c, std::int64_t n) {
        for (int m = 0; m < NC; ++m)
        {
          ki[m] += c * (x[i * NC + m] - x[n * NC + m]);
        }
        diagonal[ix] += c;
        positive[ix] += std::max(c, 0.0);
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
    }
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

/// (K x)_i, sum_j c_ij and sum_j max(c_ij, 0) for points i in [first,
/// first + n) of voxel cells: per direction d and point (7 arrays of
/// size each) the neighbour up and down (the point itself where there is
/// no edge) and the index of the down edge's weight in `weights` (7 arrays of size + 1:
/// per direction each point's edge up, 0 where none, then a 0 that the
/// missing down edges read).  Without branches, so that it vectorizes
/// (with the indices direction by direction: GCC 12 does not vectorize
/// groups of 7).
template <int NC, typename Real>
CLONES void StencilRows(std::int64_t first, std::int64_t n, std::int64_t size, const double* __restrict x,
  const Index* __restrict upper, const Index* __restrict lower, const Index* __restrict lowerWeight,
  const Real* __restrict weights, double* __restrict kx, double* __restrict diagonal, double* __restrict positive)
{
  for (std::int64_t i = first; i < first + n; ++i)
  {
    double dg = 0.0, ps = 0.0, sum[NC] = {};
#pragma GCC unroll 7
    for (int d = 0; d < 7; ++d)
    {
      const std::int64_t u = upper[d * size + i], l = lower[d * size + i];
      const double cu = weights[d * (size + 1) + i], cl = weights[lowerWeight[d * size + i]];
#pragma GCC unroll 8
      for (int m = 0; m < NC; ++m)
      {
        const double xi = x[i * NC + m];
        sum[m] += cu * (xi - x[u * NC + m]) + cl * (xi - x[l * NC + m]);
      }
      dg += cu + cl;
      ps += std::max(cu, 0.0) + std::max(cl, 0.0);
    }
#pragma GCC unroll 8
    for (int m = 0; m < NC; ++m)
    {
      kx[(i - first) * NC + m] = sum[m];
    }
    diagonal[i - first] = dg;
    positive[i - first] = ps;
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
    Gamma = gamma;
    Threads = threads;
    Size = size;
    Components = NC;
    StoreOperator = storeOperator;
    Allocate();
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
    // The points of the cells in lattice order (a cell's corner keys follow
    // from its corner 0's), and the caller's fixed flags in that order.
    std::vector<std::int64_t> pointKey(Size, -1);
    for (std::int64_t c = 0; c < cells; ++c)
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
    if (7 * (static_cast<double>(Active) + 1) >= 2147483647.0)
    {
      return false;
    }
    std::vector<Index> rank(Size, -1);
    for (Index a = 0; a < Active; ++a)
    {
      rank[Perm[a]] = a;
    }
    // The cells in that order, renumbered.
    std::vector<std::int64_t> order(cells);
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](std::int64_t a, std::int64_t b) { return cellKey[a] < cellKey[b]; });
    std::vector<Index> v(8 * static_cast<std::size_t>(cells));
    std::vector<std::int64_t> sortedKey(cells);
    for (std::int64_t c = 0; c < cells; ++c)
    {
      for (int k = 0; k < 8; ++k)
      {
        v[8 * c + k] = rank[corners[8 * order[c] + k]];
      }
      sortedKey[c] = cellKey[order[c]];
    }
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

  void ProbeSigns(std::vector<double>& b) const override { PositionProbeSigns(Size, Components, Points, LengthScale, b); }

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
    const std::vector<double>& in = Input;
    Gather(x, Input.data());
    std::fill(y, y + static_cast<std::size_t>(Size) * NC, 0.0); // (points in no cell: no edges)
    const std::int64_t blocks = (Active + PointsPerBlock - 1) / PointsPerBlock;
    ParallelFor(blocks, Threads, [&](std::int64_t b, std::int64_t e) {
      ScratchLease lease(Scratch, static_cast<std::size_t>(NC + 2) * PointsPerBlock);
      for (std::int64_t block = b; block < e; ++block)
      {
        const std::int64_t first = block * PointsPerBlock, n = std::min<std::int64_t>(PointsPerBlock, Active - first);
        double* kx = lease.data();
        PointStiffness(in.data(), first, n, kx, kx + NC * PointsPerBlock, kx + (NC + 1) * PointsPerBlock);
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
        LowerWeight[k] = static_cast<Index>(d * (static_cast<std::int64_t>(Active) + 1) + (Lower[k] < 0 ? Active : Lower[k]));
        Upper[k] = Upper[k] < 0 ? a : Upper[k];
        Lower[k] = Lower[k] < 0 ? a : Lower[k];
      }
    }
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
      LongestRun = std::max<std::int64_t>(LongestRun, 1);
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
      add(edges + e * n, Weights.data() + d * (Active + 1) + v[Kuhn.Lower[e]]);
    }
  }

  /// (K x), sum_j c_ij and sum_j max(c_ij, 0) of points [first, first + n)
  /// (lattice order; x too).
  void PointStiffness(const double* x, std::int64_t first, std::int64_t n, double* kx, double* diagonal,
    double* positive) const
  {
    StencilRows<NC, Real>(first, n, Active, x, Upper.data(), Lower.data(), LowerWeight.data(), Weights.data(), kx,
      diagonal, positive);
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
    PointStiffness(State.data(), first, n, ku, diagonal, positive);
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
        VelocityRow<NC, Real, RowOutput::Velocity>(n, mass, speed, fixed, ku, positive, x, 0.0, velocity, rate, area);
        break;
      case RowOutput::Step:
        VelocityRow<NC, Real, RowOutput::Step>(n, mass, speed, fixed, ku, positive, x, StepSize, velocity, rate, area);
        break;
      case RowOutput::None:
        VelocityRow<NC, Real, RowOutput::None>(n, mass, speed, fixed, ku, positive, x, 0.0, nullptr, rate, area);
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
      Fixed[i] = ActiveFixed[first + k];
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
      return std::make_unique<VoxelDiscretization<NC, VoxelReal>>(grid, fixed, options.EdgeContrast, options.NumberOfThreads, store);
    };
    // A band of planes for the risk's probe (large volumes).
    const Index plane = static_cast<Index>(grid.Width * grid.Height);
    const ProbeWindow window = GridProbeWindow(static_cast<Index>(grid.Depth), plane, options,
      [&grid, fixed, &options, store, plane](Index first, Index count) -> std::unique_ptr<FlowDiscretization> {
        VoxelGrid band = grid;
        band.Depth = count;
        return std::make_unique<VoxelDiscretization<NC, VoxelReal>>(band, fixed ? fixed + static_cast<std::size_t>(first) * plane : nullptr,
          options.EdgeContrast, options.NumberOfThreads, store);
      });
    return Integrate(make, values, options, progress, window);
  });
}

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
