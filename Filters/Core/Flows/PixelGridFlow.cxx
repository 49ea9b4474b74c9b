#include "Flows/GraphFlowDiscretization.h"
#include "Flows/NoiseEstimation.h"

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

// ---------------------------------------------------------------------------
// Images: the pixel grid triangulated both ways (each cell split along both
// diagonals, the two triangulations summed), so that the operator has the
// symmetry of the grid.  Pixel (x, y) sits at (x sx, y sy, u(x, y)) in
// R^(2+n).  Cotangents and mixed areas (section 2.4.3) of the four triangles
// of every cell come from dot products of the edge vectors (section 2.8.1).
//
// One Update is one pass over the image in bands of rows: per band, each
// pixel row is copied into planes with its border (a ring of three rows), a
// row of cells (their four triangles, in single precision) is computed into
// a small buffer, then the row of pixels between it and the previous cell
// row; no per-cell or per-pixel weights are stored unless the semi-implicit
// solver needs them.  The loops over a row have no branches, so the
// compiler vectorizes them.

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

/// The cells' triangles are evaluated in single precision (from the
/// differences of the double values), as the 3D flow's tetrahedra are:
/// twice the vector width; K u stays in double.
using PixelReal = float;

struct TriangleTerms
{
  PixelReal CotP, CotQ, CotR; // cotangents at P, Q, R
  PixelReal MassP, MassQ, MassR;
};

/// Triangle P, Q, R from |Q-P|^2, |R-P|^2, (Q-P).(R-P) and its squared
/// twice-area `area2` (a sum of squared minors, CellRow: no cancellation,
/// at least (sx sy)^2).  Branch-free (selects).
inline TriangleTerms Triangle(PixelReal uu, PixelReal vv, PixelReal uv, PixelReal area2)
{
  using R = PixelReal;
  TriangleTerms t;
  const R twiceArea = std::sqrt(area2);
  const R inv = R(1) / twiceArea;
  const R dotQ = uu - uv, dotR = vv - uv; // (P-Q).(R-Q), (P-R).(Q-R)
  t.CotP = uv * inv;
  t.CotQ = dotQ * inv;
  t.CotR = dotR * inv;
  const bool acute = (uv >= R(0)) & (dotQ >= R(0)) & (dotR >= R(0)); // no short circuit: no branch
  const R ww = uu + vv - R(2) * uv;
  const R half = R(0.25) * twiceArea, quarter = R(0.125) * twiceArea;
  const R vP = (uu * t.CotR + vv * t.CotQ) * R(0.125);
  const R vQ = (uu * t.CotR + ww * t.CotP) * R(0.125);
  const R vR = (vv * t.CotQ + ww * t.CotP) * R(0.125);
  t.MassP = acute ? vP : (uv < R(0) ? half : quarter);
  t.MassQ = acute ? vQ : (dotQ < R(0) ? half : quarter);
  t.MassR = acute ? vR : (dotR < R(0) ? half : quarter);
  return t;
}

/// Dot products of the edge vectors of a cell (corners a, b, c, d) and
/// the squared twice-areas of its four triangles.
enum CellDot
{
  AB_AB = 0, AC_AC, AD_AD, BC_BC, BD_BD, AB_AC, AC_AD, AB_AD, BC_BD, AREA_ABC, AREA_ACD, AREA_ABD, AREA_BCD, CellDots
};

/// The four triangles (abc, acd, abd, bcd) of n cells from their dot
/// products (CellDots arrays of n values) into CellSlots arrays of n values.
/// The same for any number of components, so compiled once.
CLONES void TriangleRow(std::int64_t n, const PixelReal* __restrict dots, PixelReal* __restrict out)
{
  using R = PixelReal;
#pragma GCC ivdep // the slot arrays never overlap
  for (std::int64_t j = 0; j < n; ++j)
  {
    const R abab = dots[AB_AB * n + j], acac = dots[AC_AC * n + j];
    const R adad = dots[AD_AD * n + j], bcbc = dots[BC_BC * n + j];
    const R bdbd = dots[BD_BD * n + j], abac = dots[AB_AC * n + j];
    const R acad = dots[AC_AD * n + j], abad = dots[AB_AD * n + j];
    const R bcbd = dots[BC_BD * n + j];
    const TriangleTerms abc = Triangle(abab, acac, abac, dots[AREA_ABC * n + j]); // P=a, Q=b, R=c
    const TriangleTerms acd = Triangle(acac, adad, acad, dots[AREA_ACD * n + j]); // P=a, Q=c, R=d
    const TriangleTerms abd = Triangle(abab, adad, abad, dots[AREA_ABD * n + j]); // P=a, Q=b, R=d
    const TriangleTerms bcd = Triangle(bcbc, bdbd, bcbd, dots[AREA_BCD * n + j]); // P=b, Q=c, R=d
    out[Top * n + j] = R(0.5) * (abc.CotR + abd.CotR);
    out[Bottom * n + j] = R(0.5) * (acd.CotP + bcd.CotP);
    out[Left * n + j] = R(0.5) * (acd.CotQ + abd.CotQ);
    out[Right * n + j] = R(0.5) * (abc.CotP + bcd.CotR);
    out[DiagAC * n + j] = R(0.5) * (abc.CotQ + acd.CotR);
    out[DiagBD * n + j] = R(0.5) * (abd.CotP + bcd.CotQ);
    out[MassA * n + j] = abc.MassP + acd.MassP + abd.MassP;
    out[MassB * n + j] = abc.MassQ + abd.MassQ + bcd.MassP;
    out[MassC * n + j] = abc.MassR + acd.MassQ + bcd.MassQ;
    out[MassD * n + j] = acd.MassR + abd.MassR + bcd.MassR;
  }
}

/// Rows per band of the image pass (one extra cell row computed per band).
constexpr std::int64_t BandRows = 32;

/// What a pixel row's evaluation writes: the velocity, the velocity and
/// the operator (semi-implicit steps), the explicit step (fused), or only
/// the figures.
enum class PixelOutput
{
  Velocity,
  Operator,
  Step,
  None
};

template <int NC>
class GridDiscretization final : public FlowDiscretization
{
public:
  /// piece (optional): the grid is a piece of a split grid (GridPiece).
  GridDiscretization(const PixelGrid& grid, GridBoundary boundary, double gamma, int threads,
    bool storeOperator, const GridPiece* piece = nullptr)
    : Grid(grid)
    , Boundary(boundary)
  {
    if (piece && piece->Split)
    {
      Piece = *piece;
      Split = piece->Split;
      Owned = OwnedRuns(*Split, grid.Height, grid.Width);
    }
    Allocate(grid.Width * grid.Height, NC, gamma, threads, storeOperator);
    // 0.2 on unit grids (limit about 0.24), scaled with the spacing.
    AutomaticTimeStep = 0.2 * 2.0 / (1.0 / (grid.SpacingX * grid.SpacingX) + 1.0 / (grid.SpacingY * grid.SpacingY));
    PW = grid.Width + 2;
    PH = grid.Height + 2;
    PlaneSize = static_cast<std::size_t>(PW) * PH;
    if (StoreOperator) // (Padded: Apply's copy; a sweep pads its rows as it reaches them)
    {
      Padded.resize(PlaneSize * NC);
      Weights.resize(static_cast<std::size_t>(Size) * 8);
    }
    Fixed.assign(Size, 0);
    // Area scale for the indicator's guard (B has units 1/length).
    Epsilon2 = 1e-18 / std::pow(std::min(grid.SpacingX, grid.SpacingY), 2);
    BaseMass = 2.0 * grid.SpacingX * grid.SpacingY;
    LengthScale = std::sqrt(grid.SpacingX * grid.SpacingY);
  }

  double EstimateNoise(const double* values) const override
  {
    return EstimateImageNoise(Grid, NC, values, Threads, Split ? &Piece : nullptr);
  }

  void ProbeSigns(std::size_t begin, std::size_t end, UninitializedVector<double>& b) const override
  {
    Split ? GridPieceProbeSigns(*this, Piece, Grid.Width, Grid.Height, 1, b)
          : FlowDiscretization::ProbeSigns(begin, end, b);
  }

  void Update(const double* u) override
  {
    Velocity.resize(static_cast<std::size_t>(Size) * NC); // (explicit steps are fused: on demand)
    Sweep(u, StoreOperator ? PixelOutput::Operator : PixelOutput::Velocity, 0.0, nullptr);
  }

  bool FusesSteps() const override { return !StoreOperator; }
  bool SumsRows() const override { return true; }

  void FusedStep(const double* u, double dt, double* next) override
  {
    Sweep(u, next ? PixelOutput::Step : PixelOutput::None, dt, next);
  }

  /// One pass over the image: the rows' weights, masses and what `output`
  /// says (the explicit step from u into next), and the figures.
  void Sweep(const double* u, PixelOutput output, double dt, double* next)
  {
    if (Size == 0) // (an empty piece of a split grid)
    {
      Area = Split ? 0.5 * Split->Sum(0.0) : 0.0;
      MaxRate = Split ? Split->Max(0.0) : 0.0;
      StepSum = 0.0;
      return;
    }
    const Index w = Grid.Width, h = Grid.Height;
    RowArea.resize(h);
    RowRate.resize(h);
    RowSums.assign(output == PixelOutput::Step && RowSum ? h : 0, 0.0);
    const std::int64_t bands = (h + BandRows - 1) / BandRows;
    const std::size_t row = static_cast<std::size_t>(w + 1);
    ParallelFor(bands, Threads, [&](std::int64_t b0, std::int64_t b1) {
      const std::size_t reals = (2 * CellSlots + CellDots) * row;
      const std::size_t ring = 3 * NC * static_cast<std::size_t>(PW);
      ScratchLease buffer(Scratch, 2 * row + ring + (reals * sizeof(PixelReal) + sizeof(double) - 1) / sizeof(double));
      double* sums = buffer.data(); // per pixel of a row: mass, rate
      PaddedRows rows(sums + 2 * row, PW); // padded pixel rows r - 1 .. r + 1
      PixelReal* upper = reinterpret_cast<PixelReal*>(sums + 2 * row + ring);
      PixelReal* lower = upper + CellSlots * row;
      PixelReal* dots = lower + CellSlots * row;
      for (std::int64_t band = b0; band < b1; ++band)
      {
        const std::int64_t r0 = band * BandRows, r1 = std::min<std::int64_t>(h, r0 + BandRows);
        PadRow(u, r0 - 1, true, rows.At(r0 - 1));
        PadRow(u, r0, true, rows.At(r0));
        CellRow(rows.At(r0 - 1), rows.At(r0), upper, dots);
        for (std::int64_t r = r0; r < r1; ++r)
        {
          PadRow(u, r + 1, true, rows.At(r + 1));
          CellRow(rows.At(r), rows.At(r + 1), lower, dots);
          Row(output, r, rows, upper, lower, sums, dt, next);
          if (!RowSums.empty())
          {
            RowSums[r] = StepRowSum(r, next);
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
    Area = 0.5 * (Split ? Split->Sum(area) : area);
    MaxRate = Split ? Split->Max(rate) : rate;
    StepSum = std::accumulate(RowSums.begin(), RowSums.end(), 0.0);
  }

  void Apply(const double* x, double* y, bool ghosts) override
  {
    if (Size == 0)
    {
      return;
    }
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
  GridPiece Piece; // with Split: the piece of a split grid
  OwnedRuns Owned; // and its pixels, row by row
  GridBoundary Boundary;
  Index PW = 0, PH = 0;
  std::size_t PlaneSize = 0;
  LargeVector<double> Padded;  // NC planes of (H+2) x (W+2)
  LargeVector<double> Weights; // H x W x 8 (slots of Neighbor), semi-implicit only
  std::vector<double> RowArea, RowRate, RowSums; // per row (RowSums: of RowSum, when asked for)
  ScratchPool Scratch; // per-thread row buffers of Update, kept between steps
  double Epsilon2 = 0.0;
  double BaseMass = 0.0; // a pixel's mass on flat data (both triangulations)

  /// RowSum of pixel row r of the step into next (a split grid: of its
  /// runs of owned pixels).
  double StepRowSum(std::int64_t r, const double* next) const
  {
    double sum = 0.0;
    const auto add = [&](std::int64_t begin, std::int64_t end) {
      const std::int64_t first = (r * Grid.Width + begin) * NC;
      sum += RowSum(first, (end - begin) * NC, next + first);
    };
    Split ? Owned.ForEach(r, add) : add(0, Grid.Width);
    return sum;
  }

  /// Component k of pixel (r, c), -1 <= r <= H, -1 <= c <= W, of the padded copy.
  double PaddedAt(int k, std::int64_t r, std::int64_t c) const
  {
    return Padded[k * PlaneSize + (r + 1) * PW + (c + 1)];
  }

  /// The planes of padded pixel rows (column -1 first, W + 2 values): a
  /// ring of three in a thread's buffer, row r in slot (r + 1) mod 3.
  struct PaddedRows
  {
    PaddedRows(double* buffer, std::int64_t width)
    {
      for (int slot = 0; slot < 3; ++slot)
      {
        for (int k = 0; k < NC; ++k)
        {
          Planes[slot][k] = buffer + (slot * NC + k) * width;
        }
      }
    }
    double* const* At(std::int64_t r) { return Planes[(r + 1) % 3]; }
    double* Planes[3][NC];
  };

  /// Copies x (interleaved) into the padded planes (the semi-implicit
  /// operator's copy).
  void Pad(const double* x, bool ghosts)
  {
    ParallelFor(Grid.Height + 2, Threads, [&](std::int64_t r0, std::int64_t r1) {
      for (std::int64_t r = r0 - 1; r < r1 - 1; ++r)
      {
        double* planes[NC];
        for (int k = 0; k < NC; ++k)
        {
          planes[k] = &Padded[k * PlaneSize + (r + 1) * PW];
        }
        PadRow(x, r, ghosts, planes);
      }
    }, {}, 0, 64);
  }

  /// Row r (-1 <= r <= H) of x (interleaved), columns -1 .. W, into one
  /// plane per component; outside the image the boundary rule's values
  /// (ghosts) or zeros.
  void PadRow(const double* x, std::int64_t r, bool ghosts, double* const* planes) const
  {
    const Index w = Grid.Width, h = Grid.Height;
    const auto clampIndex = [](std::int64_t v, std::int64_t n) {
      return std::min<std::int64_t>(std::max<std::int64_t>(v, 0), n - 1);
    };
    const std::int64_t br = clampIndex(r, h), rr = clampIndex(2 * br - r, h);
    const bool reflect = Boundary == GridBoundary::Reflect;
    const auto ghost = [&](std::int64_t c, int k) {
      const std::int64_t bc = clampIndex(c, w), rc = clampIndex(2 * bc - c, w);
      const double base = x[(br * w + bc) * NC + k], mirror = x[(rr * w + rc) * NC + k];
      return !ghosts ? 0.0 : reflect ? mirror : 2.0 * base - mirror;
    };
    if (br == r)
    {
      DeinterleaveRow(w, x + r * w * NC, planes);
    }
    else
    {
      for (Index c = 0; c < w; ++c)
      {
        for (int k = 0; k < NC; ++k)
        {
          planes[k][c + 1] = ghost(c, k);
        }
      }
    }
    for (int k = 0; k < NC; ++k)
    {
      planes[k][0] = ghost(-1, k);
      planes[k][w + 1] = ghost(w, k);
    }
  }

  /// planes[k][1 + c] = from[c NC + k], c < w.
  CLONES static void DeinterleaveRow(Index w, const double* __restrict from, double* const* planes)
  {
    if (NC == 1)
    {
      std::copy(from, from + w, planes[0] + 1);
      return;
    }
    double* __restrict to[NC];
    for (int k = 0; k < NC; ++k)
    {
      to[k] = planes[k] + 1;
    }
    for (Index c = 0; c < w; ++c)
    {
#pragma GCC unroll 8
      for (int k = 0; k < NC; ++k)
      {
        to[k][c] = from[c * NC + k];
      }
    }
  }

  /// The four triangles of the cells between the padded pixel rows `top`
  /// and `bottom` (planes), columns -1 .. W-1, into out (CellSlots arrays
  /// of W + 1 values; `dots` is scratch of CellDots arrays): the dot
  /// products of the edge vectors and the triangles' squared twice-areas,
  /// then the triangles.
  /// The areas are sums of squared 2x2 minors of two edge vectors
  /// (Lagrange's identity), not |u|^2 |v|^2 - (u.v)^2, which cancels in
  /// single precision across steep edges.
  CLONES void CellRow(const double* const* top, const double* const* bottom, PixelReal* __restrict out,
    PixelReal* __restrict dots) const
  {
    using R = PixelReal;
    const std::int64_t n = Grid.Width + 1;
    const R sx2 = static_cast<R>(Grid.SpacingX * Grid.SpacingX), sy2 = static_cast<R>(Grid.SpacingY * Grid.SpacingY);
#pragma GCC ivdep // the slot arrays never overlap
    for (std::int64_t j = 0; j < n; ++j)
    {
      // The data parts of the edge vectors (double differences, then single).
      R ab[NC], ac[NC], ad[NC], bc[NC], bd[NC], dc[NC];
#pragma GCC unroll 8
      for (int k = 0; k < NC; ++k)
      {
        const double a = top[k][j], b = top[k][j + 1], d = bottom[k][j], c = bottom[k][j + 1];
        ab[k] = static_cast<R>(b - a);
        ac[k] = static_cast<R>(c - a);
        ad[k] = static_cast<R>(d - a);
        bc[k] = static_cast<R>(c - b);
        bd[k] = static_cast<R>(d - b);
        dc[k] = static_cast<R>(c - d);
      }
      // Full R^(2+n) dot products: base part + data part.
      R nab = 0, nad = 0, nbc = 0, ndc = 0, acac = sx2 + sy2, bdbd = sx2 + sy2;
      R abac = sx2, acad = sy2, abad = 0, bcbd = sy2;
#pragma GCC unroll 8
      for (int k = 0; k < NC; ++k)
      {
        nab += ab[k] * ab[k];
        nad += ad[k] * ad[k];
        nbc += bc[k] * bc[k];
        ndc += dc[k] * dc[k];
        acac += ac[k] * ac[k];
        bdbd += bd[k] * bd[k];
        abac += ab[k] * ac[k];
        acad += ac[k] * ad[k];
        abad += ab[k] * ad[k];
        bcbd += bc[k] * bd[k];
      }
      // Each triangle has an x edge (ab or dc) and a y edge (ad or bc).
      const R base = sx2 * sy2;
      dots[AB_AB * n + j] = sx2 + nab;
      dots[AC_AC * n + j] = acac;
      dots[AD_AD * n + j] = sy2 + nad;
      dots[BC_BC * n + j] = sy2 + nbc;
      dots[BD_BD * n + j] = bdbd;
      dots[AB_AC * n + j] = abac;
      dots[AC_AD * n + j] = acad;
      dots[AB_AD * n + j] = abad;
      dots[BC_BD * n + j] = bcbd;
      dots[AREA_ABC * n + j] = base + sy2 * nab + sx2 * nbc + DataMinors(ab, bc);
      dots[AREA_ACD * n + j] = base + sy2 * ndc + sx2 * nad + DataMinors(dc, ad);
      dots[AREA_ABD * n + j] = base + sy2 * nab + sx2 * nad + DataMinors(ab, ad);
      dots[AREA_BCD * n + j] = base + sy2 * ndc + sx2 * nbc + DataMinors(dc, bc);
    }
    TriangleRow(n, dots, out);
  }

  /// The sum of the squared 2x2 minors of two edge vectors' data parts
  /// (zero for one component).
  static PixelReal DataMinors(const PixelReal (&x)[NC], const PixelReal (&y)[NC])
  {
    PixelReal sum = 0;
#pragma GCC unroll 8
    for (int k = 0; k < NC; ++k)
    {
#pragma GCC unroll 8
      for (int l = k + 1; l < NC; ++l)
      {
        const PixelReal m = x[k] * y[l] - x[l] * y[k];
        sum += m * m;
      }
    }
    return sum;
  }

  /// PixelRow compiled for each output (and unit speed, gamma = 1).
  void Row(PixelOutput output, std::int64_t r, PaddedRows& rows, const PixelReal* upper, const PixelReal* lower, double* sums, double dt,
    double* next)
  {
    const bool unit = Gamma == 1.0;
    switch (output)
    {
      case PixelOutput::Operator:
        return PixelRow<PixelOutput::Operator, false>(r, rows, upper, lower, sums, dt, next);
      case PixelOutput::Velocity:
        return unit ? PixelRow<PixelOutput::Velocity, true>(r, rows, upper, lower, sums, dt, next)
                    : PixelRow<PixelOutput::Velocity, false>(r, rows, upper, lower, sums, dt, next);
      case PixelOutput::Step:
        return unit ? PixelRow<PixelOutput::Step, true>(r, rows, upper, lower, sums, dt, next)
                    : PixelRow<PixelOutput::Step, false>(r, rows, upper, lower, sums, dt, next);
      case PixelOutput::None:
        return unit ? PixelRow<PixelOutput::None, true>(r, rows, upper, lower, sums, dt, next)
                    : PixelRow<PixelOutput::None, false>(r, rows, upper, lower, sums, dt, next);
    }
  }

  /// Pixels per chunk of a row's evaluation (PixelRow).
  static constexpr Index PixelChunk = 256;

  /// The 8 edge weights (slots of Neighbor), the mass and the sum of the
  /// positive weights of m pixels from the cell rows above (upper) and
  /// below (lower) them, both from the pixels' first column, in arrays of n.
  CLONES static void EdgeWeights(Index m, const PixelReal* __restrict upper, const PixelReal* __restrict lower,
    std::int64_t n, double (&weights)[8][PixelChunk], double* __restrict mass, double* __restrict positive)
  {
    using R = PixelReal;
#pragma GCC ivdep // the slot arrays never overlap
    for (Index c = 0; c < m; ++c)
    {
      // Cells with this pixel as corner a (lower, c + 1), b (lower, c),
      // c (upper, c) and d (upper, c + 1).
      R wn[8];
      wn[E] = lower[Top * n + c + 1] + upper[Bottom * n + c + 1];
      wn[W] = lower[Top * n + c] + upper[Bottom * n + c];
      wn[S] = lower[Left * n + c + 1] + lower[Right * n + c];
      wn[N] = upper[Left * n + c + 1] + upper[Right * n + c];
      wn[SE] = lower[DiagAC * n + c + 1];
      wn[NW] = upper[DiagAC * n + c];
      wn[SW] = lower[DiagBD * n + c];
      wn[NE] = upper[DiagBD * n + c + 1];
      mass[c] = lower[MassA * n + c + 1] + lower[MassB * n + c] + upper[MassC * n + c] + upper[MassD * n + c + 1];
      R sum = 0;
      for (int nb = 0; nb < 8; ++nb)
      {
        weights[nb][c] = wn[nb];
        sum += std::max(wn[nb], R(0));
      }
      positive[c] = sum;
    }
  }

  /// Pixel row r from the cell rows above (upper, row r) and below (lower,
  /// row r + 1): the weights of the 8 edges, the mass, K u, the indicator
  /// max(|B_bar| / |B|, 1/W) (GraphFlow.h), what Output says (the
  /// velocity, the operator, or the step from the state into next) and the
  /// row's area and stability rate.
  template <PixelOutput Output, bool UnitSpeed>
  CLONES void PixelRow(std::int64_t r, PaddedRows& rows, const PixelReal* __restrict upper,
    const PixelReal* __restrict lower, double* __restrict sums, double dt, double* __restrict next)
  {
    constexpr bool Store = Output == PixelOutput::Operator;
    const Index w = Grid.Width;
    const std::int64_t n = w + 1;
    const double sx = Grid.SpacingX, sy = Grid.SpacingY;
    const double* p0[NC]; // pixel rows r - 1, r, r + 1 at column -1
    const double* p1[NC];
    const double* p2[NC];
    for (int k = 0; k < NC; ++k)
    {
      p0[k] = rows.At(r - 1)[k];
      p1[k] = rows.At(r)[k];
      p2[k] = rows.At(r + 1)[k];
    }
    const std::uint8_t* fixed = &Fixed[r * w];
    double* __restrict out = Output == PixelOutput::Step ? next + r * w * NC
      : Output == PixelOutput::None                     ? nullptr
                                                        : Velocity.data() + r * w * NC;
    double* __restrict masses = sums;
    double* __restrict rates = sums + w;
    // In chunks of pixels: their edge weights, masses and positive weight
    // sums in single precision into double arrays, then K u and the rest in
    // double (one loop of mixed widths spilled half its vectors).
    alignas(64) double weights[8][PixelChunk], chunkMass[PixelChunk], chunkPositive[PixelChunk];
    for (Index c0 = 0; c0 < w; c0 += PixelChunk)
    {
      const Index m = std::min<Index>(PixelChunk, w - c0);
      EdgeWeights(m, upper + c0, lower + c0, n, weights, chunkMass, chunkPositive);
#pragma GCC ivdep // the slot arrays never overlap
      for (Index c = c0; c < c0 + m; ++c)
      {
        const Index l = c - c0;
        double wn[8];
        for (int nb = 0; nb < 8; ++nb)
        {
          wn[nb] = weights[nb][l];
        }
        const double mass = chunkMass[l];
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
        for (int k = 0; k < NC && Output != PixelOutput::None; ++k)
        {
          // (the explicit step as FlowIntegrator::ExplicitStep takes it)
          out[c * NC + k] = Output == PixelOutput::Step ? p1[k][c + 1] - dt * (f * ku[k]) : f * ku[k];
        }
        masses[c] = mass;
        rates[c] = f * chunkPositive[l];
        if (Store)
        {
          StoreOperatorAt(r * w + c, wn, mass, speed, ku);
        }
      }
    }
    double area = 0.0, rate = 0.0;
    const auto add = [&](std::int64_t begin, std::int64_t end) {
      area += MassAndRate(end - begin, masses + begin, rates + begin, rate);
    };
    Split ? Owned.ForEach(r, add) : add(0, w); // (a split grid: the pixels it owns)
    RowArea[r] = area;
    RowRate[r] = rate;
  }

  /// Pixel i's part of the semi-implicit operator: its weights, mass,
  /// diagonal, speed and K u.
  void StoreOperatorAt(std::int64_t i, const double (&wn)[8], double mass, double speed, const double (&ku)[NC])
  {
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

  /// The sum of n masses and the largest of n rates (into rate): eight
  /// partial sums in a fixed order (one vector, not a chain of n dependent
  /// additions), so the sum is the same for any thread count.
  CLONES static double MassAndRate(std::int64_t n, const double* __restrict masses, const double* __restrict rates,
    double& rate)
  {
    double sum[8] = {}, top[8] = {};
    std::int64_t c = 0;
    for (; c + 8 <= n; c += 8)
    {
      for (int l = 0; l < 8; ++l)
      {
        sum[l] += masses[c + l];
        top[l] = std::max(top[l], rates[c + l]);
      }
    }
    for (int l = 0; c + l < n; ++l)
    {
      sum[l] += masses[c + l];
      top[l] = std::max(top[l], rates[c + l]);
    }
    double total = 0.0;
    for (int l = 0; l < 8; ++l)
    {
      total += sum[l];
      rate = std::max(rate, top[l]);
    }
    return total;
  }
};

template <int NC>
GraphFlowResult RunGrid(const PixelGrid& grid, double* values, const std::uint8_t* fixed,
  const GraphFlowOptions& o, const ProgressCallback& progress, const GridPiece* piece)
{
  // The grid (or a band of its rows, from row `first`).
  const auto band = [&](Index first, Index rows) -> std::unique_ptr<FlowDiscretization> {
    PixelGrid g = grid;
    g.Height = rows;
    auto disc = std::make_unique<GridDiscretization<NC>>(
      g, o.Boundary, o.EdgeContrast, o.NumberOfThreads, o.Integration == GraphFlowIntegration::SemiImplicit, piece);
    if (fixed)
    {
      const std::uint8_t* from = fixed + static_cast<std::size_t>(first) * grid.Width;
      std::copy(from, from + disc->Size, disc->Fixed.begin());
    }
    return disc;
  };
  if (piece && piece->Split)
  {
    return Integrate([&]() { return band(0, grid.Height); }, values, o, progress); // (the probe on every piece)
  }
  return Integrate([&]() { return band(0, grid.Height); }, values, o, progress,
    // A band of 1/8 of the rows for the risk's probe (images of more than
    // 2^21 values): an image's rows differ more than a volume's planes; with
    // 1/16 a noisy astronaut at 1024 x 1024 RGB stopped 3 steps late, 0.12 dB
    // below the whole image's probe (1/8: 0.07 dB, at half the time).
    GridProbeWindow(grid.Height, grid.Width, NC, 8, o, band));
}

} // namespace

GraphFlowResult RunImageGraphFlow(const PixelGrid& grid, int components, double* values,
  const std::uint8_t* fixed, const GraphFlowOptions& options, const ProgressCallback& progress,
  const GridPiece* piece)
{
  const bool split = piece && piece->Split; // (every process runs, an empty piece too)
  GraphFlowResult result;
  result.Error = CheckOptions(options, components, 6, "images");
  if (result.Error.empty() &&
    (!(grid.SpacingX > 0.0) || !(grid.SpacingY > 0.0) || !std::isfinite(grid.SpacingX) ||
      !std::isfinite(grid.SpacingY)))
  {
    result.Error = "the pixel spacing must be positive and finite";
  }
  if (!result.Error.empty() || (!split && (grid.Width <= 0 || grid.Height <= 0)))
  {
    return result;
  }
  return WithCount<6>(components, [&](auto nc) { // kernels compiled per component count
    return RunGrid<decltype(nc)::value>(grid, values, fixed, options, progress, piece);
  });
}

} // namespace beltrami
