#include "Maps/MapOptimization.h"

#include <algorithm>
#include <cmath>

namespace beltrami::detail
{

namespace
{

std::vector<double> Multiply(const std::vector<double>& a, const std::vector<double>& b)
{
  std::vector<double> c(a.size() + b.size() - 1, 0.0);
  for (std::size_t i = 0; i < a.size(); ++i)
  {
    for (std::size_t j = 0; j < b.size(); ++j)
    {
      c[i + j] += a[i] * b[j];
    }
  }
  return c;
}

} // namespace

/// Finds the minimum over [a, b] of the polynomial with coefficients `p`
/// (p[k] multiplies x^k): the derivative's roots by sign changes on a fine
/// grid refined by bisection, and the ends.
double MinimizePolynomial(const std::vector<double>& p, double a, double b)
{
  const auto value = [&](double x) {
    double v = 0.0;
    for (std::size_t k = p.size(); k-- > 0;)
    {
      v = v * x + p[k];
    }
    return v;
  };
  const auto slope = [&](double x) {
    double v = 0.0;
    for (std::size_t k = p.size(); k-- > 1;)
    {
      v = v * x + static_cast<double>(k) * p[k];
    }
    return v;
  };
  double best = a, bestValue = value(a);
  if (value(b) < bestValue)
  {
    best = b;
    bestValue = value(b);
  }
  const int samples = 4096;
  double x0 = a, s0 = slope(a);
  for (int k = 1; k <= samples; ++k)
  {
    const double x1 = a + (b - a) * k / samples;
    const double s1 = slope(x1);
    if (s0 < 0.0 && s1 >= 0.0) // a minimum in [x0, x1]
    {
      double lo = x0, hi = x1;
      for (int it = 0; it < 100 && hi - lo > 1e-15 * std::max(1.0, std::abs(hi)); ++it)
      {
        const double mid = 0.5 * (lo + hi);
        (slope(mid) < 0.0 ? lo : hi) = mid;
      }
      const double x = 0.5 * (lo + hi);
      if (value(x) < bestValue)
      {
        best = x;
        bestValue = value(x);
      }
    }
    x0 = x1;
    s0 = s1;
  }
  return best;
}

/// Coefficients in l of the energy of U = U_chi + l (U_A - U_chi), u -> s u.
std::vector<double> MixEnergyPolynomial(const MeshTopology& topo, const double* points,
  const double* uvA, const double* uvX, double s, DistortionEnergy energy)
{
  std::vector<double> total(energy == DistortionEnergy::EdgeLength ? 5 : 9, 0.0);
  const double s2 = s * s;
  if (energy == DistortionEnergy::EdgeLength)
  {
    ForEachEdge(topo, points, [&](Index i, Index j, double xx) {
      const Vec2 dX = UV(uvX, i) - UV(uvX, j);
      const Vec2 delta = UV(uvA, i) - UV(uvA, j) - dX;
      const std::vector<double> q = { s2 * dX.squaredNorm() / xx - 1.0, 2.0 * s2 * dX.dot(delta) / xx,
        s2 * delta.squaredNorm() / xx };
      const std::vector<double> q2 = Multiply(q, q);
      for (std::size_t k = 0; k < q2.size(); ++k)
      {
        total[k] += q2[k];
      }
    });
    return total;
  }
  ForEachTriangle(topo, points, [&](Index t, double a3) {
    // The signed area is quadratic in l: evaluate at 0, 1/2, 1 and interpolate.
    double area[3];
    double mixed[6];
    for (int k = 0; k < 3; ++k)
    {
      const double l = 0.5 * k;
      for (int c = 0; c < 3; ++c)
      {
        const Index v = topo.CornerVertex(3 * t + c);
        for (int d = 0; d < 2; ++d)
        {
          mixed[2 * c + d] = uvX[2 * v + d] + l * (uvA[2 * v + d] - uvX[2 * v + d]);
        }
      }
      const Vec2 b = Vec2(mixed[2], mixed[3]) - Vec2(mixed[0], mixed[1]);
      const Vec2 c = Vec2(mixed[4], mixed[5]) - Vec2(mixed[0], mixed[1]);
      area[k] = 0.5 * (b.x() * c.y() - b.y() * c.x());
    }
    const double f0 = area[0], fh = area[1], f1 = area[2];
    const double c2 = 2.0 * (f1 - 2.0 * fh + f0), c1 = f1 - f0 - c2;
    const std::vector<double> r = { s2 * f0 / a3, s2 * c1 / a3, s2 * c2 / a3 };
    std::vector<double> r2 = Multiply(r, r);
    r2[0] -= 1.0;
    const std::vector<double> e = Multiply(r2, r2);
    for (std::size_t k = 0; k < e.size(); ++k)
    {
      total[k] += e[k];
    }
  });
  return total;
}


/// Gradient descent on the boundary points (section 5.5.2).
void OptimizeBoundary(const MeshTopology& topo, const double* points, const BoundaryBasis& basis,
  const ParameterizationOptions& options, std::vector<double>& uv, ParameterizationResult& result)
{
  const std::size_t nb = basis.BoundaryVertices().size();
  std::vector<double> p(2 * nb), gradient(uv.size()), g(2 * nb), trial(2 * nb), uvTrial(uv.size());
  for (std::size_t k = 0; k < nb; ++k)
  {
    p[2 * k] = uv[2 * basis.BoundaryVertices()[k]];
    p[2 * k + 1] = uv[2 * basis.BoundaryVertices()[k] + 1];
  }
  const int threads = ResolveThreadCount(options.NumberOfThreads);
  const double a3 = TotalArea3D(topo, points, threads), a2 = TotalArea2D(topo, uv.data(), threads);
  const double s = a2 > 0.0 ? std::sqrt(a3 / a2) : 1.0; // kept fixed during the descent
  double energy = DistortionEnergyValue(topo, points, uv.data(), s, options.BoundaryEnergy, gradient.data());
  result.BoundaryEnergies.push_back(energy);
  // The first step moves the boundary by about a hundredth of the domain's size.
  double step = -1.0;
  for (int it = 0; it < options.BoundaryOptimizationSteps; ++it)
  {
    basis.PullBack(gradient.data(), g.data());
    double norm = 0.0;
    for (double v : g)
    {
      norm = std::max(norm, std::abs(v));
    }
    if (!(norm > 0.0))
    {
      break;
    }
    if (step < 0.0)
    {
      step = 0.01 * std::sqrt(std::abs(a2)) / norm;
    }
    double slope = 0.0;
    for (double v : g)
    {
      slope += v * v;
    }
    bool accepted = false;
    for (int tries = 0; tries < 40; ++tries, step *= 0.5)
    {
      for (std::size_t k = 0; k < 2 * nb; ++k)
      {
        trial[k] = p[k] - step * g[k];
      }
      basis.Apply(trial.data(), uvTrial.data());
      const double e = DistortionEnergyValue(topo, points, uvTrial.data(), s, options.BoundaryEnergy);
      if (e <= energy - 1e-4 * step * slope && CountFlipped(topo, points, uvTrial.data()) == 0)
      {
        p.swap(trial);
        uv.swap(uvTrial);
        energy = DistortionEnergyValue(topo, points, uv.data(), s, options.BoundaryEnergy, gradient.data());
        accepted = true;
        step *= 2.0;
        break;
      }
    }
    result.BoundaryEnergies.push_back(energy);
    if (!accepted)
    {
      break; // a local minimum, as far as the line search can tell
    }
  }
}

} // namespace beltrami::detail
