// Finite-difference checks of the gradients of appendix A behind the
// assembled Laplacians:
//  - A.2: the gradient of the total area with respect to a vertex is
//    (1/2) sum_j (cot a_ij + cot b_ij) (x_i - x_j) = 2 (S x)_i for the
//    cotangent stiffness S (c_ij = (cot a + cot b) / 4);
//  - A.6: the gradient of the angle sum theta_i around a vertex is
//    sum_j (cot g_ij + cot d_ij) / |x_i - x_j|^2 (x_j - x_i) = -(S x)_i for
//    the authalic weights of eq. 5.6 (g, d the angles at x_j).
// (Only the triangles of x_i depend on it: the area of that ring is the
// surface's area up to a constant.)
// On a sphere mesh with jittered vertices (no symmetry to hide an error) and
// on the bunny scan, by central differences of step 1e-6.
// And the 1D check of section 3.4.2: on irregularly spaced samples the
// scale-dependent weights (c = 1/|e|, a = (|e_prev| + |e_next|) / 2) are the
// second difference of the 1D heat equation - exact for quadratics, first
// order for smooth data - where the plain umbrella is not.
#include "TestMeshes.h"

#include "Mesh/Laplacian.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

using namespace beltrami;
using test::Mesh;

namespace
{

/// The area of the triangles of vertex i (the rest of the surface does not
/// depend on x_i; summing only these keeps the differences accurate).
double RingArea(const Mesh& m, Index i)
{
  double area = 0.0;
  for (std::size_t t = 0; t < m.Triangles.size(); t += 3)
  {
    if (m.Triangles[t] == i || m.Triangles[t + 1] == i || m.Triangles[t + 2] == i)
    {
      const Eigen::Vector3d a = m.Point(m.Triangles[t]), b = m.Point(m.Triangles[t + 1]),
                            c = m.Point(m.Triangles[t + 2]);
      area += 0.5 * (b - a).cross(c - a).norm();
    }
  }
  return area;
}

/// The angle sum at vertex i over its triangles.
double AngleSum(const Mesh& m, Index i)
{
  double sum = 0.0;
  for (std::size_t t = 0; t < m.Triangles.size(); t += 3)
  {
    for (int k = 0; k < 3; ++k)
    {
      if (m.Triangles[t + k] == i)
      {
        const Eigen::Vector3d a = m.Point(m.Triangles[t + (k + 1) % 3]) - m.Point(i);
        const Eigen::Vector3d b = m.Point(m.Triangles[t + (k + 2) % 3]) - m.Point(i);
        sum += std::atan2(a.cross(b).norm(), a.dot(b));
      }
    }
  }
  return sum;
}

/// Central differences of f with respect to vertex i's coordinates.
template <typename F>
Eigen::Vector3d NumericalGradient(Mesh& m, Index i, F&& f)
{
  const double h = 1e-6;
  Eigen::Vector3d g;
  for (int d = 0; d < 3; ++d)
  {
    const double x = m.Points[3 * i + d];
    m.Points[3 * i + d] = x + h;
    const double plus = f();
    m.Points[3 * i + d] = x - h;
    const double minus = f();
    m.Points[3 * i + d] = x;
    g[d] = (plus - minus) / (2 * h);
  }
  return g;
}

/// (S x)_i of an assembled Laplacian, row i.
Eigen::Vector3d StiffnessRow(const GraphLaplacian& l, const Mesh& m, Index i)
{
  Eigen::Vector3d s = Eigen::Vector3d::Zero();
  for (std::int64_t k = l.Offsets[i]; k < l.Offsets[i + 1]; ++k)
  {
    s += l.Weights[k] * (m.Point(i) - m.Point(l.Neighbors[k]));
  }
  return s;
}

void CheckGradients(Mesh m, int samples, const char* what)
{
  const MeshTopology topology = m.Topology();
  GraphLaplacian cotangent, authalic;
  AssembleSurfaceLaplacian(topology, m.Points.data(), LaplacianWeights::Cotangent, cotangent, 1);
  AssembleSurfaceLaplacian(topology, m.Points.data(), LaplacianWeights::Authalic, authalic, 1);
  double worstArea = 0.0, worstAngle = 0.0;
  const Index n = m.NumberOfVertices();
  for (int s = 0; s < samples; ++s)
  {
    const Index i = static_cast<Index>((static_cast<std::int64_t>(s) * 7919) % n);
    if (topology.VertexFlags(i) != 0)
    {
      continue; // boundary or non-manifold
    }
    const Eigen::Vector3d area = NumericalGradient(m, i, [&] { return RingArea(m, i); });
    const Eigen::Vector3d angle = NumericalGradient(m, i, [&] { return AngleSum(m, i); });
    worstArea = std::max(worstArea, (area - 2.0 * StiffnessRow(cotangent, m, i)).norm() / area.norm());
    worstAngle = std::max(worstAngle, (angle + StiffnessRow(authalic, m, i)).norm() / angle.norm());
  }
  std::printf("%s: largest relative error of the area gradient %.2e, of the angle gradient %.2e\n", what,
    worstArea, worstAngle);
  EXPECT_LT(worstArea, 1e-5) << what; // the truncation error of the differences: (h / edge)^2
  EXPECT_LT(worstAngle, 1e-5) << what;
}

} // namespace

TEST(AppendixGradients, AreaAndAngleGradientsMatchTheAssembledWeights)
{
  Mesh sphere = test::OctahedronSphere(3);
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> jitter(-0.03, 0.03);
  for (double& x : sphere.Points)
  {
    x += jitter(rng);
  }
  CheckGradients(sphere, 200, "jittered sphere");
  std::string error;
  const Mesh bunny = test::ReadMesh("bunny00.off", error);
  ASSERT_TRUE(error.empty()) << error;
  CheckGradients(bunny, 40, "bunny00");
}

TEST(ScaleDependentUmbrella, IsThe1DHeatOperatorOnIrregularSamples)
{
  // Samples of [0, 1] with spacings varying by up to a factor 4, on a line.
  for (int n : { 40, 80, 160 })
  {
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> spacing(0.5, 2.0);
    std::vector<double> t(n + 1, 0.0);
    for (int i = 1; i <= n; ++i)
    {
      t[i] = t[i - 1] + spacing(rng);
    }
    std::vector<double> points(3 * (n + 1), 0.0);
    std::vector<Index> chain;
    for (int i = 0; i <= n; ++i)
    {
      t[i] /= t[n];
      points[3 * i] = t[i];
      chain.push_back(i);
    }
    CurveGraph graph;
    graph.Build(n + 1, {}, { chain });
    GraphLaplacian scaled, umbrella;
    AssembleCurveLaplacian(graph, points.data(), LaplacianWeights::InverseEdgeLength, scaled);
    AssembleCurveLaplacian(graph, points.data(), LaplacianWeights::Umbrella, umbrella);
    // L f_i = -(S f)_i / a_i against f'' (the umbrella: L f_i = second difference / 2,
    // so 2 L f_i / h^2 with h the mean spacing).
    const auto laplace = [&](const GraphLaplacian& l, const std::vector<double>& f, int i) {
      double s = 0.0;
      for (std::int64_t k = l.Offsets[i]; k < l.Offsets[i + 1]; ++k)
      {
        s += l.Weights[k] * (f[i] - f[l.Neighbors[k]]);
      }
      return -s / l.Mass[i];
    };
    std::vector<double> square(n + 1), wave(n + 1);
    for (int i = 0; i <= n; ++i)
    {
      square[i] = t[i] * t[i];
      wave[i] = std::sin(M_PI * t[i]);
    }
    double quadratic = 0.0, sine = 0.0, plain = 0.0;
    const double h2 = 1.0 / (static_cast<double>(n) * n);
    for (int i = 1; i < n; ++i)
    {
      quadratic = std::max(quadratic, std::abs(laplace(scaled, square, i) - 2.0));
      sine = std::max(sine, std::abs(laplace(scaled, wave, i) + M_PI * M_PI * wave[i]));
      plain = std::max(plain, std::abs(laplace(umbrella, square, i) * 2.0 / h2 - 2.0)); // (second difference) / h^2
    }
    std::printf("1D, %d irregular samples: scale-dependent operator on x^2: error %.1e; on sin(pi x): %.3f; "
                "umbrella on x^2: %.2f\n", n + 1, quadratic, sine, plain);
    EXPECT_LT(quadratic, 1e-8);
    EXPECT_LT(sine, 0.5 * M_PI * M_PI * 40.0 / n); // first order in the spacing
    EXPECT_GT(plain, 0.5);                         // the umbrella ignores the spacing
  }
}
