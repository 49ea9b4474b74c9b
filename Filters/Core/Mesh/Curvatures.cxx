#include "Mesh/Curvatures.h"

#pragma GCC diagnostic ignored "-Wpsabi" // (lanes::Real in RingGeometry.h's templates: see Support/LaneVectors.h)

#include "Mesh/MeshMeasures.h"
#include "Mesh/RingGeometry.h"

#include "Support/LaneVectors.h"
#include "Support/Vectorization.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <atomic>
#include <limits>
#include <vector>

namespace beltrami
{

namespace
{

constexpr double NaN = std::numeric_limits<double>::quiet_NaN();
/// cos(60 deg): K/|K| is used as the normal only this close to the face normals.
constexpr double MinimumNormalCosine = 0.5;
/// The least cotangent weight (per triangle) of an edge sample in the
/// direction fit: right-triangle grids give their diagonals weight 0, and
/// without them the fit cannot tell the directions apart from the grid's
/// axes (on a regular grid of a Gaussian bump e1 was up to 50 degrees off).
constexpr double MinimumFitCotangent = 0.1;
constexpr std::uint8_t UndefinedMask = VertexBoundary | VertexNonManifold | VertexDuplicateFace |
  VertexIsolated;

void Store(double* array, Index i, double value)
{
  if (array)
  {
    array[i] = value;
  }
}

void Store(double* array, Index i, const Vec3& value)
{
  if (array)
  {
    Eigen::Map<Vec3>(array + 3 * static_cast<std::int64_t>(i)) = value;
  }
}

/// An edge sample of the 1-ring: the edge vector x_j - x_i, its length squared
/// and the cotangent weight of the triangle that contributes it.
struct EdgeSample
{
  Vec3 E;
  double EE;
  double Cot;
  double Area; ///< area of the contributing triangle (Taubin's weights)
};

/// The direction (cos psi, sin psi) of psi = atan2(y, x) / 2 in (-pi/2, pi/2],
/// from half-angle formulas (no atan2, cos, sin per vertex); (1, 0) if x = y = 0.
Eigen::Vector2d HalfAngleDirection(double y, double x)
{
  const double r = std::sqrt(x * x + y * y); // (curvature-sized: hypot's overflow guard costs, not needed)
  if (!(r > 0.0))
  {
    return { 1.0, 0.0 };
  }
  if (x >= 0.0)
  {
    const double c = std::sqrt((r + x) / (2.0 * r));
    return { c, y / (2.0 * r * c) };
  }
  const double s = std::sqrt((r - x) / (2.0 * r));
  return { std::abs(y) / (2.0 * r * s), y < 0.0 ? -s : s };
}

/// Projection of an edge onto the tangent plane as the angle 2*phi
/// (cos 2phi, sin 2phi), and the normal curvature estimate
/// kappa^N = 2 (x_i - x_j).n / |x_i - x_j|^2 (eq. 2.12, figure A.1); en is
/// the edge's normal component (x_j - x_i).n.
bool ProjectSample(const EdgeSample& s, const Vec3& n, const Vec3& u, const Vec3& v,
  double& cos2, double& sin2, double& en)
{
  if (!(s.EE > 0.0))
  {
    return false;
  }
  en = s.E.dot(n);
  const double pu = s.E.dot(u), pv = s.E.dot(v); // u, v are orthogonal to n
  const double r2 = pu * pu + pv * pv;
  if (!(r2 > 1e-12 * s.EE))
  {
    return false;
  }
  const double inverse = 1.0 / r2;
  cos2 = (pu * pu - pv * pv) * inverse;
  sin2 = 2.0 * pu * pv * inverse;
  return true;
}

/// Principal directions by the least-squares fit of section 2.6.2 with the
/// trace constraint a + c = 2 kappa_H: the tensor is
/// [[kH + d, b], [b, kH - d]] and the samples give a 2x2 normal system in
/// (d, b).  Returns e1 in the (u, v) frame: (cos psi, sin psi).
Eigen::Vector2d FitMeyerDirection(const std::vector<EdgeSample>& samples, double kappaH, const Vec3& n,
  const Vec3& u, const Vec3& v)
{
  double s11 = 0, s12 = 0, s22 = 0, r1 = 0, r2 = 0;
  for (const EdgeSample& s : samples)
  {
    double c, sn, en;
    if (!ProjectSample(s, n, u, v, c, sn, en))
    {
      continue;
    }
    // w_ij = (cot a + cot b)|e|^2 / 8, each triangle contributing its half;
    // negative weights (obtuse triangles) are clamped to keep the fit convex.
    // w (kappa^N - kappa_H) = -cot en / 4 - w kappa_H: no division by |e|^2.
    const double cot = std::max(MinimumFitCotangent, s.Cot);
    const double w = cot * s.EE / 8.0;
    const double weightedResidual = -0.25 * cot * en - w * kappaH;
    s11 += w * c * c;
    s12 += w * c * sn;
    s22 += w * sn * sn;
    r1 += weightedResidual * c;
    r2 += weightedResidual * sn;
  }
  // A tiny Tikhonov term picks the least-norm solution when the samples do
  // not determine both unknowns (e.g. right-triangle grids, whose diagonals
  // have zero cotangent weight).
  const double lambda = 1e-10 * (s11 + s22);
  s11 += lambda;
  s22 += lambda;
  const double det = s11 * s22 - s12 * s12;
  if (!(det > 0.0))
  {
    return { 1.0, 0.0 }; // no usable sample: any tangent direction is as good
  }
  const double d = (s22 * r1 - s12 * r2) / det;
  const double b = (s11 * r2 - s12 * r1) / det;
  return HalfAngleDirection(b, d);
}

/// Taubin (1995): M = sum_i w_i kappa^N(t_i) t_i t_i^T with area weights
/// summing to one; kappa_1,2 = 3 lambda_1,2 - lambda_2,1.
void FitTaubin(const std::vector<EdgeSample>& samples, const Vec3& n, const Vec3& u,
  const Vec3& v, double& k1, double& k2, Eigen::Vector2d& psi)
{
  double m11 = 0, m12 = 0, m22 = 0, wsum = 0;
  for (const EdgeSample& s : samples)
  {
    double c, sn, en;
    if (!ProjectSample(s, n, u, v, c, sn, en))
    {
      continue;
    }
    const double kappaN = -2.0 * en / s.EE;
    // t t^T = [[1 + cos2, sin2], [sin2, 1 - cos2]] / 2
    const double w = s.Area;
    m11 += w * kappaN * (1.0 + c) / 2.0;
    m22 += w * kappaN * (1.0 - c) / 2.0;
    m12 += w * kappaN * sn / 2.0;
    wsum += w;
  }
  if (!(wsum > 0.0))
  {
    k1 = k2 = NaN;
    psi = Eigen::Vector2d::Constant(NaN);
    return;
  }
  m11 /= wsum;
  m12 /= wsum;
  m22 /= wsum;
  const double mean = 0.5 * (m11 + m22);
  const double radius = std::sqrt(0.25 * (m11 - m22) * (m11 - m22) + m12 * m12);
  const double l1 = mean + radius, l2 = mean - radius;
  k1 = 3.0 * l1 - l2;
  k2 = 3.0 * l2 - l1;
  psi = HalfAngleDirection(2.0 * m12, m11 - m22);
}

/// At a regular vertex (`pairs`: its RingPairsBegin), the position of the
/// corner across each corner's leaving edge (MeshTopology::CornerAcross)
/// into `across`; false if one is missing (not a regular fan).
bool FanPartners(const Index* pairs, Index valence, std::vector<Index>& across)
{
  across.resize(valence);
  for (Index a = 0; a < valence; ++a)
  {
    across[a] = MeshTopology::CornerAcross(pairs, valence, a);
    if (across[a] == valence)
    {
      return false;
    }
  }
  return true;
}

/// One vertex's 1-ring, a corner a lane: the edges A = x_j - x_i and
/// B = x_k - x_i of each corner and what MakeCornerGeometry and
/// RingSums::Add make of them, computed lanes::Width corners at a time by
/// ComputeRingCorners (corner by corner, that was most of the kernel's
/// time).  Field f of corner c: (*this)(f, c).
struct RingBatch
{
  enum Field
  {
    Ax, Ay, Az, Bx, By, Bz, // the inputs
    AA, BB, AB, TwiceArea,
    CotJ, CotK, MixedArea, // (0 in degenerate triangles)
    Degenerate,            // 1 or 0
    Px, Py, Pz,            // CotK A + CotJ B: the corner's part of -CotangentSum
    Cx, Cy, Cz,            // A x B
    InverseCross,          // InverseCrossNorm of A x B
    Finite,                // 1 where A and B are finite
    Fields
  };
  Index Stride = 0; // values per field: the corners in whole vectors
  std::vector<double> Data;

  double operator()(int f, Index c) const { return Data[f * Stride + c]; }
  Vec3 Get(int f, Index c) const { return { Data[f * Stride + c], Data[(f + 1) * Stride + c], Data[(f + 2) * Stride + c] }; }

  template <typename T>
  void Gather(const T* points, const Index* pairs, Index valence, const Vec3& xi)
  {
    Stride = (valence + lanes::Width - 1) / lanes::Width * lanes::Width;
    Data.resize(Fields * static_cast<std::size_t>(Stride));
    for (Index c = 0; c < Stride; ++c)
    {
      const Index k = std::min(c, valence - 1); // (spare lanes repeat the last corner)
      const Vec3 a = LoadPoint<3>(points, 3, pairs[2 * k]) - xi, b = LoadPoint<3>(points, 3, pairs[2 * k + 1]) - xi;
      for (int d = 0; d < 3; ++d)
      {
        Data[(Ax + d) * Stride + c] = a[d];
        Data[(Bx + d) * Stride + c] = b[d];
      }
    }
  }
};

/// RingBatch's fields from its inputs (`data`, `stride`: RingBatch's),
/// as MakeCornerGeometry computes them, lanes::Width corners at once, with
/// the same roundings: no fused multiply-adds, which the AVX2 clones would
/// otherwise contract (on flat CAD faces the old sums cancel exactly; with
/// fused ones a rounding residue picked the principal directions there,
/// and those changed with the order of a vertex's triangles, so that split
/// and whole surfaces drew different lines).
#pragma GCC push_options
#pragma GCC optimize("fp-contract=off")
CLONES void ComputeRingCorners(double* data, Index stride)
{
  using namespace lanes;
  using F = RingBatch::Field;
  const Real zero{};
  for (Index v = 0; v < stride; v += Width)
  {
    const auto in = [&](F f) { return Load(data + f * stride + v); };
    const auto out = [&](F f, const Real& x) { lanes::Store(data + f * stride + v, x); };
    const V3 a{ in(F::Ax), in(F::Ay), in(F::Az) }, b{ in(F::Bx), in(F::By), in(F::Bz) };
    const Real aa = Dot(a, a), bb = Dot(b, b), ab = Dot(a, b);
    const Real square = aa * bb - ab * ab;
    const Real twiceArea = Sqrt(square > 0.0 ? square : zero); // (NaN: 0, as std::max(0.0, NaN))
    const Real ee = aa + bb - 2.0 * ab;
    // Written so that NaN also counts as degenerate.
    const Mask defined = twiceArea > DegenerateTolerance * Max(ee, Max(aa, bb));
    const Real inverse = 1.0 / twiceArea;
    const Real cotJ = defined ? (aa - ab) * inverse : zero, cotK = defined ? (bb - ab) * inverse : zero;
    const Real mixed = CornerMixedArea(aa, bb, ab, twiceArea, cotJ, cotK);
    const V3 p = cotK * a + cotJ * b;
    const V3 cross = Cross(a, b);
    out(F::AA, aa);
    out(F::BB, bb);
    out(F::AB, ab);
    out(F::TwiceArea, twiceArea);
    out(F::CotJ, cotJ);
    out(F::CotK, cotK);
    out(F::MixedArea, defined ? mixed : zero);
    out(F::Degenerate, defined ? zero : zero + 1.0);
    out(F::Px, p.X);
    out(F::Py, p.Y);
    out(F::Pz, p.Z);
    out(F::Cx, cross.X);
    out(F::Cy, cross.Y);
    out(F::Cz, cross.Z);
    out(F::InverseCross, 1.0 / Sqrt(cross.X * cross.X + cross.Y * cross.Y + cross.Z * cross.Z)); // (InverseCrossNorm)
    const Mask finite = Finite(a.X) & Finite(a.Y) & Finite(a.Z) & Finite(b.X) & Finite(b.Y) & Finite(b.Z);
    out(F::Finite, finite ? zero + 1.0 : zero);
  }
}
#pragma GCC pop_options

/// The smallest NormalCosine of the edges at a regular vertex, from its
/// corners' cross products in `ring` and FanPartners; 1 if none is defined.
float SharpestCosine(const RingBatch& ring, const std::vector<Index>& across)
{
  double lowest = 1.0;
  for (std::size_t a = 0; a < across.size(); ++a)
  {
    const Index b = across[a];
    const double cosine =
      NormalCosine(ring.Get(RingBatch::Cx, a), ring(RingBatch::InverseCross, a), ring.Get(RingBatch::Cx, b), ring(RingBatch::InverseCross, b));
    lowest = cosine < lowest ? cosine : lowest; // (NaN: left out)
  }
  return static_cast<float>(lowest);
}

/// The samples of the direction fits into `samples`: two per corner, its A
/// with the cotangent at x_k and its B with the one at x_j (each triangle
/// contributes its half of an edge's weight).  At a regular vertex
/// (`across`: FanPartners, empty elsewhere) and `merge`, one per edge
/// instead: corner a's A and the B of corner across[a] are the same
/// vector, and one sample with the sum of both triangles' clamped
/// cotangents is the same to the Meyer fit (linear in the weights), with
/// half the projections.
void EdgeSamples(const RingBatch& ring, Index valence, const std::vector<Index>& across, bool merge,
  std::vector<EdgeSample>& samples)
{
  using F = RingBatch::Field;
  if (merge && !across.empty())
  {
    samples.resize(valence);
    for (Index a = 0; a < valence; ++a)
    {
      const double cot = std::max(MinimumFitCotangent, ring(F::CotK, a)) +
        std::max(MinimumFitCotangent, ring(F::CotJ, across[a]));
      samples[a] = { ring.Get(F::Ax, a), ring(F::AA, a), cot, 0.5 * ring(F::TwiceArea, a) };
    }
    return;
  }
  samples.resize(2 * static_cast<std::size_t>(valence));
  for (Index c = 0; c < valence; ++c)
  {
    samples[2 * c] = { ring.Get(F::Ax, c), ring(F::AA, c), ring(F::CotK, c), 0.5 * ring(F::TwiceArea, c) };
    samples[2 * c + 1] = { ring.Get(F::Bx, c), ring(F::BB, c), ring(F::CotJ, c), 0.5 * ring(F::TwiceArea, c) };
  }
}

template <typename T>
struct CurvatureKernel
{
  const MeshTopology& Topo;
  const T* Points;
  const CurvatureOptions& Options;
  const CurvatureOutputs& Out;
  std::vector<std::uint8_t>& Status;
  bool WantDirections;

  std::atomic<Index> Undefined{ 0 }, Degenerate{ 0 }, NonFinite{ 0 };

  void WriteUndefined(Index i, const Vec3& normal, double mixedArea)
  {
    const Vec3 nan3 = Vec3::Constant(NaN);
    Store(Out.MeanCurvatureNormal, i, nan3);
    Store(Out.MixedArea, i, mixedArea);
    Store(Out.MeanCurvature, i, NaN);
    Store(Out.GaussianCurvature, i, NaN);
    Store(Out.MaximumCurvature, i, NaN);
    Store(Out.MinimumCurvature, i, NaN);
    Store(Out.PrincipalDirection1, i, nan3);
    Store(Out.PrincipalDirection2, i, nan3);
    Store(Out.Normals, i, normal);
  }

  void Run(std::int64_t begin, std::int64_t end)
  {
    std::vector<EdgeSample> samples;
    std::vector<Index> across; // (regular vertices: FanPartners)
    RingBatch ring;
    Index nUndefined = 0, nDegenerate = 0, nNonFinite = 0;
    for (Index i = static_cast<Index>(begin); i < end; ++i)
    {
      PrefetchRing(Topo, Points, 3, i);
      std::uint8_t status = Topo.VertexFlags(i);
      const Vec3 xi = LoadPoint<3>(Points, 3, i);
      RingSums<3> sums;
      Vec3 faceSum = Vec3::Zero(); // sum of 2*area*face normal: orientation reference
      Vec3 weighted = Vec3::Zero();
      bool finite = xi.allFinite();
      const Index valence = Topo.Valence(i);
      if (valence > 0)
      {
        ring.Gather(Points, Topo.RingPairsBegin(i), valence, xi);
        ComputeRingCorners(ring.Data.data(), ring.Stride);
      }
      using F = RingBatch::Field;
      for (Index c = 0; c < valence; ++c)
      {
        // RingSums::Add, from the batch.
        sums.CotangentSum -= ring.Get(F::Px, c);
        sums.MixedArea += ring(F::MixedArea, c);
        const double twiceArea = ring(F::TwiceArea, c);
        sums.AddCornerAngle(ring(F::AA, c), ring(F::BB, c), ring(F::AB, c), twiceArea);
        const bool degenerate = ring(F::Degenerate, c) != 0.0;
        sums.Degenerate += degenerate;
        finite = finite && ring(F::Finite, c) != 0.0;
        const Vec3 cross = ring.Get(F::Cx, c);
        faceSum += cross;
        if (!degenerate)
        {
          switch (Options.Weighting)
          {
            case NormalWeighting::Uniform:
              weighted += cross / twiceArea;
              break;
            case NormalWeighting::Angle:
              weighted += std::atan2(twiceArea, ring(F::AB, c)) * cross / twiceArea;
              break;
            case NormalWeighting::Max1999:
              weighted += cross / (ring(F::AA, c) * ring(F::BB, c));
              break;
            case NormalWeighting::Area:                // faceSum is the area-weighted sum
            case NormalWeighting::MeanCurvatureNormal: // its fallback is faceSum too
              break;
          }
        }
      }
      across.clear();
      if ((WantDirections || Out.SharpestEdgeCosine) && status == VertexRegular &&
        !FanPartners(Topo.RingPairsBegin(i), valence, across))
      {
        across.clear();
      }
      if (Out.SharpestEdgeCosine)
      {
        Out.SharpestEdgeCosine[i] =
          across.empty() ? std::numeric_limits<float>::quiet_NaN() : SharpestCosine(ring, across);
      }

      if (status & VertexIsolated)
      {
        ++nUndefined;
        Status[i] = status;
        WriteUndefined(i, Vec3::Constant(NaN), 0.0);
        continue;
      }
      if (!finite)
      {
        ++nNonFinite;
        Status[i] = status | VertexInvalidGeometry;
        WriteUndefined(i, Vec3::Constant(NaN), NaN);
        continue;
      }
      if (sums.Degenerate)
      {
        ++nDegenerate;
        status |= VertexInvalidGeometry;
      }
      const double area = sums.MixedArea;
      const double faceNorm = faceSum.norm();
      const double ksumNorm = sums.CotangentSum.norm();
      // Orientation of the surface at x_i; positive kappa_H where K agrees with it.
      const double orientation = sums.CotangentSum.dot(faceSum) < 0.0 ? -1.0 : 1.0;

      Vec3 n;
      const bool undefined = (status & UndefinedMask) != 0;
      // K gives the normal where it is a normal: not vanishing (section 2.4.5)
      // and within 60 degrees of the face normals.  On irregular, noisy scans
      // K can be mostly tangential at a few vertices; those take the fallback.
      const bool normalK = ksumNorm > 1e-9 * std::sqrt(area) &&
        std::abs(sums.CotangentSum.dot(faceSum)) >= MinimumNormalCosine * ksumNorm * faceNorm;
      if (Options.Weighting == NormalWeighting::MeanCurvatureNormal && !undefined &&
        area > 0.0 && normalK)
      {
        n = orientation * sums.CotangentSum / ksumNorm;
      }
      else
      {
        // Section 2.4.5's fallback where K vanishes, and the other weightings.
        if (Options.Weighting == NormalWeighting::Area ||
          Options.Weighting == NormalWeighting::MeanCurvatureNormal)
        {
          weighted = faceSum;
        }
        const double norm = weighted.norm();
        n = norm > 0.0 ? Vec3(weighted / norm)
                       : (faceNorm > 0.0 ? Vec3(faceSum / faceNorm) : Vec3::Constant(NaN));
      }

      if (undefined || !(area > 0.0))
      {
        ++nUndefined;
        Status[i] = status;
        WriteUndefined(i, n, area);
        continue;
      }

      double kH, kG, k1, k2;
      Eigen::Vector2d psi(1.0, 0.0); // e1 in the tangent frame
      Vec3 u, v;
      if (WantDirections || Options.Method == CurvatureMethod::Taubin1995)
      {
        TangentFrame(n, u, v);
      }
      Vec3 K;
      if (Options.Method == CurvatureMethod::Meyer2003)
      {
        K = sums.MeanCurvatureNormal();                 // eq. 2.8
        kH = 0.5 * orientation * ksumNorm / (2.0 * area); // kappa_H = |K| / 2, signed
        kG = sums.AngleDefect() / area;                 // eq. 2.9
        const double delta = std::max(0.0, kH * kH - kG); // clamped, section 2.6.1
        k1 = kH + std::sqrt(delta);                     // eq. 2.10
        k2 = kH - std::sqrt(delta);                     // eq. 2.11
        if (WantDirections)
        {
          EdgeSamples(ring, valence, across, true, samples);
          psi = FitMeyerDirection(samples, kH, n, u, v);
        }
      }
      else
      {
        EdgeSamples(ring, valence, across, false, samples);
        FitTaubin(samples, n, u, v, k1, k2, psi);
        kH = 0.5 * (k1 + k2);
        kG = k1 * k2;
        K = 2.0 * kH * n;
      }
      Store(Out.MeanCurvatureNormal, i, K);
      Store(Out.MixedArea, i, area);
      Store(Out.MeanCurvature, i, kH);
      Store(Out.GaussianCurvature, i, kG);
      Store(Out.MaximumCurvature, i, k1);
      Store(Out.MinimumCurvature, i, k2);
      Store(Out.Normals, i, n);
      if (WantDirections)
      {
        const Vec3 e1 = psi[0] * u + psi[1] * v;
        Store(Out.PrincipalDirection1, i, e1);
        Store(Out.PrincipalDirection2, i, Vec3(n.cross(e1)));
      }
      Status[i] = status;
    }
    Undefined += nUndefined;
    Degenerate += nDegenerate;
    NonFinite += nNonFinite;
  }
};

/// BoundaryPolicy::InteriorAverage: undefined vertices take the mean of the
/// values of their defined 1-ring neighbours, ring by ring inwards-out, so
/// that vertices with no regular neighbour (grid corners) are reached in a
/// later sweep.  Each sweep reads only values defined before it, so the
/// result does not depend on the thread count.  Principal directions stay NaN.
void AverageFromInterior(const MeshTopology& topo, const std::vector<std::uint8_t>& status,
  const CurvatureOutputs& out, int numThreads)
{
  struct Field
  {
    double* Data;
    int Components;
  };
  const Field fields[] = { { out.MeanCurvatureNormal, 3 }, { out.MeanCurvature, 1 },
    { out.GaussianCurvature, 1 }, { out.MaximumCurvature, 1 }, { out.MinimumCurvature, 1 } };
  const Index n = topo.NumberOfVertices();
  // Sources: vertices whose values were computed (an inconsistently oriented
  // but closed 1-ring counts).  Targets: boundary / non-manifold vertices.
  const auto needsValue = [&](Index i) {
    return (status[i] & UndefinedMask) && !(status[i] & (VertexIsolated | VertexInvalidGeometry));
  };
  std::vector<std::uint8_t> defined(n), next(n);
  Index pending = 0;
  for (Index i = 0; i < n; ++i)
  {
    defined[i] = !(status[i] & (UndefinedMask | VertexInvalidGeometry));
    pending += needsValue(i);
  }
  while (pending > 0)
  {
    next = defined;
    std::atomic<Index> filled{ 0 };
    ParallelFor(n, numThreads, [&](std::int64_t begin, std::int64_t end) {
      std::vector<Index> ring;
      Index count = 0;
      for (Index i = static_cast<Index>(begin); i < end; ++i)
      {
        if (defined[i] || !needsValue(i))
        {
          continue;
        }
        ring.clear();
        for (const Index* c = topo.CornersBegin(i); c != topo.CornersEnd(i); ++c)
        {
          for (Index j : { topo.CornerVertex(MeshTopology::Next(*c)),
                 topo.CornerVertex(MeshTopology::Prev(*c)) })
          {
            if (defined[j])
            {
              ring.push_back(j);
            }
          }
        }
        std::sort(ring.begin(), ring.end());
        ring.erase(std::unique(ring.begin(), ring.end()), ring.end());
        if (ring.empty())
        {
          continue;
        }
        for (const Field& f : fields)
        {
          for (int k = 0; f.Data && k < f.Components; ++k)
          {
            double sum = 0.0;
            for (Index j : ring)
            {
              sum += f.Data[static_cast<std::int64_t>(f.Components) * j + k];
            }
            f.Data[static_cast<std::int64_t>(f.Components) * i + k] = sum / ring.size();
          }
        }
        next[i] = 1;
        ++count;
      }
      filled += count;
    });
    if (filled == 0)
    {
      break; // components without any regular vertex stay NaN
    }
    pending -= filled;
    defined.swap(next);
  }
}

template <typename T>
CurvatureReport CurvaturesAtScale(const MeshTopology& topo, const T* points, const CurvatureOptions& options,
  const CurvatureOutputs& outputs, const ProgressCallback& progress);

} // namespace

template <typename T>
CurvatureReport ComputeCurvatures(const MeshTopology& topo, const T* points,
  const CurvatureOptions& options, const CurvatureOutputs& outputs,
  const ProgressCallback& progress)
{
  const int e = FarScaleExponent(UsedPointsBox(topo, points));
  if (e == 0)
  {
    return CurvaturesAtScale(topo, points, options, outputs, progress);
  }
  // Points scaled by 2^-e (exact), the outputs scaled back: curvatures by
  // 2^-e (1 / length), Gaussian curvature by 2^-2e, areas by 2^2e.
  const std::vector<double> scaled = PointsTimesPowerOfTwo(points, topo.NumberOfVertices(), -e);
  const CurvatureReport report = CurvaturesAtScale(topo, scaled.data(), options, outputs, progress);
  const std::size_t n = static_cast<std::size_t>(topo.NumberOfVertices());
  TimesPowerOfTwo(outputs.MeanCurvatureNormal, 3 * n, -e);
  TimesPowerOfTwo(outputs.MeanCurvature, n, -e);
  TimesPowerOfTwo(outputs.MaximumCurvature, n, -e);
  TimesPowerOfTwo(outputs.MinimumCurvature, n, -e);
  TimesPowerOfTwo(outputs.GaussianCurvature, n, -2 * e);
  TimesPowerOfTwo(outputs.MixedArea, n, 2 * e);
  return report;
}

namespace
{

template <typename T>
CurvatureReport CurvaturesAtScale(const MeshTopology& topo, const T* points,
  const CurvatureOptions& options, const CurvatureOutputs& outputs,
  const ProgressCallback& progress)
{
  std::vector<std::uint8_t> status(topo.NumberOfVertices(), VertexRegular);
  const bool wantDirections = outputs.PrincipalDirection1 || outputs.PrincipalDirection2 ||
    options.Method == CurvatureMethod::Taubin1995;
  CurvatureKernel<T> kernel{ topo, points, options, outputs, status, wantDirections };
  CurvatureReport report;
  report.Completed = ParallelFor(
    topo.NumberOfVertices(), options.NumberOfThreads,
    [&](std::int64_t b, std::int64_t e) { kernel.Run(b, e); }, progress);
  if (report.Completed && options.Boundary == BoundaryPolicy::InteriorAverage)
  {
    AverageFromInterior(topo, status, outputs, options.NumberOfThreads);
  }
  if (outputs.Status)
  {
    std::copy(status.begin(), status.end(), outputs.Status);
  }
  report.UndefinedVertices = kernel.Undefined;
  report.DegenerateTriangleVertices = kernel.Degenerate;
  report.NonFiniteVertices = kernel.NonFinite;
  return report;
}

} // namespace

template CurvatureReport ComputeCurvatures<float>(const MeshTopology&, const float*,
  const CurvatureOptions&, const CurvatureOutputs&, const ProgressCallback&);
template CurvatureReport ComputeCurvatures<double>(const MeshTopology&, const double*,
  const CurvatureOptions&, const CurvatureOutputs&, const ProgressCallback&);

} // namespace beltrami
