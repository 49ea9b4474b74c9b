#include "GraphFlow.h"

#include "ConjugateGradient.h"
#include "LargeBuffer.h"
#include "Laplacian.h"
#include "Tetrahedra.h"

#include <algorithm>
#include <functional>
#include <cmath>
#include <memory>
#include <mutex>
#include <numeric>
#include <type_traits>
#include <vector>

namespace beltrami
{

namespace
{

/// Edge indicators below this are clamped (cliffs): bounds the speed-up of
/// gamma < 1 flows at E^(gamma - 1) <= 1e6.
constexpr double MinimumIndicator = 1e-3;

/// A discretization of the graph surface: the symmetric stiffness K (with
/// (K u)_i = sum_j c_ij (u_i - u_j)), the lumped mass a_i and the speed
/// s_i = E_i^(gamma - 1), so that the flow is du_i/dt = -s_i (K u)_i / a_i.
class FlowDiscretization
{
public:
  virtual ~FlowDiscretization() = default;

  Index Size = 0;
  int Components = 1;
  std::vector<std::uint8_t> Fixed; ///< non-zero: value kept
  /// Set before the first Update: the semi-implicit solver needs the operator
  /// (Mass, Speed, Diagonal, KU and Apply); the explicit one only Velocity.
  bool StoreOperator = true;
  // Filled by Update(u):
  LargeVector<double> Velocity; ///< s_i (K u)_i / a_i, zero where fixed: du/dt = -Velocity
  LargeVector<double> Mass, Speed, Diagonal, KU; ///< a_i, s_i, sum_j c_ij, K u (with ghosts)
  double Area = 0.0;    ///< area of the graph surface
  double MaxRate = 0.0; ///< max over free vertices of s_i sum_j max(c_ij, 0) / a_i

  /// Weights, masses and speeds at state u (scaled data, Components per vertex).
  virtual void Update(const double* u) = 0;
  /// y = K x; ghosts: include the values the boundary rule derives from x
  /// outside the domain (images; false: those neighbours count as zero).
  virtual void Apply(const double* x, double* y, bool ghosts) = 0;
  /// K as an explicit graph Laplacian, where it is one (meshes): the
  /// semi-implicit step then uses the faster graph solver.
  virtual const GraphLaplacian* Graph() const { return nullptr; }

protected:
  double Gamma = 1.0;
  int Threads = 0;

  double SpeedOf(double indicator) const
  {
    if (Gamma == 1.0)
    {
      return 1.0;
    }
    const double e = std::min(1.0, std::max(MinimumIndicator, indicator));
    return Gamma == 0.0 ? 1.0 / e : std::pow(e, Gamma - 1.0);
  }

  void Allocate()
  {
    Velocity.assign(static_cast<std::size_t>(Size) * Components, 0.0);
    if (StoreOperator)
    {
      Mass.assign(Size, 0.0);
      Speed.assign(Size, 1.0);
      Diagonal.assign(Size, 0.0);
      KU.assign(static_cast<std::size_t>(Size) * Components, 0.0);
    }
  }
};

// ---------------------------------------------------------------------------
// Images: the pixel grid triangulated both ways (each cell split along both
// diagonals, the two triangulations summed), so that the operator has the
// symmetry of the grid.  Pixel (x, y) sits at (x sx, y sy, u(x, y)) in
// R^(2+n).  Cotangents and mixed areas (section 2.4.3) of the four triangles
// of every cell come from dot products of the edge vectors (section 2.8.1).
//
// One Update is one pass over the image in bands of rows: per band, a row of
// cells (their four triangles) is computed into a small buffer, then the row
// of pixels between it and the previous cell row; no per-cell or per-pixel
// weights are stored unless the semi-implicit solver needs them.  The loops
// over a row have no branches, so the compiler vectorizes them.

/// The 8 neighbours of a pixel: offsets and slots of the per-pixel weights.
enum Neighbor
{
  E = 0, W, S, N, SE, NW, SW, NE
};
constexpr int NeighborDx[8] = { 1, -1, 0, 0, 1, -1, -1, 1 };
constexpr int NeighborDy[8] = { 0, 0, 1, -1, 1, -1, 1, -1 };

/// Per cell (corners a = top-left, b = top-right, c = bottom-right,
/// d = bottom-left): the weights (cot/2 sums) its triangles give to its six
/// edges and the mixed-area parts of its corners.
enum CellSlot
{
  Top = 0, Bottom, Left, Right, DiagAC, DiagBD, MassA, MassB, MassC, MassD, CellSlots
};

struct TriangleTerms
{
  double CotP, CotQ, CotR; // cotangents at P, Q, R
  double MassP, MassQ, MassR;
};

/// Triangle P, Q, R from |Q-P|^2, |R-P|^2 and (Q-P).(R-P) (never degenerate
/// here: the base part alone has area sx sy / 2).  Branch-free (selects).
inline TriangleTerms Triangle(double uu, double vv, double uv)
{
  TriangleTerms t;
  const double twiceArea = std::sqrt(std::max(uu * vv - uv * uv, 0.0));
  const double inv = 1.0 / twiceArea;
  const double dotQ = uu - uv, dotR = vv - uv; // (P-Q).(R-Q), (P-R).(Q-R)
  t.CotP = uv * inv;
  t.CotQ = dotQ * inv;
  t.CotR = dotR * inv;
  const bool acute = (uv >= 0.0) & (dotQ >= 0.0) & (dotR >= 0.0); // no short circuit: no branch
  const double ww = uu + vv - 2.0 * uv;
  const double half = 0.25 * twiceArea, quarter = 0.125 * twiceArea;
  const double vP = (uu * t.CotR + vv * t.CotQ) * 0.125;
  const double vQ = (uu * t.CotR + ww * t.CotP) * 0.125;
  const double vR = (vv * t.CotQ + ww * t.CotP) * 0.125;
  t.MassP = acute ? vP : (uv < 0.0 ? half : quarter);
  t.MassQ = acute ? vQ : (dotQ < 0.0 ? half : quarter);
  t.MassR = acute ? vR : (dotR < 0.0 ? half : quarter);
  return t;
}

template <int NC>
inline double Dot(const double* a, const double* b)
{
  double s = 0.0;
  for (int k = 0; k < NC; ++k)
  {
    s += a[k] * b[k];
  }
  return s;
}

/// The row kernels are compiled twice, for AVX2/FMA processors and for any
/// x86-64, and the processor picks at run time: the build stays portable.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__linux__)
#define CLONES __attribute__((target_clones("arch=x86-64-v4", "arch=x86-64-v3", "default")))
#else
#define CLONES
#endif

/// Dot products of the edge vectors of a cell (corners a, b, c, d).
enum CellDot
{
  AB_AB = 0, AC_AC, AD_AD, BC_BC, BD_BD, AB_AC, AC_AD, AB_AD, BC_BD, CellDots
};

/// The four triangles (abc, acd, abd, bcd) of n cells from their dot
/// products (CellDots arrays of n values) into CellSlots arrays of n values.
/// The same for any number of components, so compiled once.
CLONES void TriangleRow(std::int64_t n, const double* __restrict dots, double* __restrict out)
{
#pragma GCC ivdep // the slot arrays never overlap
  for (std::int64_t j = 0; j < n; ++j)
  {
    const double abab = dots[AB_AB * n + j], acac = dots[AC_AC * n + j];
    const double adad = dots[AD_AD * n + j], bcbc = dots[BC_BC * n + j];
    const double bdbd = dots[BD_BD * n + j], abac = dots[AB_AC * n + j];
    const double acad = dots[AC_AD * n + j], abad = dots[AB_AD * n + j];
    const double bcbd = dots[BC_BD * n + j];
    const TriangleTerms abc = Triangle(abab, acac, abac); // P=a, Q=b, R=c
    const TriangleTerms acd = Triangle(acac, adad, acad); // P=a, Q=c, R=d
    const TriangleTerms abd = Triangle(abab, adad, abad); // P=a, Q=b, R=d
    const TriangleTerms bcd = Triangle(bcbc, bdbd, bcbd); // P=b, Q=c, R=d
    out[Top * n + j] = 0.5 * (abc.CotR + abd.CotR);
    out[Bottom * n + j] = 0.5 * (acd.CotP + bcd.CotP);
    out[Left * n + j] = 0.5 * (acd.CotQ + abd.CotQ);
    out[Right * n + j] = 0.5 * (abc.CotP + bcd.CotR);
    out[DiagAC * n + j] = 0.5 * (abc.CotQ + acd.CotR);
    out[DiagBD * n + j] = 0.5 * (abd.CotP + bcd.CotQ);
    out[MassA * n + j] = abc.MassP + acd.MassP + abd.MassP;
    out[MassB * n + j] = abc.MassQ + abd.MassQ + bcd.MassP;
    out[MassC * n + j] = abc.MassR + acd.MassQ + bcd.MassQ;
    out[MassD * n + j] = acd.MassR + abd.MassR + bcd.MassR;
  }
}

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

/// Buffers lent to the threads of a parallel loop and kept for the next loop
/// (no allocation, zeroing or page faults per step).
class ScratchPool
{
public:
  std::vector<double> Take(std::size_t size)
  {
    std::vector<double> buffer;
    {
      std::lock_guard<std::mutex> lock(Mutex);
      if (!Free.empty())
      {
        buffer.swap(Free.back());
        Free.pop_back();
      }
    }
    if (buffer.size() < size)
    {
      buffer.resize(size);
    }
    return buffer;
  }
  void Give(std::vector<double>&& buffer)
  {
    std::lock_guard<std::mutex> lock(Mutex);
    Free.push_back(std::move(buffer));
  }

private:
  std::mutex Mutex;
  std::vector<std::vector<double>> Free;
};

/// A buffer of the pool for one scope.
class ScratchLease
{
public:
  ScratchLease(ScratchPool& pool, std::size_t size)
    : Pool(pool)
    , Buffer(pool.Take(size))
  {
  }
  ~ScratchLease() { Pool.Give(std::move(Buffer)); }
  ScratchLease(const ScratchLease&) = delete;
  ScratchLease& operator=(const ScratchLease&) = delete;
  double* data() { return Buffer.data(); }

private:
  ScratchPool& Pool;
  std::vector<double> Buffer;
};

/// Rows per band of the image pass (one extra cell row computed per band).
constexpr std::int64_t BandRows = 16;

template <int NC>
class GridDiscretization final : public FlowDiscretization
{
public:
  GridDiscretization(const PixelGrid& grid, GridBoundary boundary, double gamma, int threads,
    bool storeOperator)
    : Grid(grid)
    , Boundary(boundary)
  {
    Gamma = gamma;
    Threads = threads;
    StoreOperator = storeOperator;
    Size = grid.Width * grid.Height;
    Components = NC;
    PW = grid.Width + 2;
    PH = grid.Height + 2;
    PlaneSize = static_cast<std::size_t>(PW) * PH;
    Padded.resize(PlaneSize * NC);
    if (StoreOperator)
    {
      Weights.resize(static_cast<std::size_t>(Size) * 8);
    }
    Allocate();
    Fixed.assign(Size, 0);
    // Area scale for the indicator's guard (B has units 1/length).
    Epsilon2 = 1e-18 / std::pow(std::min(grid.SpacingX, grid.SpacingY), 2);
    BaseMass = 2.0 * grid.SpacingX * grid.SpacingY;
  }

  void Update(const double* u) override
  {
    Pad(u, true);
    const Index w = Grid.Width, h = Grid.Height;
    RowArea.resize(h);
    RowRate.resize(h);
    const std::int64_t bands = (h + BandRows - 1) / BandRows;
    const std::size_t row = static_cast<std::size_t>(w + 1);
    ParallelFor(bands, Threads, [&](std::int64_t b0, std::int64_t b1) {
      ScratchLease buffer(Scratch, (2 * CellSlots + CellDots + 2) * row);
      double* upper = buffer.data();
      double* lower = upper + CellSlots * row;
      double* dots = lower + CellSlots * row;
      double* sums = dots + CellDots * row; // per pixel of a row: mass, rate
      for (std::int64_t band = b0; band < b1; ++band)
      {
        const std::int64_t r0 = band * BandRows, r1 = std::min<std::int64_t>(h, r0 + BandRows);
        CellRow(r0, upper, dots);
        for (std::int64_t r = r0; r < r1; ++r)
        {
          CellRow(r + 1, lower, dots);
          if (StoreOperator)
          {
            PixelRow<true, false>(r, upper, lower, sums);
          }
          else if (Gamma == 1.0)
          {
            PixelRow<false, true>(r, upper, lower, sums);
          }
          else
          {
            PixelRow<false, false>(r, upper, lower, sums);
          }
          std::swap(upper, lower);
        }
      }
    }, {}, 0, 1);
    double area = 0.0, rate = 0.0;
    for (Index r = 0; r < h; ++r) // in order: the same sum for any thread count
    {
      area += RowArea[r];
      rate = std::max(rate, RowRate[r]);
    }
    Area = 0.5 * area;
    MaxRate = rate;
  }

  void Apply(const double* x, double* y, bool ghosts) override
  {
    Pad(x, ghosts);
    const Index w = Grid.Width;
    ParallelFor(Grid.Height, Threads, [&](std::int64_t r0, std::int64_t r1) {
      for (std::int64_t r = r0; r < r1; ++r)
      {
        for (Index c = 0; c < w; ++c)
        {
          const std::int64_t i = r * w + c;
          const double* wi = &Weights[i * 8];
          const double* xi = x + i * NC;
          double acc[NC];
          for (int k = 0; k < NC; ++k)
          {
            acc[k] = Diagonal[i] * xi[k];
          }
          for (int nb = 0; nb < 8; ++nb)
          {
            for (int k = 0; k < NC; ++k)
            {
              acc[k] -= wi[nb] * PaddedAt(k, r + NeighborDy[nb], c + NeighborDx[nb]);
            }
          }
          for (int k = 0; k < NC; ++k)
          {
            y[i * NC + k] = acc[k];
          }
        }
      }
    }, {}, 0, BandRows);
  }

private:
  PixelGrid Grid;
  GridBoundary Boundary;
  Index PW = 0, PH = 0;
  std::size_t PlaneSize = 0;
  LargeVector<double> Padded;  // NC planes of (H+2) x (W+2)
  LargeVector<double> Weights; // H x W x 8 (slots of Neighbor), semi-implicit only
  std::vector<double> RowArea, RowRate;
  ScratchPool Scratch; // per-thread row buffers of Update, kept between steps
  double Epsilon2 = 0.0;
  double BaseMass = 0.0; // a pixel's mass on flat data (both triangulations)

  /// Component k of pixel (r, c), -1 <= r <= H, -1 <= c <= W, of the padded copy.
  double PaddedAt(int k, std::int64_t r, std::int64_t c) const
  {
    return Padded[k * PlaneSize + (r + 1) * PW + (c + 1)];
  }

  /// Row r (-1 <= r <= H) of plane k of the padded copy, at column -1.
  const double* PaddedRow(int k, std::int64_t r) const
  {
    return &Padded[k * PlaneSize + (r + 1) * PW];
  }

  /// Copies x (interleaved) into the padded planes; the border ring gets the
  /// boundary rule (ghosts) or zeros.
  void Pad(const double* x, bool ghosts)
  {
    const Index w = Grid.Width, h = Grid.Height;
    ParallelFor(h, Threads, [&](std::int64_t r0, std::int64_t r1) {
      for (std::int64_t r = r0; r < r1; ++r)
      {
        const double* src = x + r * w * NC;
        for (int k = 0; k < NC; ++k)
        {
          double* dst = &Padded[k * PlaneSize + (r + 1) * PW + 1];
          for (Index c = 0; c < w; ++c)
          {
            dst[c] = src[c * NC + k];
          }
        }
      }
    }, {}, 0, 64);
    const auto clampIndex = [](std::int64_t v, std::int64_t n) {
      return std::min<std::int64_t>(std::max<std::int64_t>(v, 0), n - 1);
    };
    const auto ghost = [&](std::int64_t r, std::int64_t c) {
      const std::int64_t br = clampIndex(r, h), bc = clampIndex(c, w);
      const std::int64_t rr = clampIndex(2 * br - r, h), rc = clampIndex(2 * bc - c, w);
      const double* base = x + (br * w + bc) * NC;
      const double* mirror = x + (rr * w + rc) * NC;
      for (int k = 0; k < NC; ++k)
      {
        Padded[k * PlaneSize + (r + 1) * PW + (c + 1)] =
          !ghosts ? 0.0 : Boundary == GridBoundary::Reflect ? mirror[k] : 2.0 * base[k] - mirror[k];
      }
    };
    for (std::int64_t c = -1; c <= w; ++c)
    {
      ghost(-1, c);
      ghost(h, c);
    }
    for (std::int64_t r = 0; r < h; ++r)
    {
      ghost(r, -1);
      ghost(r, w);
    }
  }

  /// The four triangles of the cells of row q (between pixel rows q - 1 and
  /// q), columns -1 .. W-1, into out (CellSlots arrays of W + 1 values;
  /// `dots` is scratch of CellDots arrays): the dot products of the edge
  /// vectors, then the triangles.
  CLONES void CellRow(std::int64_t q, double* __restrict out, double* __restrict dots) const
  {
    const std::int64_t n = Grid.Width + 1;
    const double sx2 = Grid.SpacingX * Grid.SpacingX, sy2 = Grid.SpacingY * Grid.SpacingY;
    const double* top[NC];
    const double* bottom[NC];
    for (int k = 0; k < NC; ++k)
    {
      top[k] = PaddedRow(k, q - 1);
      bottom[k] = PaddedRow(k, q);
    }
#pragma GCC ivdep // the slot arrays never overlap
    for (std::int64_t j = 0; j < n; ++j)
    {
      // Full R^(2+n) dot products: base part + data part.
      double abab = sx2, acac = sx2 + sy2, adad = sy2, bcbc = sy2, bdbd = sx2 + sy2;
      double abac = sx2, acad = sy2, abad = 0.0, bcbd = sy2;
      for (int k = 0; k < NC; ++k)
      {
        const double a = top[k][j], b = top[k][j + 1], d = bottom[k][j], c = bottom[k][j + 1];
        const double ab = b - a, ac = c - a, ad = d - a, bc = c - b, bd = d - b;
        abab += ab * ab;
        acac += ac * ac;
        adad += ad * ad;
        bcbc += bc * bc;
        bdbd += bd * bd;
        abac += ab * ac;
        acad += ac * ad;
        abad += ab * ad;
        bcbd += bc * bd;
      }
      dots[AB_AB * n + j] = abab;
      dots[AC_AC * n + j] = acac;
      dots[AD_AD * n + j] = adad;
      dots[BC_BC * n + j] = bcbc;
      dots[BD_BD * n + j] = bdbd;
      dots[AB_AC * n + j] = abac;
      dots[AC_AD * n + j] = acad;
      dots[AB_AD * n + j] = abad;
      dots[BC_BD * n + j] = bcbd;
    }
    TriangleRow(n, dots, out);
  }

  /// Pixel row r from the cell rows above (upper, row r) and below (lower,
  /// row r + 1): the weights of the 8 edges, the mass, K u, the indicator
  /// max(|B_bar| / |B|, 1/W) (GraphFlow.h), the velocity and the row's area
  /// and stability rate.
  template <bool Store, bool UnitSpeed>
  CLONES void PixelRow(std::int64_t r, const double* __restrict upper, const double* __restrict lower,
    double* __restrict sums)
  {
    const Index w = Grid.Width;
    const std::int64_t n = w + 1;
    const double sx = Grid.SpacingX, sy = Grid.SpacingY;
    const double* p0[NC]; // pixel rows r - 1, r, r + 1 at column -1
    const double* p1[NC];
    const double* p2[NC];
    for (int k = 0; k < NC; ++k)
    {
      p0[k] = PaddedRow(k, r - 1);
      p1[k] = PaddedRow(k, r);
      p2[k] = PaddedRow(k, r + 1);
    }
    const std::uint8_t* fixed = &Fixed[r * w];
    double* __restrict velocity = &Velocity[r * w * NC];
    double* __restrict masses = sums;
    double* __restrict rates = sums + w;
#pragma GCC ivdep // the slot arrays never overlap
    for (Index c = 0; c < w; ++c)
    {
      // Cells with this pixel as corner a (lower, c + 1), b (lower, c),
      // c (upper, c) and d (upper, c + 1).
      double wn[8];
      wn[E] = lower[Top * n + c + 1] + upper[Bottom * n + c + 1];
      wn[W] = lower[Top * n + c] + upper[Bottom * n + c];
      wn[S] = lower[Left * n + c + 1] + lower[Right * n + c];
      wn[N] = upper[Left * n + c + 1] + upper[Right * n + c];
      wn[SE] = lower[DiagAC * n + c + 1];
      wn[NW] = upper[DiagAC * n + c];
      wn[SW] = lower[DiagBD * n + c];
      wn[NE] = upper[DiagBD * n + c + 1];
      const double mass =
        lower[MassA * n + c + 1] + lower[MassB * n + c] + upper[MassC * n + c] + upper[MassD * n + c + 1];
      double ku[NC];
      double data2 = 0.0;
      for (int k = 0; k < NC; ++k)
      {
        const double ui = p1[k][c + 1];
        ku[k] = wn[E] * (ui - p1[k][c + 2]) + wn[W] * (ui - p1[k][c]) + wn[S] * (ui - p2[k][c + 1]) +
          wn[N] * (ui - p0[k][c + 1]) + wn[SE] * (ui - p2[k][c + 2]) + wn[NW] * (ui - p0[k][c]) +
          wn[SW] * (ui - p2[k][c]) + wn[NE] * (ui - p0[k][c + 2]);
        data2 += ku[k] * ku[k];
      }
      double speed = 1.0;
      if (!UnitSpeed)
      {
        const double bx = sx * (wn[E] - wn[W] + wn[SE] - wn[NW] - wn[SW] + wn[NE]);
        const double by = sy * (wn[S] - wn[N] + wn[SE] - wn[NW] + wn[SW] - wn[NE]);
        const double guard = Epsilon2 * mass * mass;
        speed = SpeedOf(std::max(std::sqrt((data2 + guard) / (data2 + bx * bx + by * by + guard)),
          BaseMass / mass));
      }
      const double f = (fixed[c] == 0) & (mass > 0.0) ? speed / mass : 0.0;
      for (int k = 0; k < NC; ++k)
      {
        velocity[c * NC + k] = f * ku[k];
      }
      double positive = 0.0;
      for (int nb = 0; nb < 8; ++nb)
      {
        positive += std::max(wn[nb], 0.0);
      }
      masses[c] = mass;
      rates[c] = f * positive;
      if (Store)
      {
        const std::int64_t i = r * w + c;
        double diag = 0.0;
        for (int nb = 0; nb < 8; ++nb)
        {
          Weights[i * 8 + nb] = wn[nb];
          diag += wn[nb];
        }
        Mass[i] = mass;
        Diagonal[i] = diag;
        Speed[i] = speed;
        for (int k = 0; k < NC; ++k)
        {
          KU[i * NC + k] = ku[k];
        }
      }
    }
    double area = 0.0, rate = 0.0; // in order (not vectorized): sums are reproducible
    for (Index c = 0; c < w; ++c)
    {
      area += masses[c];
      rate = std::max(rate, rates[c]);
    }
    RowArea[r] = area;
    RowRate[r] = rate;
  }
};

// ---------------------------------------------------------------------------
// Meshes: the data as extra coordinates of the mesh, (x, y, z, alpha f) in
// R^(3+n), and the Laplacian of that embedding from the shared assemblers:
// triangle surfaces (the cotangent formula) and tetrahedral volumes (the
// volume gradient, appendix A.4).  The indicator is the ratio of the base
// and graph measures (mixed areas or vertex volumes: 1/W).

class MeshDiscretization final : public FlowDiscretization
{
public:
  /// Assembles the Laplacian of points with `dimension` coordinates each.
  using Assembler = std::function<void(const double* points, int dimension, GraphLaplacian& laplacian)>;

  /// massScale: the lumped mass is massScale * laplacian.Mass, so that
  /// -K u / mass is the Laplace-Beltrami operator (1/2 for the surface
  /// weights cot/4 over mixed areas; 1 for volume gradients over vertex
  /// volumes).  unusable (optional): non-zero = vertex kept (non-manifold).
  MeshDiscretization(Index size, const double* points, int components, const std::uint8_t* fixed,
    const std::uint8_t* unusable, Assembler assemble, double massScale, double gamma, int threads)
    : Assemble(std::move(assemble))
    , MassScale(massScale)
  {
    Gamma = gamma;
    Threads = threads;
    Size = size;
    Components = components;
    Allocate();
    GraphLaplacian base;
    Assemble(points, 3, base);
    BaseMeasure.assign(base.Mass.begin(), base.Mass.end());
    Fixed.assign(Size, 0);
    for (Index i = 0; i < Size; ++i)
    {
      Fixed[i] = (fixed && fixed[i]) || (unusable && unusable[i]) || !(BaseMeasure[i] > 0.0);
    }
    // The base coordinates of the embedding, once; Update writes the data.
    const int dim = 3 + components;
    Embedded.resize(static_cast<std::size_t>(Size) * dim);
    for (Index i = 0; i < Size; ++i)
    {
      std::copy(points + 3 * static_cast<std::size_t>(i), points + 3 * static_cast<std::size_t>(i) + 3,
        &Embedded[static_cast<std::size_t>(i) * dim]);
    }
  }

  void Update(const double* u) override
  {
    const int dim = 3 + Components;
    ParallelFor(Size, Threads, [&](std::int64_t b, std::int64_t e) {
      for (std::int64_t i = b; i < e; ++i)
      {
        std::copy(u + i * Components, u + (i + 1) * Components, &Embedded[i * dim + 3]);
      }
    });
    Assemble(Embedded.data(), dim, Laplacian);
    Positive.resize(Size);
    ParallelFor(Size, Threads, [&](std::int64_t b, std::int64_t e) {
      for (std::int64_t i = b; i < e; ++i)
      {
        Mass[i] = MassScale * Laplacian.Mass[i];
        Diagonal[i] = Laplacian.Diagonal[i];
        double p = 0.0;
        for (std::int64_t k = Laplacian.Offsets[i]; k < Laplacian.Offsets[i + 1]; ++k)
        {
          p += std::max(Laplacian.Weights[k], 0.0);
        }
        Positive[i] = p;
        Speed[i] = Laplacian.Mass[i] > 0.0 ? SpeedOf(BaseMeasure[i] / Laplacian.Mass[i]) : 1.0;
        if (!(Mass[i] > 0.0))
        {
          Fixed[i] = 1; // lost its measure (degenerate graph elements)
        }
      }
    });
    Laplacian.ApplyStiffness(u, KU.data(), Components, Threads);
    // Chunk maxima (ParallelSum would add them: the step was up to Size/4096
    // times smaller than stable on large meshes).
    std::vector<double> rates = ParallelPartials(Size, 1, Threads, [&](std::int64_t b, std::int64_t e, double* acc) {
      for (std::int64_t i = b; i < e; ++i)
      {
        const double f = !Fixed[i] && Mass[i] > 0.0 ? Speed[i] / Mass[i] : 0.0;
        for (int k = 0; k < Components; ++k)
        {
          Velocity[i * Components + k] = f * KU[i * Components + k];
        }
        acc[0] = std::max(acc[0], f * Positive[i]); // a maximum: any order gives the same
      }
    });
    MaxRate = rates.empty() ? 0.0 : *std::max_element(rates.begin(), rates.end());
    Area = ParallelSum(Size, 1, Threads, [&](std::int64_t b, std::int64_t e, double* acc) {
      for (std::int64_t i = b; i < e; ++i)
      {
        acc[0] += Laplacian.Mass[i];
      }
    })[0];
  }

  void Apply(const double* x, double* y, bool) override
  {
    Laplacian.ApplyStiffness(x, y, Components, Threads);
  }
  const GraphLaplacian* Graph() const override { return &Laplacian; }

private:
  Assembler Assemble;
  double MassScale;
  std::vector<double> BaseMeasure, Embedded, Positive;
  GraphLaplacian Laplacian;
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
  VoxelDiscretization(const VoxelGrid& grid, const std::uint8_t* fixed, double gamma, int threads, bool storeOperator)
    : Grid(grid)
  {
    Gamma = gamma;
    Threads = threads;
    StoreOperator = storeOperator;
    Size = static_cast<Index>(grid.Width * grid.Height * grid.Depth);
    Components = NC;
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

// ---------------------------------------------------------------------------

/// The options and the number of components (1 to `maximum`) of `what`.
std::string CheckOptions(const GraphFlowOptions& o, int components, int maximum, const std::string& what)
{
  if (components < 1 || components > maximum)
  {
    return what + " with 1 to " + std::to_string(maximum) + " components are supported";
  }
  if (!(o.ContrastScale > 0.0) || !std::isfinite(o.ContrastScale))
  {
    return "the contrast scale (alpha) must be positive and finite";
  }
  if (!(o.EdgeContrast >= -1.0) || !(o.EdgeContrast <= 10.0))
  {
    return "the edge contrast (gamma) must be in [-1, 10]";
  }
  if (!(o.TimeStep > 0.0) || !std::isfinite(o.TimeStep))
  {
    return "the time step must be positive and finite";
  }
  if (o.NumberOfIterations < 0)
  {
    return "the number of iterations must not be negative";
  }
  if (!(o.NoiseLevel >= 0.0) || !std::isfinite(o.NoiseLevel))
  {
    return "the noise level must be >= 0 and finite";
  }
  return {};
}

/// The time loop shared by images and surfaces (section 3.8.5).
GraphFlowResult Integrate(FlowDiscretization& disc, double* values, const GraphFlowOptions& o,
  const ProgressCallback& progress)
{
  GraphFlowResult result;
  const int nc = disc.Components;
  const Index n = disc.Size;
  const std::size_t size = static_cast<std::size_t>(n) * nc;
  const double alpha = o.ContrastScale;
  const int threads = o.NumberOfThreads;
  for (std::size_t k = 0; k < size; ++k)
  {
    if (!std::isfinite(values[k]))
    {
      result.Error = "the data contain NaN or infinite values";
      return result;
    }
  }
  LargeVector<double> u(size), u0(size), next(size), rhs, shift, diag;
  std::vector<Index> order; // the graph solver's renumbering (meshes)
  if (o.Integration == GraphFlowIntegration::SemiImplicit)
  {
    rhs.resize(size);
    shift.resize(n);
  }
  for (std::size_t k = 0; k < size; ++k)
  {
    u0[k] = u[k] = alpha * values[k];
  }
  std::vector<double> scratch;
  const auto measured = [&](const LargeVector<double>& x) {
    // The user's measure, on the values in data units.
    scratch.resize(size);
    for (std::size_t k = 0; k < size; ++k)
    {
      scratch[k] = x[k] / alpha;
    }
    return o.ChangeMeasure(scratch.data());
  };
  const auto rmsChange = [&]() {
    if (o.ChangeMeasure)
    {
      return measured(u);
    }
    const double s = ParallelSum(static_cast<std::int64_t>(size), 1, threads,
      [&](std::int64_t b, std::int64_t e, double* acc) {
        for (std::int64_t k = b; k < e; ++k)
        {
          acc[0] += (u[k] - u0[k]) * (u[k] - u0[k]);
        }
      })[0];
    return size ? std::sqrt(s / static_cast<double>(size)) / alpha : 0.0;
  };

  disc.Update(u.data());
  result.InitialArea = result.FinalArea = disc.Area;
  result.SmallestStableStep = disc.MaxRate > 0.0 ? 1.0 / disc.MaxRate : HUGE_VAL;
  double dt = o.TimeStep;
  if (o.AdaptiveTimeStep && o.Integration == GraphFlowIntegration::Explicit)
  {
    dt = std::min(dt, 0.9 * result.SmallestStableStep);
  }
  double previousRate = -1.0; // relative area decrease per unit time, last step
  for (int it = 0; it < o.NumberOfIterations; ++it)
  {
    if (progress && !progress(static_cast<double>(it) / o.NumberOfIterations))
    {
      result.Cancelled = true;
      break;
    }
    const double stable = disc.MaxRate > 0.0 ? 1.0 / disc.MaxRate : HUGE_VAL;
    result.SmallestStableStep = std::min(result.SmallestStableStep, stable);
    if (o.Integration == GraphFlowIntegration::Explicit)
    {
      if (o.AdaptiveTimeStep)
      {
        dt = std::min(dt, 0.9 * stable);
      }
      else if (dt > stable)
      {
        ++result.UnstableSteps;
      }
      // Velocity is zero at fixed vertices: one flat loop over all values.
      ParallelFor(static_cast<std::int64_t>(size), threads, [&](std::int64_t b, std::int64_t e) {
        const double* __restrict v = disc.Velocity.data();
        const double* __restrict x = u.data();
        double* __restrict y = next.data();
        for (std::int64_t j = b; j < e; ++j)
        {
          y[j] = x[j] - dt * v[j];
        }
      });
    }
    else
    {
      // (D + K_int) u' = D u - (K u - K_int u), D_i = a_i / (dt s_i): the
      // ghost values beyond the image border are those of the current state.
      disc.Apply(u.data(), next.data(), false);
      ParallelFor(n, threads, [&](std::int64_t b, std::int64_t e) {
        for (std::int64_t i = b; i < e; ++i)
        {
          const double d = disc.Mass[i] / (dt * disc.Speed[i]);
          shift[i] = d;
          for (int k = 0; k < nc; ++k)
          {
            const std::int64_t j = i * nc + k;
            rhs[j] = d * u[j] - (disc.KU[j] - next[j]);
          }
        }
      });
      std::vector<double> scale = ParallelSum(n, nc, threads, [&](std::int64_t b, std::int64_t e, double* acc) {
        for (std::int64_t i = b; i < e; ++i)
        {
          for (int k = 0; k < nc; ++k)
          {
            acc[k] += rhs[i * nc + k] * rhs[i * nc + k];
          }
        }
      });
      for (double& s : scale)
      {
        s = std::sqrt(s) + 1e-300;
      }
      next = u; // initial guess and fixed values
      if (const GraphLaplacian* graph = disc.Graph())
      {
        ShiftedLaplacianProblem sl = graph->Problem(nc);
        sl.Shift = shift.data();
        sl.Fixed = disc.Fixed.data();
        if (order.empty())
        {
          order = LocalityOrder(n, graph->Offsets, graph->Neighbors); // the graph stays
        }
        sl.Order = order.data();
        sl.Scale = scale;
        sl.Tolerance = o.SolverTolerance;
        sl.MaximumIterations = o.MaximumSolverIterations;
        sl.NumberOfThreads = threads;
        result.SolverIterations += SolveShiftedLaplacian(sl, rhs.data(), next.data()).Iterations;
      }
      else
      {
        diag.resize(n);
        ParallelFor(n, threads, [&](std::int64_t b, std::int64_t e) {
          for (std::int64_t i = b; i < e; ++i)
          {
            diag[i] = shift[i] + disc.Diagonal[i]; // Jacobi
          }
        });
        ConjugateGradientProblem cg;
        cg.Rows = n;
        cg.Columns = nc;
        cg.Diagonal = diag.data();
        cg.Fixed = disc.Fixed.data();
        cg.Scale = scale;
        cg.Tolerance = o.SolverTolerance;
        cg.MaximumIterations = o.MaximumSolverIterations;
        cg.NumberOfThreads = threads;
        cg.Apply = [&](const double* x, double* y) {
          disc.Apply(x, y, false);
          ParallelFor(n, threads, [&](std::int64_t b, std::int64_t e) {
            for (std::int64_t i = b; i < e; ++i)
            {
              for (int k = 0; k < nc; ++k)
              {
                y[i * nc + k] += shift[i] * x[i * nc + k];
              }
            }
          });
        };
        result.SolverIterations += SolveConjugateGradient(cg, rhs.data(), next.data()).Iterations;
      }
    }
    u.swap(next);
    const double previousArea = disc.Area;
    disc.Update(u.data());
    ++result.Iterations;
    result.Time += dt;
    result.LastTimeStep = dt;
    result.FinalArea = disc.Area;
    if (o.AdaptiveTimeStep)
    {
      // Section 3.8.5: a large change of the total area means much noise was
      // removed and a larger step is safe; when the change slows down the
      // step shrinks so that the structure of the data is not flattened.
      const double rate = previousArea > 0.0 ? (previousArea - disc.Area) / (previousArea * dt) : 0.0;
      if (previousRate > 0.0 && rate > 0.0)
      {
        dt *= std::min(2.0, std::max(0.5, rate / previousRate));
      }
      previousRate = rate;
    }
    if (o.NoiseLevel > 0.0 && rmsChange() >= o.NoiseLevel)
    {
      // Discrepancy reached within this step: go back along it to the point
      // where the RMS change equals the noise level, |a + t d|^2 = target.
      std::vector<double> s = ParallelSum(static_cast<std::int64_t>(size), 3, threads,
        [&](std::int64_t b, std::int64_t e, double* acc) {
          for (std::int64_t k = b; k < e; ++k)
          {
            const double a = next[k] - u0[k], d = u[k] - next[k];
            acc[0] += a * a;
            acc[1] += a * d;
            acc[2] += d * d;
          }
        });
      const double target = static_cast<double>(size) * std::pow(o.NoiseLevel * alpha, 2);
      double t = 1.0;
      if (o.ChangeMeasure)
      {
        // A measure of its own: its square taken as quadratic along the step,
        // through t = 0, 1/2 and 1.
        const double m0 = std::pow(measured(next), 2), m1 = std::pow(rmsChange(), 2);
        LargeVector<double> half(size);
        for (std::size_t k = 0; k < size; ++k)
        {
          half[k] = 0.5 * (next[k] + u[k]);
        }
        const double mh = std::pow(measured(half), 2), goal = o.NoiseLevel * o.NoiseLevel;
        // m(t) = m0 + b t + c t^2
        const double c = 2.0 * (m1 + m0 - 2.0 * mh), b = m1 - m0 - c;
        if (std::abs(c) > 1e-300)
        {
          const double d2 = b * b - 4.0 * c * (m0 - goal);
          t = d2 >= 0.0 ? (-b + (c > 0 ? 1 : -1) * std::sqrt(d2)) / (2.0 * c) : 1.0;
        }
        else if (std::abs(b) > 0.0)
        {
          t = (goal - m0) / b;
        }
        t = std::isfinite(t) ? std::min(1.0, std::max(0.0, t)) : 1.0;
      }
      else
      {
        const double disc2 = s[1] * s[1] - s[2] * (s[0] - target);
        t = s[2] > 0.0 && disc2 >= 0.0 ? std::min(1.0, std::max(0.0, (-s[1] + std::sqrt(disc2)) / s[2])) : 1.0;
      }
      if (t < 1.0)
      {
        for (std::size_t k = 0; k < size; ++k)
        {
          u[k] = next[k] + t * (u[k] - next[k]);
        }
        result.Time -= (1.0 - t) * dt;
        result.LastTimeStep = t * dt;
        disc.Update(u.data());
        result.FinalArea = disc.Area;
      }
      break;
    }
  }
  result.RMSChange = rmsChange();
  for (Index i = 0; i < n; ++i)
  {
    if (!disc.Fixed[i]) // fixed values stay bit-exact (no round trip through alpha)
    {
      for (int k = 0; k < nc; ++k)
      {
        values[i * nc + k] = u[i * nc + k] / alpha;
      }
    }
  }
  if (progress)
  {
    progress(1.0);
  }
  return result;
}

/// Calls run(std::integral_constant<int, NC>()) with NC = components (1 to 6):
/// the kernels are compiled per component count.
template <typename Run>
GraphFlowResult WithComponents(int components, Run&& run)
{
  switch (components)
  {
    case 1: return run(std::integral_constant<int, 1>());
    case 2: return run(std::integral_constant<int, 2>());
    case 3: return run(std::integral_constant<int, 3>());
    case 4: return run(std::integral_constant<int, 4>());
    case 5: return run(std::integral_constant<int, 5>());
    default: return run(std::integral_constant<int, 6>());
  }
}

template <int NC>
GraphFlowResult RunGrid(const PixelGrid& grid, double* values, const std::uint8_t* fixed,
  const GraphFlowOptions& o, const ProgressCallback& progress)
{
  GridDiscretization<NC> disc(
    grid, o.Boundary, o.EdgeContrast, o.NumberOfThreads, o.Integration == GraphFlowIntegration::SemiImplicit);
  if (fixed)
  {
    std::copy(fixed, fixed + disc.Size, disc.Fixed.begin());
  }
  return Integrate(disc, values, o, progress);
}

} // namespace

GraphFlowResult RunImageGraphFlow(const PixelGrid& grid, int components, double* values,
  const std::uint8_t* fixed, const GraphFlowOptions& options, const ProgressCallback& progress)
{
  GraphFlowResult result;
  result.Error = CheckOptions(options, components, 6, "images");
  if (result.Error.empty() &&
    (!(grid.SpacingX > 0.0) || !(grid.SpacingY > 0.0) || !std::isfinite(grid.SpacingX) ||
      !std::isfinite(grid.SpacingY)))
  {
    result.Error = "the pixel spacing must be positive and finite";
  }
  if (!result.Error.empty() || grid.Width <= 0 || grid.Height <= 0)
  {
    return result;
  }
  return WithComponents(components, [&](auto nc) {
    return RunGrid<decltype(nc)::value>(grid, values, fixed, options, progress);
  });
}

GraphFlowResult RunSurfaceGraphFlow(const MeshTopology& topology, const double* points,
  int components, double* values, const std::uint8_t* fixed, const GraphFlowOptions& options,
  const ProgressCallback& progress)
{
  GraphFlowResult result;
  result.Error = CheckOptions(options, components, 5, "point data");
  if (!result.Error.empty() || topology.NumberOfVertices() == 0)
  {
    return result;
  }
  const int threads = options.NumberOfThreads;
  std::vector<std::uint8_t> unusable(topology.NumberOfVertices());
  for (Index i = 0; i < topology.NumberOfVertices(); ++i)
  {
    unusable[i] = (topology.VertexFlags(i) & ~VertexBoundary) != 0;
  }
  MeshDiscretization disc(topology.NumberOfVertices(), points, components, fixed, unusable.data(),
    [&](const double* x, int dimension, GraphLaplacian& l) {
      AssembleSurfaceLaplacian(topology, x, dimension, LaplacianWeights::Cotangent, l, threads);
    },
    0.5, options.EdgeContrast, threads);
  return Integrate(disc, values, options, progress);
}

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
  return WithComponents(components, [&](auto nc) {
    VoxelDiscretization<decltype(nc)::value> disc(grid, fixed, options.EdgeContrast, options.NumberOfThreads,
      options.Integration == GraphFlowIntegration::SemiImplicit);
    return Integrate(disc, values, options, progress);
  });
}

GraphFlowResult RunTetrahedralGraphFlow(const TetrahedralMesh& mesh, const double* points,
  int components, double* values, const std::uint8_t* fixed, const GraphFlowOptions& options,
  const ProgressCallback& progress)
{
  GraphFlowResult result;
  result.Error = CheckOptions(options, components, 6, "point data");
  if (!result.Error.empty() || mesh.NumberOfVertices() == 0)
  {
    return result;
  }
  const int threads = options.NumberOfThreads;
  MeshDiscretization disc(mesh.NumberOfVertices(), points, components, fixed, nullptr,
    [&](const double* x, int dimension, GraphLaplacian& l) {
      AssembleTetrahedralLaplacian(mesh, x, dimension, l, threads);
    },
    1.0, options.EdgeContrast, threads);
  return Integrate(disc, values, options, progress);
}

} // namespace beltrami
