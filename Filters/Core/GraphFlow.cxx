#include "GraphFlow.h"

#include "ConjugateGradient.h"
#include "Laplacian.h"

#include <algorithm>
#include <cmath>
#include <memory>
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
  // Filled by Update(u):
  std::vector<double> Mass, Speed, Diagonal, KU; ///< a_i, s_i, sum_j c_ij, K u (with ghosts)
  double Area = 0.0;    ///< area of the graph surface
  double MaxRate = 0.0; ///< max over free vertices of s_i sum_j max(c_ij, 0) / a_i

  /// Weights, masses and speeds at state u (scaled data, Components per vertex).
  virtual void Update(const double* u) = 0;
  /// y = K x; ghosts: include the values the boundary rule derives from x
  /// outside the domain (images; false: those neighbours count as zero).
  virtual void Apply(const double* x, double* y, bool ghosts) = 0;

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
    return std::pow(e, Gamma - 1.0);
  }

  void Allocate()
  {
    Mass.assign(Size, 0.0);
    Speed.assign(Size, 1.0);
    Diagonal.assign(Size, 0.0);
    KU.assign(static_cast<std::size_t>(Size) * Components, 0.0);
  }

  /// Largest s_i sum_j c_ij^+ / a_i over free vertices, from per-vertex
  /// positive weight sums (deterministic: a maximum does not depend on order).
  void ComputeMaxRate(const std::vector<double>& positiveSum)
  {
    const Index n = Size;
    const std::int64_t chunk = 4096;
    const std::int64_t chunks = (n + chunk - 1) / chunk;
    std::vector<double> partial(static_cast<std::size_t>(chunks), 0.0);
    ParallelFor(chunks, Threads, [&](std::int64_t b, std::int64_t e) {
      for (std::int64_t k = b; k < e; ++k)
      {
        double m = 0.0;
        for (std::int64_t i = k * chunk; i < std::min<std::int64_t>(n, (k + 1) * chunk); ++i)
        {
          if (!Fixed[i] && Mass[i] > 0.0)
          {
            m = std::max(m, Speed[i] * positiveSum[i] / Mass[i]);
          }
        }
        partial[k] = m;
      }
    });
    MaxRate = partial.empty() ? 0.0 : *std::max_element(partial.begin(), partial.end());
  }
};

// ---------------------------------------------------------------------------
// Images: the pixel grid triangulated both ways (each cell split along both
// diagonals, the two triangulations summed), so that the operator has the
// symmetry of the grid.  Pixel (x, y) sits at (x sx, y sy, u(x, y)) in
// R^(2+n).  Cotangents and mixed areas (section 2.4.3) of the four triangles
// of every cell come from dot products of the edge vectors (section 2.8.1).

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
/// here: the base part alone has area sx sy / 2).
inline TriangleTerms Triangle(double uu, double vv, double uv)
{
  TriangleTerms t;
  const double twiceArea = std::sqrt(std::max(uu * vv - uv * uv, 0.0));
  const double inv = 1.0 / twiceArea;
  const double dotQ = uu - uv, dotR = vv - uv; // (P-Q).(R-Q), (P-R).(Q-R)
  t.CotP = uv * inv;
  t.CotQ = dotQ * inv;
  t.CotR = dotR * inv;
  if (uv >= 0.0 && dotQ >= 0.0 && dotR >= 0.0)
  {
    const double ww = uu + vv - 2.0 * uv;
    t.MassP = (uu * t.CotR + vv * t.CotQ) / 8.0;
    t.MassQ = (uu * t.CotR + ww * t.CotP) / 8.0;
    t.MassR = (vv * t.CotQ + ww * t.CotP) / 8.0;
  }
  else
  {
    const double area = 0.5 * twiceArea;
    t.MassP = uv < 0.0 ? area / 2.0 : area / 4.0;
    t.MassQ = dotQ < 0.0 ? area / 2.0 : area / 4.0;
    t.MassR = dotR < 0.0 ? area / 2.0 : area / 4.0;
  }
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

template <int NC>
class GridDiscretization final : public FlowDiscretization
{
public:
  GridDiscretization(const PixelGrid& grid, GridBoundary boundary, double gamma, int threads)
    : Grid(grid)
    , Boundary(boundary)
  {
    Gamma = gamma;
    Threads = threads;
    Size = grid.Width * grid.Height;
    Components = NC;
    PW = grid.Width + 2;
    PH = grid.Height + 2;
    Padded.resize(static_cast<std::size_t>(PW) * PH * NC);
    Cells.resize(static_cast<std::size_t>(grid.Width + 1) * (grid.Height + 1) * CellSlots);
    Weights.resize(static_cast<std::size_t>(Size) * 8);
    Allocate();
    Fixed.assign(Size, 0);
    // Area scale for the indicator's guard (B has units 1/length).
    Epsilon2 = 1e-18 / std::pow(std::min(grid.SpacingX, grid.SpacingY), 2);
  }

  void Update(const double* u) override
  {
    Pad(u, true);
    ComputeCells();
    ComputePixels();
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
            const double* xj = PaddedAt(r + NeighborDy[nb], c + NeighborDx[nb]);
            for (int k = 0; k < NC; ++k)
            {
              acc[k] -= wi[nb] * xj[k];
            }
          }
          for (int k = 0; k < NC; ++k)
          {
            y[i * NC + k] = acc[k];
          }
        }
      }
    });
  }

private:
  PixelGrid Grid;
  GridBoundary Boundary;
  Index PW = 0, PH = 0;
  std::vector<double> Padded;  // (H+2) x (W+2) x NC
  std::vector<double> Cells;   // (H+1) x (W+1) x CellSlots
  std::vector<double> Weights; // H x W x 8 (slots of Neighbor)
  std::vector<double> PositiveSum;
  double Epsilon2 = 0.0;

  /// Pixel (r, c), -1 <= r <= H, -1 <= c <= W, of the padded copy.
  const double* PaddedAt(std::int64_t r, std::int64_t c) const
  {
    return &Padded[((r + 1) * PW + (c + 1)) * NC];
  }

  /// Copies x into the padded buffer; the border ring gets the boundary rule
  /// (ghosts) or zeros.
  void Pad(const double* x, bool ghosts)
  {
    const Index w = Grid.Width, h = Grid.Height;
    ParallelFor(h, Threads, [&](std::int64_t r0, std::int64_t r1) {
      for (std::int64_t r = r0; r < r1; ++r)
      {
        std::copy(x + r * w * NC, x + (r + 1) * w * NC, &Padded[((r + 1) * PW + 1) * NC]);
      }
    });
    const auto clampIndex = [](std::int64_t v, std::int64_t n) {
      return std::min<std::int64_t>(std::max<std::int64_t>(v, 0), n - 1);
    };
    const auto ghost = [&](std::int64_t r, std::int64_t c) {
      double* dst = &Padded[((r + 1) * PW + (c + 1)) * NC];
      if (!ghosts)
      {
        std::fill(dst, dst + NC, 0.0);
        return;
      }
      const std::int64_t br = clampIndex(r, h), bc = clampIndex(c, w);
      const std::int64_t rr = clampIndex(2 * br - r, h), rc = clampIndex(2 * bc - c, w);
      const double* base = x + (br * w + bc) * NC;
      const double* mirror = x + (rr * w + rc) * NC;
      for (int k = 0; k < NC; ++k)
      {
        dst[k] = Boundary == GridBoundary::Reflect ? mirror[k] : 2.0 * base[k] - mirror[k];
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

  /// Pass 1: the four triangles of every cell, -1 <= row < H, -1 <= col < W.
  void ComputeCells()
  {
    const Index w = Grid.Width, h = Grid.Height;
    const double sx2 = Grid.SpacingX * Grid.SpacingX, sy2 = Grid.SpacingY * Grid.SpacingY;
    ParallelFor(h + 1, Threads, [&](std::int64_t q0, std::int64_t q1) {
      for (std::int64_t q = q0; q < q1; ++q)
      {
        const std::int64_t r = q - 1;
        for (std::int64_t c = -1; c < w; ++c)
        {
          const double* a = PaddedAt(r, c);
          const double* b = PaddedAt(r, c + 1);
          const double* cc = PaddedAt(r + 1, c + 1);
          const double* d = PaddedAt(r + 1, c);
          double ab[NC], ac[NC], ad[NC], bc[NC], bd[NC];
          for (int k = 0; k < NC; ++k)
          {
            ab[k] = b[k] - a[k];
            ac[k] = cc[k] - a[k];
            ad[k] = d[k] - a[k];
            bc[k] = cc[k] - b[k];
            bd[k] = d[k] - b[k];
          }
          // Full R^(2+n) dot products: base part + data part.
          const double abab = sx2 + Dot<NC>(ab, ab), acac = sx2 + sy2 + Dot<NC>(ac, ac);
          const double adad = sy2 + Dot<NC>(ad, ad), bcbc = sy2 + Dot<NC>(bc, bc);
          const double bdbd = sx2 + sy2 + Dot<NC>(bd, bd);
          const double abac = sx2 + Dot<NC>(ab, ac), acad = sy2 + Dot<NC>(ac, ad);
          const double abad = Dot<NC>(ab, ad), bcbd = sy2 + Dot<NC>(bc, bd);
          const TriangleTerms abc = Triangle(abab, acac, abac); // P=a, Q=b, R=c
          const TriangleTerms acd = Triangle(acac, adad, acad); // P=a, Q=c, R=d
          const TriangleTerms abd = Triangle(abab, adad, abad); // P=a, Q=b, R=d
          const TriangleTerms bcd = Triangle(bcbc, bdbd, bcbd); // P=b, Q=c, R=d
          double* cell = &Cells[(q * (w + 1) + (c + 1)) * CellSlots];
          cell[Top] = 0.5 * (abc.CotR + abd.CotR);
          cell[Bottom] = 0.5 * (acd.CotP + bcd.CotP);
          cell[Left] = 0.5 * (acd.CotQ + abd.CotQ);
          cell[Right] = 0.5 * (abc.CotP + bcd.CotR);
          cell[DiagAC] = 0.5 * (abc.CotQ + acd.CotR);
          cell[DiagBD] = 0.5 * (abd.CotP + bcd.CotQ);
          cell[MassA] = abc.MassP + acd.MassP + abd.MassP;
          cell[MassB] = abc.MassQ + abd.MassQ + bcd.MassP;
          cell[MassC] = abc.MassR + acd.MassQ + bcd.MassQ;
          cell[MassD] = acd.MassR + abd.MassR + bcd.MassR;
        }
      }
    });
  }

  /// Pass 2: per pixel, the weights of its 8 edges, its mass, K u, the
  /// indicator |B_bar| / |B| and the positive weight sum.
  void ComputePixels()
  {
    const Index w = Grid.Width, h = Grid.Height;
    const double sx = Grid.SpacingX, sy = Grid.SpacingY;
    PositiveSum.resize(Size);
    const std::int64_t cw = w + 1;
    ParallelFor(h, Threads, [&](std::int64_t r0, std::int64_t r1) {
      for (std::int64_t r = r0; r < r1; ++r)
      {
        for (Index c = 0; c < w; ++c)
        {
          const std::int64_t i = r * w + c;
          // Cells with this pixel as corner a, b, c, d.
          const double* ca = &Cells[((r + 1) * cw + (c + 1)) * CellSlots];
          const double* cb = &Cells[((r + 1) * cw + c) * CellSlots];
          const double* cc = &Cells[(r * cw + c) * CellSlots];
          const double* cd = &Cells[(r * cw + (c + 1)) * CellSlots];
          double* wi = &Weights[i * 8];
          wi[E] = ca[Top] + cd[Bottom];
          wi[W] = cb[Top] + cc[Bottom];
          wi[S] = ca[Left] + cb[Right];
          wi[N] = cd[Left] + cc[Right];
          wi[SE] = ca[DiagAC];
          wi[NW] = cc[DiagAC];
          wi[SW] = cb[DiagBD];
          wi[NE] = cd[DiagBD];
          const double mass = ca[MassA] + cb[MassB] + cc[MassC] + cd[MassD];
          const double* ui = PaddedAt(r, c);
          double ku[NC];
          double diag = 0.0, positive = 0.0, bx = 0.0, by = 0.0;
          for (int k = 0; k < NC; ++k)
          {
            ku[k] = 0.0;
          }
          for (int nb = 0; nb < 8; ++nb)
          {
            const double wn = wi[nb];
            diag += wn;
            positive += std::max(wn, 0.0);
            bx += wn * NeighborDx[nb];
            by += wn * NeighborDy[nb];
            const double* uj = PaddedAt(r + NeighborDy[nb], c + NeighborDx[nb]);
            for (int k = 0; k < NC; ++k)
            {
              ku[k] += wn * (ui[k] - uj[k]);
            }
          }
          bx *= sx;
          by *= sy;
          const double data2 = Dot<NC>(ku, ku);
          const double indicator =
            std::sqrt((data2 + Epsilon2 * mass * mass) / (data2 + bx * bx + by * by + Epsilon2 * mass * mass));
          Mass[i] = mass;
          Diagonal[i] = diag;
          PositiveSum[i] = positive;
          Speed[i] = SpeedOf(indicator);
          for (int k = 0; k < NC; ++k)
          {
            KU[i * NC + k] = ku[k];
          }
        }
      }
    });
    Area = 0.5 * ParallelSum(Size, 1, Threads, [&](std::int64_t b, std::int64_t e, double* acc) {
      for (std::int64_t i = b; i < e; ++i)
      {
        acc[0] += Mass[i];
      }
    })[0];
    ComputeMaxRate(PositiveSum);
  }
};

// ---------------------------------------------------------------------------
// Surfaces: the mesh with the data as extra coordinates, (x, y, z, alpha f)
// in R^(3+n); the cotangent Laplacian of that embedding from the shared
// assembler.  The indicator is the area ratio A_base / A_graph (1/W).

class SurfaceDiscretization final : public FlowDiscretization
{
public:
  SurfaceDiscretization(const MeshTopology& topo, const double* points, int components,
    const std::uint8_t* fixed, double gamma, int threads)
    : Topology(topo)
    , Points(points)
  {
    Gamma = gamma;
    Threads = threads;
    Size = topo.NumberOfVertices();
    Components = components;
    Allocate();
    GraphLaplacian base;
    AssembleSurfaceLaplacian(topo, points, LaplacianWeights::Cotangent, base, threads);
    BaseArea = base.Mass;
    Fixed.assign(Size, 0);
    for (Index i = 0; i < Size; ++i)
    {
      const std::uint8_t flags = topo.VertexFlags(i);
      Fixed[i] = (fixed && fixed[i]) || (flags & ~VertexBoundary) != 0 || !(BaseArea[i] > 0.0);
    }
    Embedded.resize(static_cast<std::size_t>(Size) * (3 + components));
  }

  void Update(const double* u) override
  {
    const int dim = 3 + Components;
    ParallelFor(Size, Threads, [&](std::int64_t b, std::int64_t e) {
      for (std::int64_t i = b; i < e; ++i)
      {
        std::copy(Points + 3 * i, Points + 3 * i + 3, &Embedded[i * dim]);
        std::copy(u + i * Components, u + (i + 1) * Components, &Embedded[i * dim + 3]);
      }
    });
    AssembleSurfaceLaplacian(Topology, Embedded.data(), dim, LaplacianWeights::Cotangent, Laplacian, Threads);
    Positive.resize(Size);
    ParallelFor(Size, Threads, [&](std::int64_t b, std::int64_t e) {
      for (std::int64_t i = b; i < e; ++i)
      {
        // c = cot/4 and a = A_Mixed / 2 give -K u / a = Delta_g u.
        Mass[i] = 0.5 * Laplacian.Mass[i];
        Diagonal[i] = Laplacian.Diagonal[i];
        double p = 0.0;
        for (std::int64_t k = Laplacian.Offsets[i]; k < Laplacian.Offsets[i + 1]; ++k)
        {
          p += std::max(Laplacian.Weights[k], 0.0);
        }
        Positive[i] = p;
        Speed[i] = Laplacian.Mass[i] > 0.0 ? SpeedOf(BaseArea[i] / Laplacian.Mass[i]) : 1.0;
        if (!(Mass[i] > 0.0))
        {
          Fixed[i] = 1; // lost its area (degenerate graph triangles)
        }
      }
    });
    Laplacian.ApplyStiffness(u, KU.data(), Components, Threads);
    Area = ParallelSum(Size, 1, Threads, [&](std::int64_t b, std::int64_t e, double* acc) {
      for (std::int64_t i = b; i < e; ++i)
      {
        acc[0] += Laplacian.Mass[i];
      }
    })[0];
    ComputeMaxRate(Positive);
  }

  void Apply(const double* x, double* y, bool) override
  {
    Laplacian.ApplyStiffness(x, y, Components, Threads);
  }

private:
  const MeshTopology& Topology;
  const double* Points;
  std::vector<double> BaseArea, Embedded, Positive;
  GraphLaplacian Laplacian;
};

// ---------------------------------------------------------------------------

std::string CheckOptions(const GraphFlowOptions& o)
{
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
  std::vector<double> u(size), u0(size), next(size), rhs(size), diag(n);
  for (std::size_t k = 0; k < size; ++k)
  {
    u0[k] = u[k] = alpha * values[k];
  }
  const auto rmsChange = [&]() {
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
      ParallelFor(n, threads, [&](std::int64_t b, std::int64_t e) {
        for (std::int64_t i = b; i < e; ++i)
        {
          const double f = disc.Fixed[i] || !(disc.Mass[i] > 0.0) ? 0.0 : dt * disc.Speed[i] / disc.Mass[i];
          for (int k = 0; k < nc; ++k)
          {
            next[i * nc + k] = u[i * nc + k] - f * disc.KU[i * nc + k];
          }
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
          diag[i] = d + disc.Diagonal[i];
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
            const double d = diag[i] - disc.Diagonal[i];
            for (int k = 0; k < nc; ++k)
            {
              y[i * nc + k] += d * x[i * nc + k];
            }
          }
        });
      };
      next = u; // initial guess and fixed values
      result.SolverIterations += SolveConjugateGradient(cg, rhs.data(), next.data()).Iterations;
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
      const double disc2 = s[1] * s[1] - s[2] * (s[0] - target);
      const double t = s[2] > 0.0 && disc2 >= 0.0 ? std::min(1.0, std::max(0.0, (-s[1] + std::sqrt(disc2)) / s[2])) : 1.0;
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

template <int NC>
GraphFlowResult RunGrid(const PixelGrid& grid, double* values, const std::uint8_t* fixed,
  const GraphFlowOptions& o, const ProgressCallback& progress)
{
  GridDiscretization<NC> disc(grid, o.Boundary, o.EdgeContrast, o.NumberOfThreads);
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
  result.Error = CheckOptions(options);
  if (result.Error.empty() && (components < 1 || components > 6))
  {
    result.Error = "images with 1 to 6 components are supported";
  }
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
  switch (components)
  {
    case 1: return RunGrid<1>(grid, values, fixed, options, progress);
    case 2: return RunGrid<2>(grid, values, fixed, options, progress);
    case 3: return RunGrid<3>(grid, values, fixed, options, progress);
    case 4: return RunGrid<4>(grid, values, fixed, options, progress);
    case 5: return RunGrid<5>(grid, values, fixed, options, progress);
    default: return RunGrid<6>(grid, values, fixed, options, progress);
  }
}

GraphFlowResult RunSurfaceGraphFlow(const MeshTopology& topology, const double* points,
  int components, double* values, const std::uint8_t* fixed, const GraphFlowOptions& options,
  const ProgressCallback& progress)
{
  GraphFlowResult result;
  result.Error = CheckOptions(options);
  if (result.Error.empty() && (components < 1 || components > 5))
  {
    result.Error = "point data with 1 to 5 components are supported";
  }
  if (!result.Error.empty() || topology.NumberOfVertices() == 0)
  {
    return result;
  }
  SurfaceDiscretization disc(topology, points, components, fixed, options.EdgeContrast, options.NumberOfThreads);
  return Integrate(disc, values, options, progress);
}

} // namespace beltrami
