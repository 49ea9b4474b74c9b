// Beltrami core: the geometry of a vertex's 1-ring, for 2-manifolds embedded
// in R^N (thesis sections 2.4 and 2.8.1).
//
// Everything is written with dot products only, so it holds in any embedding
// dimension:  2A = sqrt(|u|^2 |v|^2 - (u.v)^2)            (eq. 2.13)
//             cot(u, v) = u.v / sqrt(|u|^2 |v|^2 - (u.v)^2)  (section 2.8.1)
// ForEachRingCorner() visits the triangles around x_i and hands each one's
// CornerGeometry to a callback; RingSums accumulates the three quantities
// every operator needs: the cotangent sum of eq. 2.8, the mixed area of
// figure 2.3 and the angle sum of eq. 2.9.
#pragma once

#include "Mesh/Geometry.h"
#include "Mesh/MeshTopology.h"
#include "Support/Vectorization.h"

#include <algorithm>
#include <cmath>

namespace beltrami
{

/// Relative area below which a triangle counts as degenerate (zero area):
/// 2A <= DegenerateTolerance * (longest edge)^2.
constexpr double DegenerateTolerance = 1e-12;

template <int N>
struct CornerGeometry
{
  Index Corner;       ///< corner of x_i in triangle (x_i, x_j, x_k)
  Index J, K;         ///< the next and previous vertices of that triangle
  VecN<N> A, B;       ///< x_j - x_i and x_k - x_i
  double AA, BB, AB;  ///< |A|^2, |B|^2, A.B
  double TwiceArea;   ///< 2 * area, eq. 2.13
  double CotJ, CotK;  ///< cotangents of the angles at x_j and x_k (0 if degenerate)
  /// The angle at x_i, from atan2 (thesis table 2.1); computed on demand
  /// (RingSums adds the angles of a ring with one atan2 in all).
  double Angle() const { return std::atan2(TwiceArea, AB); }
  double MixedArea;   ///< the triangle's part of A_Mixed(x_i), figure 2.3
  bool Degenerate;    ///< zero area (cotangents and areas left out)
};

/// The part of A_Mixed(x_i) in a non-degenerate triangle (x_i, x_j, x_k)
/// (figure 2.3), from |x_j - x_i|^2, |x_k - x_i|^2, their dot product and
/// the cotangents at x_j and x_k.  T: double, or a GCC vector of doubles
/// (one triangle a lane: CurvatureDerivatives' face fit).
template <typename T>
inline T CornerMixedArea(const T& aa, const T& bb, const T& ab, const T& twiceArea, const T& cotJ, const T& cotK)
{
  // Non-obtuse: Voronoi region, (|PR|^2 cot Q + |PQ|^2 cot R) / 8 (section 2.4.3).
  // Obtuse triangle: area/2 if the obtuse angle is at x_i, else area/4.
  const auto nonObtuse = (ab >= 0.0) & (aa - ab >= 0.0) & (bb - ab >= 0.0);
  const T obtuse = ab < 0.0 ? twiceArea / 4.0 : twiceArea / 8.0;
  return nonObtuse ? (bb * cotJ + aa * cotK) / 8.0 : obtuse;
}

/// 1 / |c| for a triangle's cross product c (twice its area times its unit
/// normal), summed in this order (the 1-ring batch of the curvature kernel
/// computes the same per lane: the same values).
inline double InverseCrossNorm(double x, double y, double z)
{
  return 1.0 / std::sqrt(x * x + y * y + z * z);
}
inline double InverseCrossNorm(const Vec3& c)
{
  return InverseCrossNorm(c[0], c[1], c[2]);
}

/// The cosine of the angle between the normals of two triangles given as
/// cross products of their edges and their InverseCrossNorm; NaN where one
/// is zero or not finite.
inline double NormalCosine(const Vec3& a, double inverseA, const Vec3& b, double inverseB)
{
  return (a[0] * b[0] + a[1] * b[1] + a[2] * b[2]) * inverseA * inverseB;
}
inline double NormalCosine(const Vec3& a, const Vec3& b)
{
  return NormalCosine(a, InverseCrossNorm(a), b, InverseCrossNorm(b));
}

/// Computes the geometry of corner c of vertex i in triangle (x_i, x_j, x_k).
template <int N, typename T>
inline CornerGeometry<N> MakeCornerGeometry(
  const T* points, int stride, const VecN<N>& xi, Index c, Index j, Index k)
{
  CornerGeometry<N> g;
  g.Corner = c;
  g.J = j;
  g.K = k;
  g.A = LoadPoint<N>(points, stride, g.J) - xi;
  g.B = LoadPoint<N>(points, stride, g.K) - xi;
  g.AA = g.A.squaredNorm();
  g.BB = g.B.squaredNorm();
  g.AB = g.A.dot(g.B);
  g.TwiceArea = std::sqrt(std::max(0.0, g.AA * g.BB - g.AB * g.AB));
  const double ee = g.AA + g.BB - 2.0 * g.AB; // |x_k - x_j|^2
  const double longest = std::max(ee, std::max(g.AA, g.BB));
  // Written so that NaN also counts as degenerate.
  g.Degenerate = !(g.TwiceArea > DegenerateTolerance * longest);
  if (g.Degenerate)
  {
    g.CotJ = g.CotK = g.MixedArea = 0.0;
    return g;
  }
  // Angle at x_j is between (x_i - x_j) and (x_k - x_j): dot = AA - AB; at x_k: BB - AB.
  const double dotJ = g.AA - g.AB;
  const double dotK = g.BB - g.AB;
  const double inverseTwiceArea = 1.0 / g.TwiceArea;
  g.CotJ = dotJ * inverseTwiceArea;
  g.CotK = dotK * inverseTwiceArea;
  g.MixedArea = CornerMixedArea(g.AA, g.BB, g.AB, g.TwiceArea, g.CotJ, g.CotK);
  return g;
}

/// Software prefetch for loops over vertices that read their 1-rings: on
/// large meshes those loops wait on the random reads of the neighbours'
/// points.  Called at vertex i, it asks for the neighbour points of i + 8.
template <typename T>
inline void PrefetchRing(const MeshTopology& topo, const T* points, int stride, Index i)
{
  constexpr Index Distance = 8;
  if (i + Distance < topo.NumberOfVertices())
  {
    const Index v = i + Distance;
    for (const Index* p = topo.RingPairsBegin(v); p != topo.RingPairsBegin(v + 1); ++p)
    {
      PrefetchKept(points + static_cast<std::int64_t>(stride) * *p);
    }
  }
}

template <int N, typename T, typename Visitor>
inline void ForEachRingCorner(
  const MeshTopology& topo, const T* points, int stride, Index i, const VecN<N>& xi, Visitor&& visit)
{
  const Index* pair = topo.RingPairsBegin(i);
  for (const Index* c = topo.CornersBegin(i); c != topo.CornersEnd(i); ++c, pair += 2)
  {
    visit(MakeCornerGeometry<N>(points, stride, xi, *c, pair[0], pair[1]));
  }
}

/// The sums over a 1-ring that the operators of chapter 2 are made of.
template <int N>
struct RingSums
{
  VecN<N> CotangentSum = VecN<N>::Zero(); ///< sum_j (cot a_ij + cot b_ij)(x_i - x_j)
  double MixedArea = 0.0;                 ///< A_Mixed
  /// The sum of the triangle angles at x_i, as the product of the unit
  /// complex numbers e^(i theta) (re, im) and the number of turns: one atan2
  /// per ring instead of one per triangle (the angle of a product is the sum
  /// of the angles; each angle is in [0, pi], so a turn is completed exactly
  /// when the product goes from the lower to the upper half plane).
  double AngleRe = 1.0, AngleIm = 0.0;
  int AngleTurns = 0;
  int Degenerate = 0;                     ///< zero-area triangles left out

  void Add(const CornerGeometry<N>& g)
  {
    // This triangle holds edge (i,j) opposite x_k and edge (i,k) opposite x_j.
    CotangentSum -= g.CotK * g.A + g.CotJ * g.B;
    MixedArea += g.MixedArea;
    AddCornerAngle(g.AA, g.BB, g.AB, g.TwiceArea);
    Degenerate += g.Degenerate;
  }
  /// Adds the angle at x_i of a triangle of |A|^2 = aa, |B|^2 = bb, A.B =
  /// ab and twice the area `twiceArea`.  Where x_i coincides with x_j or
  /// x_k (a zero-length edge, as a collapsed edge leaves), its angle is
  /// undefined: it takes pi/2, so that the two coincident corners share the
  /// triangle's pi (pi/3 where all three coincide), and the angle sums obey
  /// Gauss-Bonnet as on any other closed surface (adding 0 there, a bunny with
  /// 1,456 such triangles summed sum K A to 4586 instead of 4 pi).
  void AddCornerAngle(double aa, double bb, double ab, double twiceArea)
  {
    if (aa > 0.0 && bb > 0.0)
    {
      AddAngle(ab, twiceArea);
    }
    else if (aa > 0.0 || bb > 0.0)
    {
      AddAngle(0.0, 1.0);
    }
    else if (aa == 0.0 && bb == 0.0)
    {
      AddAngle(0.5, 0.5 * std::sqrt(3.0));
    }
  }
  /// K(x_i), eq. 2.8; the mean curvature normal in R^3.
  VecN<N> MeanCurvatureNormal() const { return CotangentSum / (2.0 * MixedArea); }
  /// 2*pi - sum(theta_j), the numerator of eq. 2.9.
  double AngleDefect() const { return 2.0 * M_PI - AngleSum(); }
  /// Sum of the triangle angles at x_i (the same as adding atan2 of each).
  double AngleSum() const
  {
    const double a = std::atan2(AngleIm, AngleRe); // (-pi, pi]
    return 2.0 * M_PI * AngleTurns + (a < 0.0 ? a + 2.0 * M_PI : a);
  }
  /// Adds the angle of the complex number (re, im), im >= 0 (|re|, |im| of
  /// the order of a squared edge length: the product stays far from under-
  /// and overflow, as the dot products of the corner geometry do).
  void AddAngle(double re, double im)
  {
    const bool lowerBefore = AngleIm < 0.0 || (AngleIm == 0.0 && AngleRe < 0.0);
    const double pr = AngleRe * re - AngleIm * im;
    const double pi = AngleRe * im + AngleIm * re;
    const double norm = std::max(std::abs(pr), std::abs(pi));
    if (!(norm > 0.0))
    {
      return; // a zero-length edge: atan2(0, 0) = 0
    }
    const double scale = 1.0 / norm; // keep the product of order 1 (its angle is unchanged)
    AngleRe = pr * scale;
    AngleIm = pi * scale;
    const bool lowerAfter = AngleIm < 0.0 || (AngleIm == 0.0 && AngleRe < 0.0);
    AngleTurns += lowerBefore && !lowerAfter;
  }
};

} // namespace beltrami
