#include "Flows/FairingAnisotropy.h"

#include "Mesh/Curvatures.h"

#include <algorithm>
#include <cmath>

namespace beltrami::detail
{

/// Section 3.7.1: w = 1 in noisy regions, 0 at corners, kappa_min / kappa_H on
/// edges, clamped below.  `along` receives, for edge vertices, the principal
/// direction of the smaller curvature (along the edge); zero elsewhere.
std::vector<double> AnisotropicWeights(const MeshTopology& topo, const double* x,
  const FairingOptions& opt, std::vector<Vec3>* along, Index& featureVertices, const Partition* split)
{
  const Index n = topo.NumberOfVertices();
  std::vector<double> kH(n), k1(n), k2(n), e1, e2;
  CurvatureOptions co;
  co.NumberOfThreads = opt.NumberOfThreads;
  CurvatureOutputs out;
  out.MeanCurvature = kH.data();
  out.MaximumCurvature = k1.data();
  out.MinimumCurvature = k2.data();
  if (along)
  {
    e1.resize(3 * static_cast<std::size_t>(n));
    e2.resize(3 * static_cast<std::size_t>(n));
    out.PrincipalDirection1 = e1.data();
    out.PrincipalDirection2 = e2.data();
    along->assign(n, Vec3::Zero());
  }
  ComputeCurvatures(topo, x, co, out);
  const double T = opt.FeatureThreshold;
  std::vector<double> w(n, 1.0);
  featureVertices = 0;
  for (Index i = 0; i < n; ++i)
  {
    const double a1 = std::abs(k1[i]), a2 = std::abs(k2[i]), aH = std::abs(kH[i]);
    if (!std::isfinite(a1 + a2 + aH) || (a1 <= T && a2 <= T))
    {
      continue; // noise (or undefined): isotropic
    }
    featureVertices += !split || split->IsOwned(i);
    if (a1 > T && a2 > T && k1[i] * k2[i] > 0.0)
    {
      w[i] = 0.0; // corner
      continue;
    }
    const double smallest = std::min({ a1, a2, aH });
    if (aH == 0.0 || smallest == aH)
    {
      w[i] = 1.0;
      continue;
    }
    const bool firstIsSmall = smallest == a1;
    w[i] = std::max(opt.MinimumAnisotropicWeight, (firstIsSmall ? k1[i] : k2[i]) / kH[i]);
    if (along)
    {
      (*along)[i] = LoadPoint<3>(firstIsSmall ? e1.data() : e2.data(), 3, i);
    }
  }
  if (split)
  {
    featureVertices = static_cast<Index>(split->Sum(static_cast<double>(featureVertices)));
  }
  return w;
}

/// Feature curves for the curve-smoothing pass: edges between edge vertices
/// that run along both vertices' edge directions (within 30 degrees); only
/// vertices with exactly two such edges are smoothed.
void FeatureChains(const MeshTopology& topo, const double* x, const std::vector<Vec3>& along,
  std::vector<std::vector<Index>>& chains, std::vector<std::uint8_t>& onCurve)
{
  const MeshTopology::EdgeTable& edges = topo.Edges();
  const Index n = topo.NumberOfVertices();
  const double cos30 = std::cos(M_PI / 6.0);
  const auto aligned = [&](Index i, Index j) {
    const Vec3 d = Point(x, j) - Point(x, i);
    const double len = d.norm();
    return along[i].squaredNorm() > 0.0 && len > 0.0 && std::abs(d.dot(along[i])) > cos30 * len;
  };
  std::vector<Index> count(n, 0);
  for (std::int64_t e = 0; e < edges.NumberOfEdges(); ++e)
  {
    const Index i = edges.Vertices[2 * e], j = edges.Vertices[2 * e + 1];
    if (aligned(i, j) && aligned(j, i))
    {
      ++count[i];
      ++count[j];
    }
  }
  onCurve.assign(n, 0);
  for (std::int64_t e = 0; e < edges.NumberOfEdges(); ++e)
  {
    const Index i = edges.Vertices[2 * e], j = edges.Vertices[2 * e + 1];
    if (aligned(i, j) && aligned(j, i) && (count[i] == 2 || count[j] == 2))
    {
      chains.push_back({ i, j });
      onCurve[i] |= count[i] == 2;
      onCurve[j] |= count[j] == 2;
    }
  }
}

} // namespace beltrami::detail
