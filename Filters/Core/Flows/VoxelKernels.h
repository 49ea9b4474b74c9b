// Beltrami core, internal to Flows/VoxelGridFlow.cxx and Flows/VoxelCellFlow.cxx:
// the kernels of the 3D flow on voxel cells shared by dense grids and sparse
// voxel cells (the six Kuhn tetrahedra of a cell row, the row additions, the
// velocity rows) and the base of their one-pass discretizations.  Internal
// linkage (an unnamed namespace): each of the two files compiles its own
// copy of the processor-specific clones.
#pragma once

#include "Flows/GraphFlowDiscretization.h"
#include "Mesh/Tetrahedra.h"

#include <algorithm>
#include <cstdint>
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

/// The index ranges a row kernel's loop over n items runs as, so that it
/// runs in whole vectors of V items (V: a multiple of the kernel's vector
/// lengths): [0, n - n % V) and, where n is not a multiple, [n - V, n),
/// which overlaps the first range.  For loops whose body gives the same
/// result when it runs twice on an item (it overwrites nothing it reads but
/// with the same value): instead of a scalar tail, which took a row of 255
/// voxels' last 63 (VelocityRow: 64 fixed flags a vector) and 8% of the
/// 3D flow's time at 255 x 255 x 231.
struct VectorRanges
{
  std::int64_t Begin[2]{}, End[2]{};
  int Count = 1;

  VectorRanges(std::int64_t n, std::int64_t v)
  {
    End[0] = n;
    if (n > v && n % v != 0)
    {
      End[0] = n - n % v;
      Begin[1] = n - v;
      End[1] = n;
      Count = 2;
    }
  }
};

/// (K x)_i, sum_j c_ij (where diagonal is not null) and sum_j max(c_ij, 0)
/// for the n voxels of a row (or of a run of points whose neighbours are
/// runs too, VoxelCellFlow) (x: the row's values; xu[d], xd[d]: the values
/// of the neighbours at +Offset[d] and -Offset[d] of the row's first voxel,
/// NC each; up[d], down[d]: the weights of those edges).  Edges that leave
/// the grid have weight 0, so the wrapped neighbours of a row's ends, and
/// rows of neighbours outside the grid (read from a row of zeros), add
/// nothing.  The sums of positive weights (the rates' bound only) are
/// taken in the weights' precision; K x and the diagonal in double.
/// (Whole vectors: VectorRanges.)
template <int NC, typename Real, bool WithDiagonal>
BELTRAMI_ALWAYS_INLINE inline void StiffnessLoop(std::int64_t n, const double* __restrict x, const double* const* xu,
  const double* const* xd, const Real* const* up, const Real* const* down, double* __restrict kx,
  double* __restrict diagonal, double* __restrict positive)
{
  const double *u1 = xu[1], *u2 = xu[2], *u3 = xu[3], *u4 = xu[4], *u5 = xu[5], *u6 = xu[6], *u7 = xu[7];
  const double *d1 = xd[1], *d2 = xd[2], *d3 = xd[3], *d4 = xd[4], *d5 = xd[5], *d6 = xd[6], *d7 = xd[7];
  const Real *w1 = up[1], *w2 = up[2], *w3 = up[3], *w4 = up[4], *w5 = up[5], *w6 = up[6], *w7 = up[7];
  const Real *v1 = down[1], *v2 = down[2], *v3 = down[3], *v4 = down[4], *v5 = down[5], *v6 = down[6],
             *v7 = down[7];
  const VectorRanges ranges(n, 16);
  for (int r = 0; r < ranges.Count; ++r)
  {
    for (std::int64_t i = ranges.Begin[r]; i < ranges.End[r]; ++i)
    {
      const Real w[14] = { w1[i], w2[i], w3[i], w4[i], w5[i], w6[i], w7[i], v1[i], v2[i], v3[i], v4[i], v5[i], v6[i],
        v7[i] };
      Real ps = 0;
#pragma GCC unroll 14
      for (int e = 0; e < 14; ++e)
      {
        ps += std::max(w[e], Real(0));
      }
      positive[i] = ps;
      if constexpr (WithDiagonal)
      {
        double dg = 0.0;
#pragma GCC unroll 14
        for (int e = 0; e < 14; ++e)
        {
          dg += w[e];
        }
        diagonal[i] = dg;
      }
      const double c[14] = { w[0], w[1], w[2], w[3], w[4], w[5], w[6], w[7], w[8], w[9], w[10], w[11], w[12], w[13] };
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
    }
  }
}

/// StiffnessLoop, without the diagonal where it is null.
template <int NC, typename Real>
CLONES void StiffnessRow(std::int64_t n, const double* __restrict x, const double* const* xu,
  const double* const* xd, const Real* const* up, const Real* const* down, double* __restrict kx,
  double* __restrict diagonal, double* __restrict positive)
{
  diagonal ? StiffnessLoop<NC, Real, true>(n, x, xu, xd, up, down, kx, diagonal, positive)
           : StiffnessLoop<NC, Real, false>(n, x, xu, xd, up, down, kx, diagonal, positive);
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
/// fixed) into out, or the step out = x - dt f (K u), or nothing; the
/// rates f sum(positive) into rates; and the row's largest rate and its
/// volume.  (The loop has no branches and no reductions, so that it
/// vectorizes: the rates are reduced after it in lanes; whole vectors:
/// VectorRanges, out must not be x or ku.)
template <int NC, typename Real, RowOutput Output>
CLONES void VelocityRow(std::int64_t n, const Real* __restrict mass, const double* __restrict speed,
  std::uint8_t* __restrict fixed, const double* __restrict ku, const double* __restrict positive,
  const double* __restrict x, double dt, double* __restrict out, double* __restrict rates, double& rate,
  double& area)
{
  const VectorRanges ranges(n, 64);
  for (int r = 0; r < ranges.Count; ++r)
  {
    for (std::int64_t i = ranges.Begin[r]; i < ranges.End[r]; ++i)
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
      rates[i] = positive[i] * f;
    }
  }
  constexpr int Lanes = 8;
  double r[Lanes] = {}, a[Lanes] = {};
  std::int64_t i = 0;
  for (; i + Lanes <= n; i += Lanes)
  {
    for (int l = 0; l < Lanes; ++l)
    {
      r[l] = std::max(r[l], rates[i + l]);
      a[l] += mass[i + l];
    }
  }
  for (; i < n; ++i)
  {
    r[0] = std::max(r[0], rates[i]);
    a[0] += mass[i];
  }
  rate = *std::max_element(r, r + Lanes);
  area = std::accumulate(a, a + Lanes, 0.0);
}

/// A discretization evaluated in one pass over the data (Sweep) that
/// writes what Output says: the velocities, the explicit step (fused, where
/// the operator is not kept), or only the figures.
class SweepDiscretization : public FlowDiscretization
{
public:
  void Update(const double* u) final
  {
    // (Explicit steps are fused: the velocity is allocated only when asked for.)
    Velocity.resize(static_cast<std::size_t>(Size) * Components);
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

} // namespace

} // namespace beltrami
